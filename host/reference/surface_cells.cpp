#include "reference/surface_cells.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "core/errors.h"
#include "reference/reference_field.h"

namespace sdfbrick::reference {

using construct::Domain;
using construct::morton_child;

namespace {

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
