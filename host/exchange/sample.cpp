#include "exchange/sample.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>

#include "core/errors.h"
#include "core/files.h"
#include "reference/reference_field.h"

namespace sdfbrick::exchange {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

// "x,y,z" -> three numbers, or nullopt.
std::optional<glm::dvec3> parse_csv_line(std::string_view line) {
    glm::dvec3 p;
    for (int axis = 0; axis < 3; ++axis) {
        const std::size_t comma = axis < 2 ? line.find(',') : line.size();
        if (comma == std::string_view::npos) return std::nullopt;
        const std::string_view field = trim(line.substr(0, comma));
        const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), p[axis]);
        if (ec != std::errc() || end != field.data() + field.size() || field.empty()) return std::nullopt;
        line = axis < 2 ? line.substr(comma + 1) : std::string_view();
    }
    return p;
}

// A header line: three names such as "x,y,z", none of which begins like a number (a digit, a sign or
// a point); a first line of numbers that do not parse ("1e400") is an error, not a header.
bool is_header(std::string_view line) {
    for (int field = 0; field < 3; ++field) {
        const std::size_t comma = line.find(',');
        if ((comma == std::string_view::npos) != (field == 2)) return false;
        const std::string_view name = trim(line.substr(0, comma));
        if (name.empty() || std::isdigit(static_cast<unsigned char>(name.front())) ||
            std::string_view("+-.").find(name.front()) != std::string_view::npos)
            return false;
        line = field < 2 ? line.substr(comma + 1) : std::string_view();
    }
    return true;
}

std::vector<glm::dvec3> read_csv_points(const std::filesystem::path& path, const std::string& text) {
    std::vector<glm::dvec3> points;
    std::size_t line_no = 0, pos = 0;
    bool header_allowed = true;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        const std::string_view line = trim(std::string_view(text).substr(pos, end - pos));
        pos = end + 1;
        ++line_no;
        if (line.empty()) continue;
        const std::optional<glm::dvec3> p = parse_csv_line(line);
        if (!p && header_allowed && is_header(line)) {
            header_allowed = false;
            continue;
        }
        if (!p) throw InputError(fmt::format("{}: line {}: expected three numbers x,y,z", path.string(), line_no));
        header_allowed = false;
        if (!std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->z))
            throw InputError(fmt::format("{}: line {}: a coordinate is not finite", path.string(), line_no));
        points.push_back(*p);
    }
    return points;
}

std::vector<glm::dvec3> read_binary_points(const std::filesystem::path& path, const std::string& bytes) {
    if (bytes.size() % 12 != 0)
        throw InputError(fmt::format("{}: {} bytes is not a whole number of float32 x y z points (12 bytes each)",
                                     path.string(), bytes.size()));
    std::vector<glm::dvec3> points(bytes.size() / 12);
    for (std::size_t n = 0; n < points.size(); ++n) {
        float xyz[3];
        std::memcpy(xyz, bytes.data() + 12 * n, 12);
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
            throw InputError(fmt::format("{}: point {}: a coordinate is not finite", path.string(), n));
        points[n] = glm::dvec3(xyz[0], xyz[1], xyz[2]);
    }
    return points;
}

}  // namespace

std::vector<glm::dvec3> read_points(const std::filesystem::path& path) {
    const std::string content = read_file(path);
    std::vector<glm::dvec3> points =
        path.extension() == ".csv" ? read_csv_points(path, content) : read_binary_points(path, content);
    if (points.empty()) throw InputError(fmt::format("{}: no points", path.string()));
    return points;
}

std::vector<PointSample> sample_points(const Scene& scene, std::span<const HostBricks> bricks,
                                       std::span<const glm::dvec3> points) {
    std::vector<PointSample> out(points.size());
    for (std::size_t n = 0; n < points.size(); ++n) {
        PointSample& s = out[n];
        s.point = points[n];
        s.reference = reference::evaluate(scene, s.point);
        for (std::size_t o = 0; o < scene.objects.size(); ++o) {
            const Object& obj = scene.objects[o];
            const HostBricks& b = bricks[obj.geometry];
            const std::optional<BrickSample> at = b.at(obj.transform.inverse_apply(s.point));
            if (!at) continue;
            const double d = at->distance * obj.transform.scale;  // world distance
            if (s.distance && *s.distance <= d) continue;
            s.distance = d;
            // world distance = s F(R^T (p - t) / s): its gradient is R grad F.
            s.gradient = obj.transform.rotation * at->gradient;
            s.object = static_cast<int>(o);
            s.saturated = std::abs(at->distance) >= at->band;
        }
    }
    return out;
}

std::string samples_csv(std::span<const PointSample> samples) {
    std::string out = "x,y,z,distance,gx,gy,gz,object,saturated,reference\n";
    for (const PointSample& s : samples) {
        out += fmt::format("{},{},{},", s.point.x, s.point.y, s.point.z);
        if (s.distance)
            out += fmt::format("{},{},{},{},", *s.distance, s.gradient.x, s.gradient.y, s.gradient.z);
        else
            out += ",,,,";
        out += fmt::format("{},{},{}\n", s.object, s.saturated ? 1 : 0, s.reference);
    }
    return out;
}

}  // namespace sdfbrick::exchange
