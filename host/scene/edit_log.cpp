#include "scene/edit_log.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "scene/scene_json.h"
#include "sdf_types.h"

namespace sdfbrick {

namespace {

using json = nlohmann::json;

constexpr int kMaxLogFrame = 1 << 30;

// One line's place in messages: "origin:LINE". A field's name is echoed escaped (it may be any key).
struct Line {
    std::string where;
    [[noreturn]] void fail(std::string_view field, const std::string& what) const {
        throw InputError(fmt::format("{}: /{}: {}", where, escaped(field), what));
    }
};

std::string type_of(const json& v) { return v.is_null() ? "null" : v.type_name(); }

// A non-negative integer field no larger than hi.
std::size_t count_field(const Line& l, const json& j, std::string_view key, double hi) {
    const auto it = j.find(key);
    if (it == j.end()) l.fail(key, "missing field");
    if (!it->is_number()) l.fail(key, "expected an integer, got " + type_of(*it));
    const double v = it->get<double>();
    if (!(v >= 0.0) || v != std::floor(v) || v > hi) l.fail(key, fmt::format("must be an integer in [0, {:g}], got {}", hi, v));
    return static_cast<std::size_t>(v);
}

std::size_t geometry_field(const Line& l, const json& j, const Scene& scene) {
    const auto it = j.find("geometry");
    if (it == j.end()) l.fail("geometry", "missing field");
    if (it->is_string()) {
        const std::string name = it->get<std::string>();
        for (std::size_t g = 0; g < scene.geometries.size(); ++g)
            if (scene.geometries[g].name == name) return g;
        l.fail("geometry", fmt::format("no geometry named {}", quoted_input(name)));
    }
    if (!it->is_number()) l.fail("geometry", "expected a name or an index, got " + type_of(*it));
    const std::size_t g = count_field(l, j, "geometry", 1e9);
    if (g >= scene.geometries.size())
        l.fail("geometry", fmt::format("no geometry {} (the scene has {})", g, scene.geometries.size()));
    return g;
}

EditOp::Kind kind_field(const Line& l, const json& j) {
    const auto it = j.find("op");
    if (it == j.end()) l.fail("op", "missing field");
    if (!it->is_string()) l.fail("op", "expected a string, got " + type_of(*it));
    const std::string s = it->get<std::string>();
    for (EditOp::Kind k : {EditOp::Kind::append, EditOp::Kind::remove, EditOp::Kind::replace})
        if (s == to_string(k)) return k;
    l.fail("op", fmt::format("unknown operation {} (known: append, remove, replace)", quoted_input(s)));
}

std::vector<Edit> edits_field(const Line& l, const json& j, EditOp::Kind kind) {
    const bool one = j.contains("edit"), many = j.contains("edits");
    if (kind == EditOp::Kind::remove) {
        if (one || many) l.fail(one ? "edit" : "edits", "remove takes no edit");
        return {};
    }
    if (one == many) l.fail("edit", "needs exactly one of \"edit\" and \"edits\"");
    if (kind == EditOp::Kind::replace && many) l.fail("edits", "replace takes one \"edit\"");
    if (one) return {edit_from_json(j["edit"], l.where, "/edit")};
    const json& a = j["edits"];
    if (!a.is_array() || a.empty()) l.fail("edits", "expected a non-empty array of edits");
    std::vector<Edit> out;
    for (std::size_t i = 0; i < a.size(); ++i) out.push_back(edit_from_json(a[i], l.where, fmt::format("/edits/{}", i)));
    return out;
}

EditOp read_op(const Line& l, const json& j, const Scene& scene) {
    if (!j.is_object()) throw InputError(fmt::format("{}: expected an operation object, got {}", l.where, type_of(j)));
    for (const auto& [key, v] : j.items())
        if (key != "frame" && key != "op" && key != "geometry" && key != "index" && key != "edit" && key != "edits")
            l.fail(key, "unknown field (known: frame, op, geometry, index, edit, edits)");
    EditOp op;
    op.frame = static_cast<int>(count_field(l, j, "frame", kMaxLogFrame));
    op.kind = kind_field(l, j);
    op.geometry = geometry_field(l, j, scene);
    if (op.kind != EditOp::Kind::append) op.index = count_field(l, j, "index", SDF_MAX_EDITS);
    else if (j.contains("index")) l.fail("index", "append takes no index (edits go to the end)");
    op.edits = edits_field(l, j, op.kind);
    return op;
}

}  // namespace

std::string_view to_string(EditOp::Kind k) {
    switch (k) {
        case EditOp::Kind::append: return "append";
        case EditOp::Kind::remove: return "remove";
        case EditOp::Kind::replace: return "replace";
    }
    return "?";
}

EditLog parse_edit_log(std::string_view text, std::string_view origin, const Scene& scene) {
    EditLog log;
    log.origin = std::string(origin);
    std::vector<std::size_t> sizes;  // each geometry's edits as the operations so far leave them
    for (const Geometry& g : scene.geometries) sizes.push_back(g.edits.size());
    std::size_t line = 0;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view body = text.substr(start, end - start);
        start = end + 1;
        ++line;
        if (body.find_first_not_of(" \t\r") == std::string_view::npos) continue;
        const Line l{fmt::format("{}:{}", escaped(origin, 160), line)};
        EditOp op = read_op(l, parse_json_text(body, l.where), scene);
        op.line = line;
        if (!log.ops.empty() && op.frame < log.ops.back().frame)
            l.fail("frame", fmt::format("frames must not decrease: {} after {}", op.frame, log.ops.back().frame));
        std::size_t& n = sizes[op.geometry];
        const std::string& name = scene.geometries[op.geometry].name;
        if (op.kind != EditOp::Kind::append && op.index >= n)
            l.fail("index", fmt::format("no edit {} in geometry {} (it has {} there)", op.index, quoted_input(name), n));
        if (op.kind == EditOp::Kind::remove && n == 1)
            l.fail("index", fmt::format("removes the last edit of geometry {}: a geometry keeps one", quoted_input(name)));
        if (op.kind == EditOp::Kind::append && n + op.edits.size() > SDF_MAX_EDITS)
            l.fail("edits", fmt::format("geometry {} would hold more than {} edits", quoted_input(name), SDF_MAX_EDITS));
        n = op.kind == EditOp::Kind::append ? n + op.edits.size() : op.kind == EditOp::Kind::remove ? n - 1 : n;
        log.ops.push_back(std::move(op));
    }
    return log;
}

EditLog load_edit_log(const std::filesystem::path& path, const Scene& scene) {
    return parse_edit_log(read_file(path), path.string(), scene);
}

void apply(Scene& scene, const EditOp& op) {
    std::vector<Edit>& edits = scene.geometries.at(op.geometry).edits;
    switch (op.kind) {
        case EditOp::Kind::append: edits.insert(edits.end(), op.edits.begin(), op.edits.end()); break;
        case EditOp::Kind::remove: edits.erase(edits.begin() + static_cast<std::ptrdiff_t>(op.index)); break;
        case EditOp::Kind::replace: edits.at(op.index) = op.edits.front(); break;
    }
}

}  // namespace sdfbrick
