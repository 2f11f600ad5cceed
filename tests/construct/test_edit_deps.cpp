// Construction stage 1 (host/construct/edit_deps.h, kernels/edit_bounds.cl, kernels/edit_deps.cl):
//  - the device's float boxes contain the host's double-precision boxes (scene.cpp) for every
//    primitive, rotated and scaled, and are not much larger;
//  - the dependency lists equal a brute-force O(n^2) computation made from the device's own boxes
//    (read back), on random edits, degenerate ones and the shipped scenes; lists ascending, unique;
//  - 65,536 edits, checked against brute force on a sample of edits (timings printed);
//  - zero edits.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "construct/edit_deps.h"
#include "core/rng.h"
#include "scene/scene_json.h"
#include "test_support.h"
#include "scene/to_device.h"

namespace sdfbrick {
namespace {

using construct::DependencyBuilder;
using construct::EditDependencies;
using construct::Scan;

DependencyBuilder& builder() {
    static Scan scan(test::device());
    static DependencyBuilder b(test::device(), scan);
    return b;
}

struct Result {
    std::vector<SdfBounds> bounds, influence;
    std::vector<cl_uint> offsets, indices;
    std::size_t total = 0;
};

Result run(const std::vector<SdfEdit>& edits, measure::Scheduler& scheduler) {
    ocl::Buffer<SdfEdit> buffer(test::device(), std::span<const SdfEdit>(edits));
    EditDependencies d = builder().compute(buffer, edits.size(), scheduler);
    Result r;
    r.bounds = d.bounds.read();
    r.influence = d.influence.read();
    r.offsets = d.offsets.read();
    r.indices = d.indices.read();
    r.total = d.total;
    return r;
}

Result run(const std::vector<SdfEdit>& edits) {
    measure::Scheduler scheduler(test::device());
    return run(edits, scheduler);
}

bool valid(const SdfBounds& b) { return b.lo[0] <= b.hi[0] && b.lo[1] <= b.hi[1] && b.lo[2] <= b.hi[2]; }

bool overlap(const SdfBounds& a, const SdfBounds& b) {
    if (!valid(a) || !valid(b)) return false;
    for (int k = 0; k < 3; ++k)
        if (!(a.lo[k] <= b.hi[k] && b.lo[k] <= a.hi[k])) return false;
    return true;
}

std::vector<cl_uint> brute_force(const std::vector<SdfEdit>& edits, const std::vector<SdfBounds>& influence,
                                 std::size_t j) {
    std::vector<cl_uint> deps;
    if (!(edits[j].blend > 0.0f)) return deps;
    for (std::size_t i = 0; i < j; ++i)
        if (overlap(influence[i], influence[j])) deps.push_back(static_cast<cl_uint>(i));
    return deps;
}

std::vector<cl_uint> list_of(const Result& r, std::size_t j) {
    return {r.indices.begin() + r.offsets[j], r.indices.begin() + r.offsets[j + 1]};
}

// CSR shape, ascending unique lists, and every list (or those in `which`) equal to brute force.
void expect_brute_force(const std::vector<SdfEdit>& edits, const Result& r, const std::string& what,
                        const std::vector<std::size_t>* which = nullptr) {
    const std::size_t n = edits.size();
    ASSERT_EQ(r.offsets.size(), n + 1) << what;
    ASSERT_EQ(r.offsets[0], 0u) << what;
    ASSERT_EQ(r.offsets[n], r.total) << what;
    ASSERT_EQ(r.indices.size(), r.total) << what;
    for (std::size_t j = 0; j < n; ++j) {
        ASSERT_LE(r.offsets[j], r.offsets[j + 1]) << what << ": edit " << j;
        for (cl_uint k = r.offsets[j] + 1; k < r.offsets[j + 1]; ++k)
            ASSERT_LT(r.indices[k - 1], r.indices[k]) << what << ": edit " << j << " not ascending and unique";
        if (r.offsets[j + 1] > r.offsets[j]) {
            ASSERT_LT(r.indices[r.offsets[j + 1] - 1], j) << what;
        }
    }
    std::size_t checked = 0, deps = 0;
    auto check = [&](std::size_t j) {
        const std::vector<cl_uint> expected = brute_force(edits, r.influence, j);
        EXPECT_EQ(list_of(r, j), expected) << what << ": edit " << j;
        ++checked;
        deps += expected.size();
    };
    if (which) {
        for (std::size_t j : *which) check(j);
    } else {
        for (std::size_t j = 0; j < n; ++j) check(j);
        EXPECT_EQ(deps, r.total) << what;
    }
    std::printf("[deps] %-24s %6zu edits, %8zu dependencies, %zu lists checked against brute force\n",
                what.c_str(), n, r.total, checked);
}

// ---- random edits ----

Edit random_edit(Rng& rng, Primitive p, double size) {
    Edit e;
    e.primitive = p;
    const auto u = [&](double lo, double hi) { return size * rng.uniform(lo, hi); };
    switch (p) {
        case Primitive::Sphere: e.params = {u(0.2, 1.0), 0, 0, 0}; break;
        case Primitive::Box: e.params = {u(0.05, 1.0), u(0.05, 1.0), u(0.05, 1.0), 0}; break;
        case Primitive::RoundBox: {
            const double bx = u(0.2, 1.0), by = u(0.2, 1.0), bz = u(0.2, 1.0);
            e.params = {bx, by, bz, std::min({bx, by, bz}) * rng.uniform(0.0, 1.0)};
            break;
        }
        case Primitive::Torus: {
            const double big = u(0.3, 1.0);
            e.params = {big, big * rng.uniform(0.05, 0.9), 0, 0};
            break;
        }
        case Primitive::Capsule: e.params = {u(0.1, 1.5), u(0.05, 0.5), 0, 0}; break;
        case Primitive::Cylinder: e.params = {u(0.1, 1.5), u(0.05, 0.8), 0, 0}; break;
        case Primitive::Cone: e.params = {u(0.1, 1.5), u(0.0, 0.8), u(0.0, 0.8), 0}; break;
        case Primitive::Ellipsoid: e.params = {u(0.05, 1.0), u(0.05, 1.0), u(0.05, 1.0), 0}; break;
        case Primitive::Menger: e.params = {u(0.2, 1.0), double(1 + rng.next() % 6), 0, 0}; break;
        case Primitive::Mesh: throw std::invalid_argument("random_edit: a mesh needs a file");
    }
    e.transform.rotation = rng.rotation();
    e.transform.scale = rng.uniform(0.3, 3.0);
    e.op = static_cast<Op>(rng.next() % 3);
    return e;
}

Primitive random_primitive(Rng& rng) { return static_cast<Primitive>(rng.next() % kAnalyticPrimitiveCount); }

// n edits in a box of side `spread`, sizes ~ size, smooth with probability `smooth`.
Geometry random_geometry(std::uint64_t seed, std::size_t n, double spread, double size, double smooth) {
    Rng rng(seed);
    Geometry g{"random", {}};
    for (std::size_t i = 0; i < n; ++i) {
        Edit e = random_edit(rng, random_primitive(rng), size);
        e.transform.translation = rng.in_box(glm::dvec3(-spread / 2), glm::dvec3(spread / 2));
        e.blend = rng.uniform() < smooth ? size * rng.uniform(0.01, 0.5) : 0.0;
        g.edits.push_back(e);
    }
    return g;
}

// ---- (a) bounds ----

double magnitude(const Aabb& b) {
    return std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z), std::abs(b.hi.x), std::abs(b.hi.y),
                     std::abs(b.hi.z), glm::length(b.extent())});
}

