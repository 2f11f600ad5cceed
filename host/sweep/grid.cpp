#include "sweep/grid.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/quote.h"
#include "render/methods.h"

namespace sdfbrick::sweep {

namespace {

template <class T>
std::vector<std::optional<T>> or_default(const std::vector<T>& v) {
    if (v.empty()) return {std::nullopt};
    return {v.begin(), v.end()};
}

template <class T>
void check_each(const std::vector<T>& values, const char* key, auto&& ok, const char* expected) {
    for (const T& v : values)
        if (!ok(v)) throw InputError(fmt::format("sweep: \"{}\" has {}; expected {}", key, escaped(nlohmann::json(v).dump()), expected));
}

// One JSON value as T, strictly: an integer must be a whole number within T's range (no silent
// truncation of 64.5 or 1e30), a bool a JSON boolean, a string a JSON string.
template <class T>
std::optional<T> value_as(const nlohmann::json& v) {
    if constexpr (std::is_same_v<T, bool>) {
        if (v.is_boolean()) return v.get<bool>();
    } else if constexpr (std::is_integral_v<T>) {
        if (!v.is_number()) return std::nullopt;
        const double d = v.get<double>();
        if (d == std::floor(d) && d >= static_cast<double>(std::numeric_limits<T>::min()) &&
            d <= static_cast<double>(std::numeric_limits<T>::max()))
            return static_cast<T>(d);
    } else if constexpr (std::is_floating_point_v<T>) {
        if (v.is_number()) return v.get<T>();
    } else {
        if (v.is_string()) return v.get<T>();
    }
    return std::nullopt;
}

template <class T>
std::string kind_name() {
    if constexpr (std::is_same_v<T, bool>) return "true or false";
    else if constexpr (std::is_integral_v<T>)
        return fmt::format("a whole number in [{}, {}]", std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
    else if constexpr (std::is_floating_point_v<T>) return "a number";
    else return "a string";
}

template <class T>
std::vector<T> list(const nlohmann::json& j, const char* key, const std::string& where) {
    if (!j.contains(key)) return {};
    const nlohmann::json& v = j.at(key);
    std::vector<T> out;
    for (const nlohmann::json& item : v.is_array() ? v : nlohmann::json::array({v})) {
        const std::optional<T> value = value_as<T>(item);
        if (!value)
            throw InputError(fmt::format("{}: \"{}\" must be {} or a list of them, got {}", where, key, kind_name<T>(),
                                         escaped(item.dump())));
        out.push_back(*value);
    }
    return out;
}

template <class T>
T scalar(const nlohmann::json& j, const char* key, const std::string& where, T fallback) {
    if (!j.contains(key)) return fallback;
    const std::optional<T> value = value_as<T>(j.at(key));
    if (!value) throw InputError(fmt::format("{}: \"{}\" must be {}, got {}", where, key, kind_name<T>(), escaped(j.at(key).dump())));
    return *value;
}

}  // namespace

std::pair<int, int> parse_group_2d(const std::string& text, const std::string& what) {
    const auto x = text.find('x');
    int a = 0, b = 0;
    const auto parse = [](std::string_view s, int& out) {
        const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
        return r.ec == std::errc() && r.ptr == s.data() + s.size() && out > 0;
    };
    if (x == std::string::npos || !parse(std::string_view(text).substr(0, x), a) ||
        !parse(std::string_view(text).substr(x + 1), b))
        throw InputError(fmt::format("{}: {} is not a work-group size WxH such as 16x8", what, quoted_input(text)));
    return {a, b};
}

void SweepSpec::validate() const {
    if (scenes.empty()) throw InputError("sweep: no scene given (\"scenes\" is empty)");
    check_each(brick_sizes, "brick_sizes", [](double v) { return std::isfinite(v) && v > 0.0; }, "positive numbers");
    check_each(tolerances, "tolerances", [](double v) { return std::isfinite(v) && v >= 0.0; },
               "numbers >= 0 (0: uniform)");
    check_each(chunks, "chunks", [](int v) { return v >= 16 && v <= 256; }, "values in 16..256");
    check_each(groups, "groups", [](int v) { return v >= 1 && v <= 1024 && (v & (v - 1)) == 0; }, "powers of two in 1..1024");
    for (const std::string& g : trace_groups) parse_group_2d(g, "sweep: \"trace_groups\"");
    check_each(formats, "formats", [](const std::string& v) { return v == "int8" || v == "int16" || v == "float"; },
               "int8, int16 or float");
    check_each(samples, "samples", [](int v) { return v == 8 || v == 10; }, "8 or 10");
    check_each(methods, "methods", [](const std::string& v) { return render::method_from_string(v).has_value(); },
               render::method_names().c_str());
    check_each(normals, "normals", [](const std::string& v) { return v == "central" || v == "tetra" || v == "continuous"; },
               "central, tetra or continuous");
    if (width < 1 || width > 3840 || height < 1 || height > 2160)
        throw InputError(fmt::format("sweep: image size {}x{} must lie within 1x1..3840x2160", width, height));
    if (warmup < 0 || warmup > 100) throw InputError(fmt::format("sweep: warmup must lie in 0..100, got {}", warmup));
    if (repeat < 1 || repeat > 1000) throw InputError(fmt::format("sweep: repeat must lie in 1..1000, got {}", repeat));
}

namespace {

// a * b, or the largest std::size_t where the product would wrap.
std::size_t saturating_product(std::size_t a, std::size_t b) {
    std::size_t p = 0;
    return __builtin_mul_overflow(a, b, &p) ? std::numeric_limits<std::size_t>::max() : p;
}

}  // namespace

std::size_t SweepSpec::size_per_device() const {
    std::size_t product = scenes.size();
    for (std::size_t s : {brick_sizes.size(), tolerances.size(), chunks.size(), groups.size(), trace_groups.size(),
                          culls.size(), formats.size(), samples.size(), methods.size(), normals.size()})
        product = saturating_product(product, std::max<std::size_t>(s, 1));
    return product;
}

SweepSpec spec_from_json(const nlohmann::json& j, const std::string& where) {
    if (!j.is_object()) throw InputError(fmt::format("{}: a sweep file is a JSON object", where));
    static const char* const kKeys[] = {"scenes", "brick_sizes", "tolerances", "chunks", "groups", "trace_groups", "cull",
                                        "formats", "samples", "methods", "normals", "devices", "width",
                                        "height", "warmup", "repeat", "accuracy"};
    for (const auto& item : j.items()) {
        const std::string& key = item.key();
        if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }) == std::end(kKeys))
            throw InputError(fmt::format("{}: unknown key {}", where, quoted_input(key)));
    }
    SweepSpec s;
    s.scenes = list<std::string>(j, "scenes", where);
    s.brick_sizes = list<double>(j, "brick_sizes", where);
    s.tolerances = list<double>(j, "tolerances", where);
    s.chunks = list<int>(j, "chunks", where);
    s.groups = list<int>(j, "groups", where);
    s.trace_groups = list<std::string>(j, "trace_groups", where);
    s.culls = list<bool>(j, "cull", where);
    s.formats = list<std::string>(j, "formats", where);
    s.samples = list<int>(j, "samples", where);
    s.methods = list<std::string>(j, "methods", where);
    s.normals = list<std::string>(j, "normals", where);
    s.devices = scalar<std::string>(j, "devices", where, "");
    s.width = scalar(j, "width", where, s.width);
    s.height = scalar(j, "height", where, s.height);
    s.warmup = scalar(j, "warmup", where, s.warmup);
    s.repeat = scalar(j, "repeat", where, s.repeat);
    s.accuracy = scalar(j, "accuracy", where, s.accuracy);
    return s;
}

