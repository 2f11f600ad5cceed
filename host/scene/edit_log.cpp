#include "scene/edit_log.h"


#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "scene/json_node.h"
#include "scene/scene_json.h"
#include "sdf_types.h"

namespace sdfbrick {

namespace {

using detail::Node;

constexpr int kMaxLogFrame = 1000000;

std::size_t geometry_field(const Node& n, const Scene& scene) {
    if (n.value().is_string()) {
        const std::string name = n.string();
        for (std::size_t g = 0; g < scene.geometries.size(); ++g)
            if (scene.geometries[g].name == name) return g;
        n.fail(fmt::format("no geometry named {}", quoted_input(name)));
    }
    if (!n.value().is_number()) n.fail("expected a name or an index");
    const auto g = static_cast<std::size_t>(n.integer(0, kMaxLogFrame));
    if (g >= scene.geometries.size()) n.fail(fmt::format("no geometry {} (the scene has {})", g, scene.geometries.size()));
    return g;
}

EditOp::Kind kind_field(const Node& n) {
    const std::string s = n.string();
    for (EditOp::Kind k : {EditOp::Kind::append, EditOp::Kind::remove, EditOp::Kind::replace})
        if (s == to_string(k)) return k;
    n.fail(fmt::format("unknown operation {} (known: append, remove, replace)", quoted_input(s)));
}

std::vector<Edit> edits_field(const Node& n, EditOp::Kind kind, std::string_view origin) {
    const bool one = n.has("edit"), many = n.has("edits");
    if (kind == EditOp::Kind::remove) {
        if (one || many) n[one ? "edit" : "edits"].fail("remove takes no edit");
        return {};
    }
    if (one == many) throw InputError(fmt::format("{}: /edit: needs exactly one of \"edit\" and \"edits\"", origin));
    if (kind == EditOp::Kind::replace && many) n["edits"].fail("replace takes one \"edit\"");
    if (one) return {edit_from_json(n["edit"].value(), origin, "/edit")};
    const Node list = n["edits"];
    const std::size_t count = list.array_size();
    if (count == 0) list.fail("expected a non-empty array of edits");
    std::vector<Edit> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(edit_from_json(list.at(i).value(), origin, list.at(i).path()));
    return out;
}

EditOp read_op(const Node& n, const Scene& scene, std::string_view origin) {
    n.expect_object({"frame", "op", "geometry", "index", "edit", "edits"});
    EditOp op;
    op.frame = n["frame"].integer(0, kMaxLogFrame);
    op.kind = kind_field(n["op"]);
    op.geometry = geometry_field(n["geometry"], scene);
    if (op.kind != EditOp::Kind::append) op.index = static_cast<std::size_t>(n["index"].integer(0, SDF_MAX_EDITS));
    else if (n.has("index")) n["index"].fail("append takes no index (edits go to the end)");
    op.edits = edits_field(n, op.kind, origin);
    return op;
}

// The operation against its geometry's edit count as the earlier operations leave it (size), which
// it then updates.
void check_size(const Node& n, const EditOp& op, const std::string& name, std::size_t& size) {
    if (op.kind != EditOp::Kind::append && op.index >= size)
        n["index"].fail(fmt::format("no edit {} in geometry {} (it has {} there)", op.index, quoted_input(name), size));
    if (op.kind == EditOp::Kind::remove && size == 1)
        n["index"].fail(fmt::format("removes the last edit of geometry {}: a geometry keeps one", quoted_input(name)));
    if (op.kind == EditOp::Kind::append && size + op.edits.size() > SDF_MAX_EDITS)
        n["edits"].fail(fmt::format("geometry {} would hold more than {} edits", quoted_input(name), SDF_MAX_EDITS));
    size = op.kind == EditOp::Kind::append ? size + op.edits.size() : op.kind == EditOp::Kind::remove ? size - 1 : size;
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
        const std::string where = fmt::format("{}:{}", escaped(origin, 160), line);
        const nlohmann::json j = parse_json_text(body, where);
        if (!j.is_object())
            throw InputError(fmt::format("{}: expected an operation object, got {}", where, j.is_null() ? "null" : j.type_name()));
        const Node n(j, "", where);
        EditOp op = read_op(n, scene, where);
        op.line = line;
        if (!log.ops.empty() && op.frame < log.ops.back().frame)
            n["frame"].fail(fmt::format("frames must not decrease: {} after {}", op.frame, log.ops.back().frame));
        check_size(n, op, scene.geometries[op.geometry].name, sizes[op.geometry]);
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