void expect_contains(const SdfBounds& device, const Aabb& host, const std::string& what) {
    // The device box contains the host's and is larger by at most a small relative amount.
    const double slack = 1e-4 * magnitude(host);
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(double(device.lo[k]), host.lo[k]) << what << " axis " << k;
        EXPECT_GE(double(device.hi[k]), host.hi[k]) << what << " axis " << k;
        EXPECT_GE(double(device.lo[k]), host.lo[k] - slack) << what << " axis " << k << ": too loose";
        EXPECT_LE(double(device.hi[k]), host.hi[k] + slack) << what << " axis " << k << ": too loose";
    }
}

TEST(ConstructEditBounds, ContainHostBoundsEveryPrimitive) {
    Rng rng(7);
    Geometry g{"bounds", {}};
    for (std::size_t p = 0; p < kAnalyticPrimitiveCount; ++p)
        for (int i = 0; i < 60; ++i) {
            const double size = std::pow(10.0, rng.uniform(-2.0, 2.0));
            Edit e = random_edit(rng, static_cast<Primitive>(p), size);
            if (i == 0) e.transform.rotation = glm::dquat(1.0, 0.0, 0.0, 0.0);
            if (i == 1) e.transform.rotation = glm::angleAxis(M_PI / 2, glm::dvec3(0.0, 0.0, 1.0));
            if (i < 3) e.transform.scale = 1.0;
            e.transform.translation = rng.in_box(glm::dvec3(-3 * size), glm::dvec3(3 * size));
            if (i % 10 == 5) e.transform.translation += glm::dvec3(1000.0, -500.0, 20.0);  // far from the origin
            e.blend = i % 3 == 0 ? 0.0 : size * rng.uniform(0.0, 0.6);
            if (p == std::size_t(Primitive::Box) && i == 4) e.params = {50.0 * size, 0.01 * size, 0.01 * size, 0};
            g.edits.push_back(e);
        }
    const std::vector<SdfEdit> device_edits = to_device(g);
    measure::Scheduler scheduler(test::device());
    const Result r = run(device_edits, scheduler);
    ASSERT_EQ(r.bounds.size(), g.edits.size());
    for (std::size_t i = 0; i < g.edits.size(); ++i) {
        const Edit& e = g.edits[i];
        const std::string what = fmt::format("edit {} ({})", i, to_string(e.primitive));
        expect_contains(r.bounds[i], bounds(e), what + " solid");
        expect_contains(r.influence[i], influence_bounds(e), what + " influence");
    }
    scheduler.resolve();
    ASSERT_FALSE(scheduler.launches().empty());
    EXPECT_EQ(scheduler.launches().front().stage, measure::Stage::edit_bounds);
    EXPECT_EQ(scheduler.launches().front().kernel, "edit_bounds");
    for (const auto& l : scheduler.launches()) {
        EXPECT_TRUE(l.stage == measure::Stage::edit_bounds || l.stage == measure::Stage::dependencies)
            << to_string(l.stage);
        EXPECT_EQ(l.level, -1);
    }
}

