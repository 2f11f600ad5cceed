#include "render/methods.h"

namespace sdfbrick::render {

std::string_view to_string(Method m) {
    return m == Method::sphere ? "sphere" : m == Method::analytic ? "analytic" : "hybrid";
}
std::string_view to_string(NormalMethod n) {
    return n == NormalMethod::central ? "central" : n == NormalMethod::tetra ? "tetra" : "continuous";
}
std::optional<Method> method_from_string(std::string_view s) {
    for (Method m : kMethods)
        if (s == to_string(m)) return m;
    return std::nullopt;
}
std::string method_names(std::string_view last) {
    std::string out;
    for (std::size_t i = 0; i < kMethods.size(); ++i)
        out += std::string(i == 0 ? "" : i + 1 == kMethods.size() ? last : ", ") + std::string(to_string(kMethods[i]));
    return out;
}
std::optional<NormalMethod> normals_from_string(std::string_view s) {
    if (s == "central") return NormalMethod::central;
    if (s == "tetra") return NormalMethod::tetra;
    if (s == "continuous") return NormalMethod::continuous;
    return std::nullopt;
}

}  // namespace sdfbrick::render
