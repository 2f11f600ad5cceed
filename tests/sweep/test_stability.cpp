// The stability atlas: its pieces (cases, thresholds, the report) and every hard case of
// scenes/stability/ at the tests' size on the test device, each method asserted to stay within the
// thresholds where docs/stability.md's test table says it is stable, and to fail where it says it fails.
#include <algorithm>
#include <map>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "sweep/stability.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

TEST(SweepStability, CasesTakeAnOptionalBrickSize) {
    const sweep::StabilityCase a = sweep::parse_case("scenes/x.json", 0.125);
    EXPECT_EQ(a.file, "scenes/x.json");
    EXPECT_EQ(a.brick_size, 0.125);
    const sweep::StabilityCase b = sweep::parse_case("dir@v/x.json@0.5", 0.125);
    EXPECT_EQ(b.file, "dir@v/x.json");
    EXPECT_EQ(b.brick_size, 0.5);
    for (const char* bad : {"x.json@", "x.json@0", "x.json@-1", "x.json@abc", "x.json@1e999", "x.json@nan"})
        EXPECT_THROW(sweep::parse_case(bad, 0.125), InputError) << bad;
}

TEST(SweepStability, ThresholdsNameEachMeasureExceeded) {
    const sweep::StabilityThresholds t = sweep::kStabilityThresholds;
    reference::AccuracyMetrics a;
    a.mismatch_fraction = t.mismatch_fraction;
    a.depth_error_p99 = t.depth_p99_voxels;
    a.normal_error_p99_deg = t.normal_p99_deg;
    EXPECT_TRUE(sweep::threshold_failures(a, t).empty());  // at the threshold: still stable
    a.depth_error_p99 = 2.0 * t.depth_p99_voxels;
    a.normal_error_p99_deg = 2.0 * t.normal_p99_deg;
    EXPECT_EQ(sweep::threshold_failures(a, t), (std::vector<std::string>{"depth", "normals"}));
    a.mismatch_fraction = 2.0 * t.mismatch_fraction;
    EXPECT_EQ(sweep::threshold_failures(a, t).front(), "mismatch");
}

// What docs/stability.md's test table says of one case: the brick size the tests build it at, and per
// method the measures that fail ("" = stable: every measure within its threshold).
struct CaseExpectation {
    const char* name;
    double brick_size;
    std::map<std::string, std::string> failures;  // method -> failures joined by ","
};

// Test names and failure messages show the case's name, not the struct's bytes.
void PrintTo(const CaseExpectation& e, std::ostream* os) { *os << e.name; }

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
}

class SweepStabilityCase : public ::testing::TestWithParam<CaseExpectation> {};

TEST_P(SweepStabilityCase, MatchesTheTestTable) {
    const CaseExpectation& e = GetParam();
    sweep::StabilitySpec spec;
    spec.cases = {{std::string(SDFBRICK_SOURCE_DIR) + "/scenes/stability/" + e.name + ".json", e.brick_size}};
    spec.normals = {render::NormalMethod::continuous};
    spec.formats = {construct::BrickFormat::int8};
    spec.adaptive = {false};
    spec.width = 97;
    spec.height = 55;
    ocl::DeviceSet devices = test::open_test_devices();
    const sweep::StabilityReport r = sweep::run_stability(spec, devices, {});
    ASSERT_EQ(r.cells.size(), render::kMethods.size());
    for (const sweep::StabilityCell& c : r.cells) {
        const std::string method(render::to_string(c.method));
        ASSERT_FALSE(c.error) << method << ": " << *c.error;
        const auto it = e.failures.find(method);
        ASSERT_NE(it, e.failures.end()) << "no expectation for method " << method;
        EXPECT_EQ(joined(c.failures), it->second)
            << e.name << " " << method << ": mismatch " << c.accuracy.mismatch_fraction << ", depth p99 "
            << c.accuracy.depth_error_p99 << " voxels, normal p99 " << c.accuracy.normal_error_p99_deg << " deg";
    }
}