// ---- (b) dependencies ----

TEST(ConstructEditDeps, RandomEditsMatchBruteForce) {
    struct Case { std::uint64_t seed; std::size_t n; double spread, size, smooth; };
    for (const Case& c : {Case{1, 300, 10.0, 0.5, 0.5}, Case{2, 400, 4.0, 0.5, 0.7}, Case{3, 250, 30.0, 0.3, 1.0},
                          Case{4, 300, 2.0, 1.0, 0.3}, Case{5, 2, 1.0, 0.5, 1.0}, Case{6, 1, 1.0, 0.5, 1.0}}) {
        const Geometry g = random_geometry(c.seed, c.n, c.spread, c.size, c.smooth);
        const std::vector<SdfEdit> edits = to_device(g);
        const Result r = run(edits);
        expect_brute_force(edits, r, fmt::format("random seed {}", c.seed));
        // Deterministic: a second run gives the same lists.
        const Result again = run(edits);
        EXPECT_EQ(again.offsets, r.offsets);
        EXPECT_EQ(again.indices, r.indices);
    }
}

TEST(ConstructEditDeps, DegenerateEditsMatchBruteForce) {
    Rng rng(99);
    {
        // Every edit the same: each smooth edit depends on all before it.
        Geometry g = random_geometry(11, 300, 0.0, 0.5, 1.0);
        for (Edit& e : g.edits) {
            e.transform = Transform{};
            e.primitive = Primitive::Sphere;
            e.params = {0.5, 0, 0, 0};
            e.blend = 0.1;
        }
        const std::vector<SdfEdit> edits = to_device(g);
        const Result r = run(edits);
        expect_brute_force(edits, r, "identical");
        EXPECT_EQ(r.total, 300u * 299u / 2u);
    }
    {
        // Small edits on a plane (one flat axis), points (radius 0), a few huge edits and one far away.
        Geometry g = random_geometry(12, 400, 8.0, 0.3, 0.6);
        for (std::size_t i = 0; i < g.edits.size(); ++i) {
            Edit& e = g.edits[i];
            if (i % 2 == 0) e.transform.translation.z = 0.0;
            if (i % 4 == 0) {
                e.primitive = Primitive::Box;
                e.params = {0.3, 0.3, 0.0, 0};
                e.transform.rotation = glm::dquat(1.0, 0.0, 0.0, 0.0);
                e.blend = i % 8 == 0 ? 0.0 : 0.05;
            }
            if (i % 37 == 0) {
                e.primitive = Primitive::Sphere;
                e.params = {0.0, 0, 0, 0};
                e.blend = 0.0;
            }
            if (i % 97 == 1) {
                e.primitive = Primitive::Sphere;
                e.params = {1e4, 0, 0, 0};
                e.blend = 1.0;
            }
        }
        g.edits[5].transform.translation = {1e7, -3e6, 2e5};
        const std::vector<SdfEdit> edits = to_device(g);
        const Result r = run(edits);
        expect_brute_force(edits, r, "degenerate");
    }
    {
        // All on a line along x.
        Geometry g = random_geometry(13, 500, 50.0, 0.2, 0.8);
        for (Edit& e : g.edits) e.transform.translation.y = e.transform.translation.z = 0.0;
        const std::vector<SdfEdit> edits = to_device(g);
        expect_brute_force(edits, run(edits), "line");
    }
    {
        // An edit with an unknown primitive has empty boxes and no dependencies either way.
        Geometry g = random_geometry(14, 50, 2.0, 0.5, 1.0);
        std::vector<SdfEdit> edits = to_device(g);
        edits[10].primitive = 1000u;
        edits[20].primitive = 1000u;
        const Result r = run(edits);
        EXPECT_FALSE(valid(r.influence[10]));
        EXPECT_FALSE(valid(r.bounds[20]));
        expect_brute_force(edits, r, "unknown primitive");
        EXPECT_EQ(r.offsets[11], r.offsets[10]);
    }
}

