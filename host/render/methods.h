// The tracer's choices by name: the in-brick surface search and the normal rule (kernels/sdf_trace.h),
// with their names for flags, sweep keys and reports. Plain data: nothing here touches a device.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace sdfbrick::render {

enum class Method { sphere, analytic, hybrid };         // in-brick surface search (kernels/sdf_trace.h METHOD)
enum class NormalMethod { central, tetra, continuous };  // see kernels/sdf_trace.h
inline constexpr std::array<Method, 3> kMethods{Method::sphere, Method::analytic, Method::hybrid};
inline constexpr std::array<NormalMethod, 3> kNormalMethods{NormalMethod::central, NormalMethod::tetra,
                                                            NormalMethod::continuous};
std::string_view to_string(Method m);
std::string_view to_string(NormalMethod n);
std::optional<Method> method_from_string(std::string_view s);
std::optional<NormalMethod> normals_from_string(std::string_view s);
// "sphere, analytic or hybrid" (sep ", ", last " or "): the method names for messages and help.
std::string method_names(std::string_view last = " or ");

}  // namespace sdfbrick::render