nlohmann::json to_json(const SweepSpec& s) {
    return {{"scenes", s.scenes}, {"brick_sizes", s.brick_sizes}, {"tolerances", s.tolerances}, {"chunks", s.chunks}, {"groups", s.groups},
            {"trace_groups", s.trace_groups}, {"cull", s.culls}, {"formats", s.formats}, {"samples", s.samples},
            {"methods", s.methods}, {"normals", s.normals}, {"devices", s.devices}, {"width", s.width},
            {"height", s.height}, {"warmup", s.warmup}, {"repeat", s.repeat}, {"accuracy", s.accuracy}};
}

std::string SweepPoint::key(const SweepSpec& spec) const {
    const auto opt = [](const auto& v) { return v ? fmt::format("{}", *v) : std::string("auto"); };
    return fmt::format("scene={};device={};brick={:.17g};chunk={};group={};trace_group={};cull={};format={};samples={};"
                       "method={};normals={};image={}x{};warmup={};repeat={};accuracy={}",
                       scene, device, brick_size, opt(chunk), opt(group), opt(trace_group), cull ? 1 : 0, format,
                       samples, method, normals, spec.width, spec.height, spec.warmup, spec.repeat, spec.accuracy ? 1 : 0) +
           (tolerance > 0.0 ? fmt::format(";tolerance={:.17g}", tolerance) : std::string());
}