TEST(ConstructEditDeps, NonFiniteEditsCoverEverything) {
    // Sizes that overflow float, NaN parameters and a NaN translation: the boxes are the whole space
    // (conservative), never NaN, and the grid is still built over the finite boxes.
    Geometry g = random_geometry(15, 200, 6.0, 0.4, 0.7);
    std::vector<SdfEdit> edits = to_device(g);
    edits[7].transform.scale = 1e30f;
    edits[7].params[0] = edits[7].params[1] = edits[7].params[2] = 1e20f;
    edits[50].params[0] = std::numeric_limits<float>::quiet_NaN();
    edits[90].transform.translation[1] = std::numeric_limits<float>::quiet_NaN();
    edits[120].blend = std::numeric_limits<float>::infinity();
    const Result r = run(edits);
    for (std::size_t i : {7, 50, 90}) {
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(r.bounds[i].lo[k], -std::numeric_limits<float>::infinity()) << "edit " << i;
            EXPECT_EQ(r.influence[i].hi[k], std::numeric_limits<float>::infinity()) << "edit " << i;
        }
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(std::isfinite(r.bounds[120].lo[k]));
        EXPECT_EQ(r.influence[120].lo[k], -std::numeric_limits<float>::infinity());
    }
    expect_brute_force(edits, r, "non-finite");
    // Every smooth edit after edit 7 depends on it.
    for (std::size_t j = 8; j < edits.size(); ++j)
        if (edits[j].blend > 0.0f) {
            const auto l = list_of(r, j);
            EXPECT_TRUE(std::find(l.begin(), l.end(), 7u) != l.end()) << "edit " << j;
        }
}

TEST(ConstructEditDeps, HugeEditsCoarsenTheGrid) {
    // 3,000 small edits and 150 that cover the whole scene: at about one cell per edit the big ones
    // alone would need 150 x 3,000 cell references, beyond the cap of 32 per edit.
    Geometry g = random_geometry(16, 3000, 20.0, 0.2, 0.5);
    for (std::size_t i = 0; i < g.edits.size(); i += 20) {
        g.edits[i].primitive = Primitive::Sphere;
        g.edits[i].params = {15.0, 0, 0, 0};
        g.edits[i].transform.scale = 1.0;
    }
    const std::vector<SdfEdit> edits = to_device(g);
    ocl::Buffer<SdfEdit> buffer(test::device(), std::span<const SdfEdit>(edits));
    measure::Scheduler scheduler(test::device());
    EditDependencies d = builder().compute(buffer, edits.size(), scheduler);
    scheduler.resolve();
    std::size_t refs_launches = 0;
    for (const auto& l : scheduler.launches()) refs_launches += l.kernel == "grid_refs";
    std::printf("[deps] huge edits: grid %u x %u x %u, %zu cell references, %zu grid_refs launches\n",
                d.grid_dims[0], d.grid_dims[1], d.grid_dims[2], d.grid_refs, refs_launches);
    EXPECT_GT(refs_launches, 1u) << "the first grid should have been too fine";
    EXPECT_LE(d.grid_refs, DependencyBuilder::max_refs(edits.size()));
    EXPECT_GT(std::uint64_t{d.grid_dims[0]} * d.grid_dims[1] * d.grid_dims[2], 1u);
    Result r;
    r.influence = d.influence.read();
    r.offsets = d.offsets.read();
    r.indices = d.indices.read();
    r.total = d.total;
    expect_brute_force(edits, r, "huge edits");
}

