// Device peaks (host/measure/peaks.h): measured on the test device, and their cache.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/files.h"
#include "measure/peaks.h"
#include "test_support.h"

namespace sdfbrick::measure {
namespace {

using test::ScopedEnv;

void expect_plausible(const DevicePeaks& p) {
    EXPECT_TRUE(std::isfinite(p.bandwidth_gbps));
    EXPECT_GT(p.bandwidth_gbps, 0.0);
    EXPECT_TRUE(std::isfinite(p.fma_gflops));
    EXPECT_GT(p.fma_gflops, 0.0);
    EXPECT_EQ(p.device, test::device().info().name);
    EXPECT_EQ(p.driver, test::device().info().driver_version);
    EXPECT_EQ(p.measured_at.size(), 24u) << p.measured_at;  // 2025-01-31T12:34:56.789Z
}

// A cache file holding made-up figures for the test device.
std::string sentinel_cache() {
    const nlohmann::json entry = {{"device", test::device().info().name},
                                  {"driver", test::device().info().driver_version},
                                  {"bandwidth_gbps", 12345.5},
                                  {"fma_gflops", 67890.25},
                                  {"measured_at", "2000-01-01T00:00:00.000Z"}};
    const nlohmann::json other = {{"device", "another device"},
                                  {"driver", "1.0"},
                                  {"bandwidth_gbps", 1.0},
                                  {"fma_gflops", 2.0},
                                  {"measured_at", "2000-01-01T00:00:00.000Z"}};
    return nlohmann::json{{"format", "sdfbrick peaks 1"}, {"devices", {other, entry}}}.dump();
}

TEST(MeasurePeaks, MeasuresFinitePositiveFigures) {
    const DevicePeaks p = measure_peaks(test::device());
    expect_plausible(p);
    EXPECT_FALSE(p.cached);
    const nlohmann::json j = to_json(p);
    EXPECT_EQ(j["bandwidth_gbps"].get<double>(), p.bandwidth_gbps);
    EXPECT_EQ(j["measured_at"], p.measured_at);
    std::printf("peaks of %s: %.2f GB/s, %.2f GFLOP/s\n", p.device.c_str(), p.bandwidth_gbps, p.fma_gflops);
}

TEST(MeasurePeaks, CacheRoundTrips) {
    const std::filesystem::path dir = test::temp_dir("peaks_round_trip");
    const ScopedEnv cache("SDFBRICK_CACHE_DIR", dir.string());
    const DevicePeaks first = device_peaks(test::device());
    expect_plausible(first);
    EXPECT_FALSE(first.cached);
    ASSERT_TRUE(std::filesystem::exists(dir / kPeaksFile));

    const DevicePeaks second = device_peaks(test::device());
    EXPECT_TRUE(second.cached);
    EXPECT_EQ(second.measured_at, first.measured_at);
    EXPECT_EQ(second.bandwidth_gbps, first.bandwidth_gbps);  // exactly: JSON numbers round-trip
    EXPECT_EQ(second.fma_gflops, first.fma_gflops);
}

TEST(MeasurePeaks, CachedValuesAreReturnedWithoutMeasuring) {
    const std::filesystem::path dir = test::temp_dir("peaks_sentinel");
    const ScopedEnv cache("SDFBRICK_CACHE_DIR", dir.string());
    test::write_text(dir / kPeaksFile, sentinel_cache());
    const DevicePeaks p = device_peaks(test::device());
    EXPECT_TRUE(p.cached);
    EXPECT_EQ(p.bandwidth_gbps, 12345.5);
    EXPECT_EQ(p.fma_gflops, 67890.25);
    EXPECT_EQ(p.measured_at, "2000-01-01T00:00:00.000Z");
    const std::optional<DevicePeaks> looked_up = cached_peaks(test::device().info());  // never measures
    ASSERT_TRUE(looked_up.has_value());
    EXPECT_EQ(looked_up->fma_gflops, 67890.25);

    // refresh measures again, replaces this device's entry and keeps the other device's.
    const DevicePeaks fresh = device_peaks(test::device(), true);
    EXPECT_FALSE(fresh.cached);
    EXPECT_NE(fresh.measured_at, "2000-01-01T00:00:00.000Z");
    const nlohmann::json doc = nlohmann::json::parse(read_file(dir / kPeaksFile));
    ASSERT_EQ(doc["devices"].size(), 2u);
    EXPECT_EQ(doc["devices"][0]["device"], "another device");
    EXPECT_EQ(doc["devices"][1]["measured_at"], fresh.measured_at);
}

TEST(MeasurePeaks, DamagedCacheIsReplaced) {
    const std::filesystem::path dir = test::temp_dir("peaks_damaged");
    const ScopedEnv cache("SDFBRICK_CACHE_DIR", dir.string());
    for (const char* damaged : {"{\"format\": \"sdfbrick peaks 1\", \"devices\": [", "[1, 2, 3]",
                                "{\"format\": \"sdfbrick peaks 1\", \"devices\": [{\"device\": 5}]}"}) {
        test::write_text(dir / kPeaksFile, damaged);
        const DevicePeaks p = device_peaks(test::device());
        expect_plausible(p);
        EXPECT_FALSE(p.cached) << damaged;
        const nlohmann::json doc = nlohmann::json::parse(read_file(dir / kPeaksFile));
        ASSERT_EQ(doc["devices"].size(), 1u) << damaged;
        EXPECT_EQ(doc["devices"][0]["measured_at"], p.measured_at);
        EXPECT_TRUE(device_peaks(test::device()).cached);
    }
}

TEST(MeasurePeaks, CacheOffMeasuresEachTime) {
    const ScopedEnv cache("SDFBRICK_CACHE_DIR", std::string("off"));
    const DevicePeaks p = device_peaks(test::device());
    expect_plausible(p);
    EXPECT_FALSE(p.cached);
    EXPECT_FALSE(cached_peaks(test::device().info()).has_value());
}

TEST(MeasurePeaks, DevicesCommandShowsCachedPeaks) {
    const std::filesystem::path dir = test::temp_dir("peaks_cli");
    test::write_text(dir / kPeaksFile, sentinel_cache());
    const char* spec = std::getenv(test::kTestDeviceEnv);
    const std::string command = fmt::format("SDFBRICK_CACHE_DIR='{}' '{}' --device '{}' devices --peaks", dir.string(),
                                            SDFBRICK_CLI_PATH, spec != nullptr && *spec != '\0' ? spec : "cpu");
    ASSERT_EQ(std::system((command + " --json >'" + (dir / "out.json").string() + "'").c_str()), 0);
    const nlohmann::json devices = nlohmann::json::parse(read_file(dir / "out.json"));
    const auto it = std::find_if(devices.begin(), devices.end(),
                                 [](const nlohmann::json& d) { return d["index"] == test::device().info().index; });
    ASSERT_NE(it, devices.end());
    EXPECT_EQ((*it)["peaks"]["bandwidth_gbps"], 12345.5);
    EXPECT_EQ((*it)["peaks"]["from_cache"], true);

    ASSERT_EQ(std::system((command + " >'" + (dir / "out.txt").string() + "'").c_str()), 0);
    EXPECT_NE(read_file(dir / "out.txt").find("global-memory bandwidth 12345.5 GB/s, FP32 FMA 67890.2 GFLOP/s"),
              std::string::npos)
        << read_file(dir / "out.txt");
}

}  // namespace
}  // namespace sdfbrick::measure
