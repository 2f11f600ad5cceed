#include "reference/surface_cells.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "core/errors.h"
#include "reference/reference_field.h"

namespace sdfbrick::reference {
namespace {

int log2_exact(int b) {
    int bits = 0;
    while ((1 << bits) < b) ++bits;
    return bits;
}

bool valid_branching(int b) { return b >= 2 && b <= 16 && (b & (b - 1)) == 0; }

bool keep(const Geometry& g, const Domain& d, int level, const glm::ivec3& coord) {
    const double f = evaluate(g, d.cell_centre(level, coord));
    return std::abs(f) <= d.half_diagonal(level);
}

unsigned resolve_threads(unsigned threads) {
    if (threads == 0) threads = std::thread::hardware_concurrency();
    return std::max(1u, threads);
}

// Tests the children of `parents` (cells of level `level`, kept) at level + 1. With `store`, the kept
// children go to the returned list in construction order; the count of kept children is returned
// through `kept` either way.
std::vector<glm::ivec3> expand(const Geometry& g, const Domain& d, int level, const std::vector<glm::ivec3>& parents,
                               bool store, unsigned threads, std::uint64_t& kept) {
    const int b = d.branching;
    const int children = b * b * b;
    std::vector<glm::ivec3> local(static_cast<std::size_t>(children));
    for (int i = 0; i < children; ++i) local[static_cast<std::size_t>(i)] = morton_child(b, i);

    constexpr std::size_t kChunk = 64;  // parents per work item
    const std::size_t chunks = (parents.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<glm::ivec3>> out(store ? chunks : 0);
    std::vector<std::uint64_t> counts(chunks, 0);
    std::atomic<std::size_t> next{0};

    auto work = [&] {
        for (;;) {
            const std::size_t c = next.fetch_add(1);
            if (c >= chunks) return;
            const std::size_t end = std::min(parents.size(), (c + 1) * kChunk);
            std::uint64_t n = 0;
            for (std::size_t i = c * kChunk; i < end; ++i) {
                const glm::ivec3 base = parents[i] * b;
                for (const glm::ivec3& l : local) {
                    const glm::ivec3 child = base + l;
                    if (keep(g, d, level + 1, child)) {
                        ++n;
                        if (store) out[c].push_back(child);
                    }
                }
            }
            counts[c] = n;
        }
    };
    const unsigned t = static_cast<unsigned>(std::min<std::size_t>(resolve_threads(threads), std::max<std::size_t>(chunks, 1)));
    if (t <= 1) {
        work();
    } else {
        std::vector<std::thread> pool;
        pool.reserve(t - 1);
        for (unsigned i = 0; i + 1 < t; ++i) pool.emplace_back(work);
        work();
        for (std::thread& th : pool) th.join();
    }

    kept = 0;
    for (const std::uint64_t n : counts) kept += n;
    std::vector<glm::ivec3> result;
    if (store) {
        result.reserve(static_cast<std::size_t>(kept));
        for (const auto& v : out) result.insert(result.end(), v.begin(), v.end());
    }
    return result;
}

// Shared walk, level by level. keep_all: every level's cells go to levels_out; keep_leaves: the
// last level's cells do. Otherwise the last level is only counted.
void walk(const Geometry& g, const Domain& d, unsigned threads, bool keep_all, bool keep_leaves,
          std::vector<std::uint64_t>& counts, std::vector<std::vector<glm::ivec3>>& levels_out) {
    const std::size_t n_levels = static_cast<std::size_t>(d.levels);
    counts.assign(n_levels, 0);
    levels_out.assign(n_levels, {});
    std::vector<glm::ivec3> current;  // the kept cells of level `at`
    if (keep(g, d, 0, glm::ivec3(0))) current.push_back(glm::ivec3(0));
    counts[0] = current.size();
    int at = 0;
    while (at + 1 < d.levels && !current.empty()) {
        const bool store = at + 2 < d.levels || keep_all || keep_leaves;
        std::uint64_t kept = 0;
        std::vector<glm::ivec3> next = expand(g, d, at, current, store, threads, kept);
        counts[static_cast<std::size_t>(at) + 1] = kept;
        if (keep_all) levels_out[static_cast<std::size_t>(at)] = std::move(current);
        current = std::move(next);
        ++at;
    }
    if (keep_all || keep_leaves) levels_out[static_cast<std::size_t>(at)] = std::move(current);
}

}  // namespace

std::int64_t Domain::cells_per_axis(int level) const {
    std::int64_t n = 1;
    for (int i = 0; i < level; ++i) n *= branching;
    return n;
}

double Domain::side() const { return leaf_size * static_cast<double>(cells_per_axis(levels - 1)); }

double Domain::cell_size(int level) const {
    return leaf_size * static_cast<double>(cells_per_axis(levels - 1 - level));
}

glm::dvec3 Domain::cell_lo(int level, const glm::ivec3& c) const {
    return origin + glm::dvec3(c) * cell_size(level);
}

glm::dvec3 Domain::cell_centre(int level, const glm::ivec3& c) const {
    return origin + (glm::dvec3(c) + 0.5) * cell_size(level);
}

double Domain::half_diagonal(int level) const { return 0.5 * std::sqrt(3.0) * cell_size(level); }

glm::ivec3 morton_child(int branching, int index) {
    const int bits = log2_exact(branching);
    glm::ivec3 c(0);
    for (int j = 0; j < bits; ++j) {
        c.x |= ((index >> (3 * j)) & 1) << j;
        c.y |= ((index >> (3 * j + 1)) & 1) << j;
        c.z |= ((index >> (3 * j + 2)) & 1) << j;
    }
    return c;
}

Domain make_domain(const Aabb& bounds, double leaf_size, int branching) {
    if (bounds.empty()) throw InputError("make_domain: the bounds are empty");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(bounds.lo[a]) || !std::isfinite(bounds.hi[a]))
            throw InputError("make_domain: the bounds are not finite");
    if (!(leaf_size > 0.0) || !std::isfinite(leaf_size))
        throw InputError("make_domain: leaf size must be > 0, got " + std::to_string(leaf_size));
    if (!valid_branching(branching))
        throw InputError("make_domain: branching must be a power of two in 2..16, got " + std::to_string(branching));
    Domain d;
    d.leaf_size = leaf_size;
    d.branching = branching;
    d.origin = glm::floor(bounds.lo / leaf_size) * leaf_size;
    const glm::dvec3 need = bounds.hi - d.origin;
    const double reach = std::max(need.x, std::max(need.y, need.z));
    d.levels = 1;
    while (d.side() < reach) {
        if (d.cells_per_axis(d.levels) > (std::int64_t{1} << 30))
            throw InputError("make_domain: more than 2^30 leaf cells per axis (leaf size " +
                             std::to_string(leaf_size) + " too small for the bounds)");
        ++d.levels;
    }
    return d;
}

std::vector<std::uint64_t> count_surface_cells(const Geometry& g, const Domain& d, unsigned threads) {
    std::vector<std::uint64_t> counts;
    std::vector<std::vector<glm::ivec3>> unused;
    walk(g, d, threads, false, false, counts, unused);
    return counts;
}

std::vector<std::vector<glm::ivec3>> surface_cells_by_level(const Geometry& g, const Domain& d, unsigned threads) {
    std::vector<std::uint64_t> counts;
    std::vector<std::vector<glm::ivec3>> levels;
    walk(g, d, threads, true, true, counts, levels);
    return levels;
}

std::vector<glm::ivec3> surface_cells(const Geometry& g, const Domain& d, unsigned threads) {
    std::vector<std::uint64_t> counts;
    std::vector<std::vector<glm::ivec3>> levels;
    walk(g, d, threads, false, true, counts, levels);
    std::vector<glm::ivec3> leaves;
    if (counts.back() > 0) leaves = std::move(levels.back());
    std::sort(leaves.begin(), leaves.end(), [](const glm::ivec3& a, const glm::ivec3& b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        return a.z < b.z;
    });
    return leaves;
}

}  // namespace sdfbrick::reference