TEST(ConstructEditDeps, ShippedScenesMatchBruteForce) {
    for (const char* name : {"drops", "rain", "cubes", "fractal", "spheres"}) {
        const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
        const Scene at_t = scene_at(s, s.time);
        for (const Geometry& geometry : at_t.geometries) {
            const std::vector<SdfEdit> edits = to_device(geometry);
            const Result r = run(edits);
            expect_brute_force(edits, r, name);
            // The device boxes contain the host's here too.
            for (std::size_t i = 0; i < geometry.edits.size(); ++i) {
                expect_contains(r.bounds[i], bounds(geometry.edits[i]), fmt::format("{} edit {}", name, i));
                expect_contains(r.influence[i], influence_bounds(geometry.edits[i]),
                                fmt::format("{} edit {}", name, i));
            }
        }
    }
}

// ---- (c) 65,536 edits ----

TEST(ConstructEditDeps, MaxEditsMatchBruteForceOnSample) {
    const std::size_t n = SDF_MAX_EDITS;
    // Density of the drops scene (about 1,000 edits in a 6.4 x 6 x 6.4 column), scaled to n edits.
    const double spread = 6.3 * std::cbrt(double(n) / 1024.0);
    const Geometry g = random_geometry(2024, n, spread, 0.3, 0.5);
    const std::vector<SdfEdit> edits = to_device(g);
    ocl::Buffer<SdfEdit> buffer(test::device(), std::span<const SdfEdit>(edits));
    measure::Scheduler warm(test::device());
    builder().compute(buffer, n, warm);  // programs built, scan buffers sized
    warm.resolve();
    measure::Scheduler scheduler(test::device());
    const auto start = std::chrono::steady_clock::now();
    EditDependencies d = builder().compute(buffer, n, scheduler);
    scheduler.resolve();
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("[deps] %zu edits: %zu dependencies; grid %u x %u x %u (cell %.3g), %zu cell references; "
                "buffers %zu bytes, scratch %zu bytes\n",
                n, d.total, d.grid_dims[0], d.grid_dims[1], d.grid_dims[2], double(d.grid_cell), d.grid_refs,
                d.bytes(), d.scratch_bytes);
    std::printf("[deps] device ms: edit_bounds %.3f, dependencies %.3f; wall (incl. read-backs) %.3f ms\n",
                scheduler.stage_ms(measure::Stage::edit_bounds), scheduler.stage_ms(measure::Stage::dependencies), wall_ms);
    for (const auto& l : scheduler.launches())
        std::printf("[deps]   %-13s %-12s global %8zu  %.3f ms\n", std::string(to_string(l.stage)).c_str(), l.kernel.c_str(), static_cast<std::size_t>(l.work_items()),
                    l.device_ms);

    Result r;
    r.influence = d.influence.read();
    r.offsets = d.offsets.read();
    r.indices = d.indices.read();
    r.total = d.total;
    EXPECT_GT(r.total, n / 2);  // the scene is dense enough for many dependencies
    EXPECT_LE(d.grid_refs, DependencyBuilder::max_refs(n));
    std::vector<std::size_t> sample;
    Rng rng(5);
    for (int k = 0; k < 1500; ++k) sample.push_back(static_cast<std::size_t>(rng.next() % n));
    for (std::size_t j = n - 20; j < n; ++j) sample.push_back(j);
    expect_brute_force(edits, r, "65536 edits", &sample);
}

// ---- (d) zero edits ----

TEST(ConstructEditDeps, ZeroEdits) {
    ocl::Buffer<SdfEdit> buffer(test::device(), 0);
    measure::Scheduler scheduler(test::device());
    EditDependencies d = builder().compute(buffer, 0, scheduler);
    EXPECT_EQ(d.bounds.size(), 0u);
    EXPECT_EQ(d.influence.size(), 0u);
    EXPECT_EQ(d.offsets.read(), std::vector<cl_uint>{0u});
    EXPECT_EQ(d.indices.size(), 0u);
    EXPECT_EQ(d.total, 0u);
    EXPECT_EQ(d.bytes(), sizeof(cl_uint));
    scheduler.resolve();

    // A count below the buffer's size uses only the first edits.
    const std::vector<SdfEdit> edits = to_device(random_geometry(3, 100, 2.0, 0.5, 1.0));
    ocl::Buffer<SdfEdit> some(test::device(), std::span<const SdfEdit>(edits));
    EditDependencies part = builder().compute(some, 0, scheduler);
    EXPECT_EQ(part.offsets.read(), std::vector<cl_uint>{0u});
    EditDependencies half = builder().compute(some, 50, scheduler);
    Result r;
    r.influence = half.influence.read();
    r.offsets = half.offsets.read();
    r.indices = half.indices.read();
    r.total = half.total;
    expect_brute_force(std::vector<SdfEdit>(edits.begin(), edits.begin() + 50), r, "first 50");
    EXPECT_THROW(builder().compute(some, 101, scheduler), std::out_of_range);
}

}  // namespace
}  // namespace sdfbrick
