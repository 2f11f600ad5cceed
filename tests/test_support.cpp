#include "test_support.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace sdfbrick::test {

namespace {

void set_env(const std::string& name, const std::optional<std::string>& value) {
    const int status = value ? setenv(name.c_str(), value->c_str(), 1) : unsetenv(name.c_str());
    if (status != 0) {
        throw std::runtime_error("cannot set environment variable " + name);
    }
}

}  // namespace

ocl::DeviceSet open_test_devices() {
    const char* spec = std::getenv(kTestDeviceEnv);
    return ocl::DeviceSet::open(spec != nullptr && *spec != '\0' ? spec : "cpu");
}

ocl::Device& device() {
    static ocl::DeviceSet devices = open_test_devices();
    return devices[0];
}

std::filesystem::path temp_dir(std::string_view name) {
    const std::filesystem::path dir = std::filesystem::path(SDFBRICK_TEST_TMP) / std::filesystem::path(name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

void write_text(const std::filesystem::path& path, std::string_view text) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
        throw std::runtime_error("cannot write " + path.string());
    }
}

ScopedEnv::ScopedEnv(std::string name, const std::optional<std::string>& value) : name_(std::move(name)) {
    if (const char* previous = std::getenv(name_.c_str())) {
        previous_ = previous;
    }
    set_env(name_, value);
}

ScopedEnv::~ScopedEnv() {
    // The constructor showed that the name is valid, so restoring cannot fail for that reason.
    if (previous_) {
        setenv(name_.c_str(), previous_->c_str(), 1);
    } else {
        unsetenv(name_.c_str());
    }
}

}  // namespace sdfbrick::test