std::vector<SweepPoint> expand(const SweepSpec& spec, const std::vector<std::string>& devices, std::size_t max_points) {
    spec.validate();
    const std::size_t total = saturating_product(spec.size_per_device(), devices.size());
    if (total == 0) throw InputError("sweep: the grid is empty (no device?)");
    if (total > max_points) {
        const bool wraps = total == std::numeric_limits<std::size_t>::max();
        throw InputError(fmt::format("sweep: the grid has {} points, more than {}: split it or use fewer values",
                                     wraps ? std::string("2^64 or more") : std::to_string(total), max_points));
    }
    std::vector<SweepPoint> out;
    out.reserve(total);
    SweepPoint p;
    const SweepPoint defaults;
    for (const std::string& device : devices)
        for (const std::string& scene : spec.scenes)
            for (const auto& brick : or_default(spec.brick_sizes))
              for (const auto& tolerance : or_default(spec.tolerances))
                for (const auto& chunk : or_default(spec.chunks))
                    for (const auto& group : or_default(spec.groups))
                        for (const auto& trace_group : or_default(spec.trace_groups))
                            for (const auto& cull : or_default(spec.culls))
                                for (const auto& format : or_default(spec.formats))
                                    for (const auto& samples : or_default(spec.samples))
                                        for (const auto& method : or_default(spec.methods))
                                            for (const auto& normals : or_default(spec.normals)) {
                                                p.index = out.size();
                                                p.device = device;
                                                p.scene = scene;
                                                p.brick_size = brick.value_or(defaults.brick_size);
                                                p.tolerance = tolerance.value_or(defaults.tolerance);
                                                p.chunk = chunk;
                                                p.group = group;
                                                p.trace_group = trace_group;
                                                p.cull = cull.value_or(defaults.cull);
                                                p.format = format.value_or(defaults.format);
                                                p.samples = samples.value_or(defaults.samples);
                                                p.method = method.value_or(defaults.method);
                                                p.normals = normals.value_or(defaults.normals);
                                                out.push_back(p);
                                            }
    return out;
}

Shard parse_shard(const std::string& text) {
    const auto slash = text.find('/');
    Shard s;
    const auto parse = [](std::string_view v, std::size_t& out) {
        const auto r = std::from_chars(v.data(), v.data() + v.size(), out);
        return r.ec == std::errc() && r.ptr == v.data() + v.size() && !v.empty();
    };
    if (slash == std::string::npos || !parse(std::string_view(text).substr(0, slash), s.index) ||
        !parse(std::string_view(text).substr(slash + 1), s.count) || s.count == 0 || s.index >= s.count)
        throw SettingError("shard", fmt::format("shard must be i/n with 0 <= i < n (e.g. 0/4), got \"{}\"", text));
    return s;
}

std::vector<SweepPoint> shard_points(const std::vector<SweepPoint>& points, Shard shard) {
    std::vector<SweepPoint> out;
    for (std::size_t i = shard.index; i < points.size(); i += shard.count) out.push_back(points[i]);
    return out;
}

}  // namespace sdfbrick::sweep