// The adaptive hard cases (docs/stability.md): at the tests' size, an adaptive build fails no
// threshold that the uniform build at its finest size passes, and the distance between its surface
// and the true one (p99) exceeds the uniform build's by at most the tolerance.
TEST(SweepStability, AdaptiveHardCasesFailOnlyWhereUniformFails) {
    sweep::StabilitySpec spec;
    for (const char* name : {"ground_trees", "engraved_slab", "grooved_board", "steep_blends"})
        spec.cases.push_back({std::string(SDFBRICK_SOURCE_DIR) + "/scenes/stability/" + name + ".json", 0.125});
    spec.methods = {render::Method::hybrid};
    spec.normals = {render::NormalMethod::continuous};
    spec.formats = {construct::BrickFormat::int8};
    spec.width = 97;
    spec.height = 55;
    ocl::DeviceSet devices = test::open_test_devices();
    const sweep::StabilityReport r = sweep::run_stability(spec, devices, {});
    std::map<std::string, std::vector<std::string>> uniform;
    std::map<std::string, double> uniform_surface;
    for (const sweep::StabilityCell& c : r.cells) {
        ASSERT_FALSE(c.error) << c.case_name << ": " << *c.error;
        ASSERT_TRUE(c.accuracy.surface_error_p99_world);
        if (c.tolerance > 0.0) continue;
        uniform[c.case_name] = c.failures;
        uniform_surface[c.case_name] = *c.accuracy.surface_error_p99_world;
    }
    std::size_t adaptive = 0;
    for (const sweep::StabilityCell& c : r.cells) {
        if (c.tolerance == 0.0) continue;
        ++adaptive;
        for (const std::string& f : c.failures)
            EXPECT_NE(std::find(uniform[c.case_name].begin(), uniform[c.case_name].end(), f), uniform[c.case_name].end())
                << c.case_name << ": adaptive fails " << f << ", uniform does not";
        EXPECT_LE(*c.accuracy.surface_error_p99_world, uniform_surface[c.case_name] + c.tolerance) << c.case_name;
    }
    EXPECT_EQ(adaptive, 4u);
}

// docs/stability.md, "What the tests assert": 97 x 55, int8, uniform, continuous normals.
const CaseExpectation kCases[] = {
    {"grazing_plane", 0.125, {{"sphere", "depth,normals,step cap"}, {"analytic", "depth,normals"}, {"hybrid", "depth,normals"}}},
    {"grazing_cylinder", 0.125, {{"sphere", "mismatch,normals,step cap"}, {"analytic", "mismatch,normals"}, {"hybrid", "mismatch,normals"}}},
    {"sub_voxel", 0.125, {{"sphere", "mismatch,depth,normals"}, {"analytic", "mismatch,depth,normals"}, {"hybrid", "mismatch,depth,normals"}}},
    {"blend_tiny", 0.125, {{"sphere", "step cap"}, {"analytic", ""}, {"hybrid", ""}}},
    {"blend_huge", 0.125, {{"sphere", "step cap"}, {"analytic", ""}, {"hybrid", ""}}},
    {"ellipsoid", 0.125, {{"sphere", "mismatch,normals,step cap"}, {"analytic", "mismatch,normals"}, {"hybrid", "mismatch,normals"}}},
    {"menger6", 0.125, {{"sphere", "mismatch,depth,normals,step cap"}, {"analytic", "mismatch,depth,normals"}, {"hybrid", "mismatch,depth,normals"}}},
    {"instance_stack", 0.125, {{"sphere", ""}, {"analytic", ""}, {"hybrid", ""}}},
    {"far", 0.125, {{"sphere", "normals"}, {"analytic", "normals"}, {"hybrid", "normals"}}},
    {"camera_inside", 0.125, {{"sphere", "depth,normals"}, {"analytic", "depth,normals"}, {"hybrid", "depth,normals"}}},
    {"camera_on_face", 0.125, {{"sphere", "depth,step cap"}, {"analytic", ""}, {"hybrid", ""}}},
    {"face_rays", 0.125, {{"sphere", "normals"}, {"analytic", "normals"}, {"hybrid", "normals"}}},
    {"instances_10000", 0.125, {{"sphere", "mismatch,normals,step cap"}, {"analytic", "mismatch,normals"}, {"hybrid", "mismatch,normals"}}},
    {"edits_65536", 0.5, {{"sphere", "mismatch,depth,normals,step cap"}, {"analytic", "mismatch,depth,normals"}, {"hybrid", "mismatch,depth,normals"}}},
};

INSTANTIATE_TEST_SUITE_P(Cases, SweepStabilityCase, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<CaseExpectation>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace sdfbrick
