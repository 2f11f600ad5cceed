// Shared helpers of the test suite.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "cl/device.h"
#include "measure/scheduler.h"

namespace sdfbrick::test {

// Device spec of the tests (see ocl::select_devices); "cpu" (PoCL) when unset.
inline constexpr const char* kTestDeviceEnv = "SDFBRICK_TEST_DEVICE";

// The process-wide test device: the first device of open_test_devices(). Throws when no
// device matches (or none exists), which fails the calling test: tests never skip for lack of a device.
ocl::Device& device();

// A newly opened set of the devices that $SDFBRICK_TEST_DEVICE selects (nothing cached in memory yet).
ocl::DeviceSet open_test_devices();

// A new launch recorder on device() for one call of a builder or tracer (the previous one is dropped).
measure::Scheduler& recorder();

// The description of an NVIDIA H100 (132 compute units, compute capability 9.0) as the occupancy
// model reads it, for tests of rules that depend on it without the device.
ocl::DeviceInfo nvidia_h100_info();

// A fresh, empty directory SDFBRICK_TEST_TMP/name (removed first if it exists).
std::filesystem::path temp_dir(std::string_view name);

// Writes text to path (replacing it), creating parent directories; throws on failure.
void write_text(const std::filesystem::path& path, std::string_view text);

// The message of the InputError `step` throws, or "" when it throws none.
std::string input_error_of(const std::function<void()>& step);

// Sets (or, with std::nullopt, unsets) an environment variable for the scope's lifetime, then
// restores the previous state.
class ScopedEnv {
public:
    ScopedEnv(std::string name, const std::optional<std::string>& value);
    ~ScopedEnv();
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string name_;
    std::optional<std::string> previous_;
};

}  // namespace sdfbrick::test
