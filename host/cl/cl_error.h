// OpenCL errors: every failing OpenCL call becomes a ClError that carries the CL error code, its
// name and what the library was doing, e.g.
//   OpenCL error CL_OUT_OF_RESOURCES (-5) while enqueueing kernel eval_points on pthread-skylake...
#pragma once

#include <CL/cl.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace sdfbrick::ocl {

// "CL_OUT_OF_RESOURCES" for -5; every OpenCL 1.2 code, CL_PLATFORM_NOT_FOUND_KHR (-1001), and
// "unknown OpenCL error" for anything else.
const char* error_name(cl_int code);

class ClError : public std::runtime_error {
public:
    // doing: what was being done, phrased to follow "while" ("building kernels/x.cl for ...").
    // detail: optional further text (a build log, a hint), appended after ": ".
    ClError(cl_int code, std::string doing, std::string_view detail = {});

    cl_int code() const noexcept { return code_; }
    const std::string& doing() const noexcept { return doing_; }

private:
    cl_int code_;
    std::string doing_;
};

// Throws ClError(code, doing) unless code is CL_SUCCESS.
void check(cl_int code, std::string_view doing);

// The same, with the description built only on failure: check(status, [&] { return fmt::format(...); }).
template <class Describe>
    requires std::is_invocable_r_v<std::string, Describe>
void check(cl_int code, Describe&& describe) {
    if (code != CL_SUCCESS) {
        throw ClError(code, std::forward<Describe>(describe)());
    }
}

}  // namespace sdfbrick::ocl
