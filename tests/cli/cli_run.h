// Running the sdfbrick binary from a test: exit status, stdout and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "core/files.h"
#include "test_support.h"

namespace sdfbrick::test {

struct CliRun {
    int status = -1;
    std::string out, err;
};

// Runs the sdfbrick binary with `args` (a shell fragment) after `env` (assignments, or any shell
// prefix), capturing stdout and stderr; `stdout_to` replaces the capture of stdout (">/dev/full",
// ">&-"). One directory per test: CTest runs the tests in parallel processes.
inline CliRun sdfbrick(const std::string& args, const std::string& env = "", const std::string& stdout_to = "") {
    const std::filesystem::path dir =
        temp_dir(std::string("cli_run_") + testing::UnitTest::GetInstance()->current_test_info()->name());
    test::write_text(dir / "out", "");
    const std::string cmd = env + " " SDFBRICK_CLI_PATH " " + args + " " +
                            (stdout_to.empty() ? ">" + (dir / "out").string() : stdout_to) + " 2>" + (dir / "err").string();
    const int raw = std::system(cmd.c_str());
    CliRun r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(dir / "out");
    r.err = read_file(dir / "err");
    return r;
}

// The device the tests run on (tests/test_support.cpp reads the same variable).
inline std::string test_device_spec() {
    const char* spec = std::getenv(kTestDeviceEnv);
    return spec && *spec ? spec : "cpu";
}

// The environment that makes the CLI run on the test device.
inline std::string device_env() { return "SDFBRICK_DEVICE=" + test_device_spec(); }

// Exactly one line on stderr, starting "sdfbrick: ", of printable ASCII.
inline ::testing::AssertionResult one_clean_line(const CliRun& r) {
    const std::string& e = r.err;
    if (e.size() < 11 || e.rfind("sdfbrick: ", 0) != 0 || e.back() != '\n' || e.find('\n') != e.size() - 1)
        return ::testing::AssertionFailure() << "not one line: [" << e << "]";
    for (char c : e.substr(0, e.size() - 1))
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
            return ::testing::AssertionFailure() << "unprintable byte in: [" << e << "]";
    return ::testing::AssertionSuccess();
}

inline std::string scene_path(const std::string& name) {
    return std::string(SDFBRICK_SOURCE_DIR) + "/scenes/" + name + ".json";
}

}  // namespace sdfbrick::test
