// The field kernel (kernels/eval_points.cl on the test device) against the independent
// double-precision host reference (host/reference/), on every primitive, every combine rule, hard
// and smooth, and the shipped scenes, at random points and at points on and near the surface.
//
// Tolerance: |kernel - reference| <= 32 * 2^-24 * M, M = max(1, largest |coordinate| among the points
// and the geometry's bounds). The kernel works in float: the edit parameters are rounded to float
// (relative error 2^-24), and each evaluation is a short chain of correctly rounded operations
// (subtract the translation, rotate, divide by the scale, a primitive, a combine) on values of
// magnitude <= M; a few ulp of M per step, 32 leaves margin for the longest chain (the cone and the
// Menger sponge). docs/accuracy.md records the errors measured.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "reference/field_eval.h"
#include "reference/reference_field.h"
#include "scene/scene_json.h"
#include "test_support.h"
#include "scene/to_device.h"

namespace sdfbrick {
namespace {

reference::FieldEvaluator& evaluator() {
    static reference::FieldEvaluator e(test::device());
    return e;
}

struct Comparison {
    double max_error = 0.0;
    double tolerance = 0.0;
    std::size_t worst = 0;
    std::size_t over = 0;
};

double max_abs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

Comparison compare(const Geometry& g, const std::vector<glm::dvec3>& points) {
    std::vector<float> xyz;
    xyz.reserve(points.size() * 3);
    double m = 1.0;
    const Aabb b = bounds(g);
    if (!b.empty()) m = std::max({m, max_abs(b.lo), max_abs(b.hi)});
    for (const glm::dvec3& p : points) {
        // Both sides see the same (float) point: the comparison is of the field, not of the rounding of p.
        for (int i = 0; i < 3; ++i) xyz.push_back(static_cast<float>(p[i]));
        m = std::max(m, max_abs(p));
    }
    const std::vector<SdfEdit> edits = to_device(g);
    const reference::FieldEvalResult r = evaluator().evaluate(edits, xyz);
    Comparison c;
    c.tolerance = 32.0 * std::ldexp(1.0, -24) * m;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::dvec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        const double err = std::abs(static_cast<double>(r.values[i]) - reference::evaluate(g, p));
        if (err > c.max_error) { c.max_error = err; c.worst = i; }
        c.over += err > c.tolerance;
    }
    return c;
}

void expect_agreement(const Geometry& g, const std::string& what, std::size_t n = 2000) {
    const auto random = reference::random_points(g, n, 11);
    const auto near = reference::near_surface_points(g, n, 12, 0.05 * glm::length(bounds(g).extent()));
    for (const auto& [kind, points] : {std::pair{"random", random}, std::pair{"near-surface", near}}) {
        ASSERT_FALSE(points.empty()) << what << ": no " << kind << " points";
        const Comparison c = compare(g, points);
        EXPECT_EQ(c.over, 0u) << what << " (" << kind << "): " << c.over << " of " << points.size()
                              << " points beyond the tolerance " << c.tolerance << "; worst error " << c.max_error;
        std::printf("[accuracy] %-28s %-12s max |kernel - reference| = %.3g (tolerance %.3g)\n", what.c_str(), kind,
                    c.max_error, c.tolerance);
    }
}

Edit transformed(Edit e) {
    e.transform.translation = {0.3, -0.2, 0.1};
    e.transform.rotation = glm::normalize(glm::dquat(0.9, 0.2, -0.3, 0.25));
    e.transform.scale = 1.3;
    return e;
}

std::vector<Edit> one_of_each_primitive() {
    auto make = [](Primitive p, std::array<double, 4> params) {
        Edit e;
        e.primitive = p;
        e.params = params;
        return e;
    };
    return {make(Primitive::Sphere, {0.8, 0, 0, 0}),        make(Primitive::Box, {0.6, 0.4, 0.3, 0}),
            make(Primitive::RoundBox, {0.6, 0.4, 0.3, 0.1}), make(Primitive::Torus, {0.6, 0.2, 0, 0}),
            make(Primitive::Capsule, {0.5, 0.25, 0, 0}),    make(Primitive::Cylinder, {0.5, 0.3, 0, 0}),
            make(Primitive::Cone, {0.5, 0.4, 0.1, 0}),      make(Primitive::Ellipsoid, {0.8, 0.4, 0.3, 0}),
            make(Primitive::Menger, {0.7, 3, 0, 0})};
}

TEST(ReferenceFieldEval, EveryPrimitive) {
    const auto prims = one_of_each_primitive();
    ASSERT_EQ(prims.size(), kAnalyticPrimitiveCount);
    for (const Edit& e : prims) {
        expect_agreement(Geometry{"g", {e}}, std::string(to_string(e.primitive)));
        expect_agreement(Geometry{"g", {transformed(e)}}, std::string(to_string(e.primitive)) + " transformed");
    }
}

TEST(ReferenceFieldEval, EveryCombineRuleHardAndSmooth) {
    Edit base;
    base.primitive = Primitive::Box;
    base.params = {0.7, 0.5, 0.6, 0};
    for (Op op : {Op::Add, Op::Subtract, Op::Intersect})
        for (double k : {0.0, 0.3}) {
            Edit second;
            second.primitive = Primitive::Sphere;
            second.params = {0.6, 0, 0, 0};
            second.transform.translation = {0.5, 0.3, 0.2};
            second.op = op;
            second.blend = k;
            expect_agreement(Geometry{"g", {base, second}},
                             std::string(to_string(op)) + (k > 0 ? " smooth" : " hard"));
        }
}

TEST(ReferenceFieldEval, ShippedScenes) {
    for (const char* name : {"spheres", "drops", "cubes", "rain", "fractal"}) {
        const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json");
        const Scene at_t = scene_at(s, s.time);
        for (const Geometry& g : at_t.geometries) expect_agreement(g, name, 600);
    }
}

TEST(ReferenceFieldEval, EmptyGeometryIsFar) {
    const std::vector<float> xyz = {0, 0, 0, 1, 2, 3};
    const reference::FieldEvalResult r = evaluator().evaluate({}, xyz);
    ASSERT_EQ(r.values.size(), 2u);
    EXPECT_EQ(r.values[0], SDF_FAR);
    EXPECT_EQ(r.values[1], SDF_FAR);
}

TEST(ReferenceFieldEval, RepeatedRunsAreBitIdentical) {
    const Scene s = load_scene(std::string(SDFBRICK_SOURCE_DIR) + "/scenes/rain.json");
    const Geometry g = geometry_at(s.geometries[0], s.time);
    std::vector<float> xyz;
    for (const glm::dvec3& p : reference::random_points(g, 3000, 5))
        for (int i = 0; i < 3; ++i) xyz.push_back(static_cast<float>(p[i]));
    const std::vector<SdfEdit> edits = to_device(g);
    const auto a = evaluator().evaluate(edits, xyz).values;
    const auto b = evaluator().evaluate(edits, xyz).values;
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
}

}  // namespace
}  // namespace sdfbrick
