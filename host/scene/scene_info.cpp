#include "scene/scene_info.h"

#include <algorithm>

#include <fmt/format.h>

#include "scene/mesh.h"

namespace sdfbrick {

using nlohmann::json;

json to_json(const Aabb& b) {
    if (b.empty()) return nullptr;
    return {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}}};
}

namespace {

// g: the geometry at the scene's time; animated: the same geometry as the file has it.
GeometrySummary geometry_summary(const Geometry& g, const Geometry& animated) {
    GeometrySummary s;
    s.name = g.name;
    s.edits = g.edits.size();
    for (std::size_t i = 0; i < kPrimitiveCount; ++i) s.primitives[std::string(to_string(static_cast<Primitive>(i)))] = 0;
    s.primitives["vdb"] = 0;  // a level set from a file: a mesh edit without triangles
    for (Op op : {Op::Add, Op::Subtract, Op::Intersect}) s.ops[std::string(to_string(op))] = 0;
    for (std::size_t i = 0; i < g.edits.size(); ++i) {
        const Edit& e = g.edits[i];
        ++s.primitives[e.mesh && e.mesh->level_set() ? std::string("vdb") : std::string(to_string(e.primitive))];
        ++s.ops[std::string(to_string(e.op))];
        s.smooth_edits += e.blend > 0.0;
        s.animated_edits += animated.edits[i].animation.has_value();
        s.max_blend = std::max(s.max_blend, e.blend);
        s.max_lipschitz = std::max(s.max_lipschitz, lipschitz(e));
    }
    s.bounds = bounds(g);
    return s;
}

json to_json(const SurfaceCells& c) {
    return {{"leaf_size", c.leaf_size}, {"branching", c.branching}, {"levels", c.levels},
            {"per_level", c.per_level}, {"leaves", c.per_level.empty() ? 0 : c.per_level.back()},
            {"seconds", c.seconds}};
}

json to_json(const GeometrySummary& g) {
    json j = {{"name", g.name},
              {"edits", g.edits},
              {"primitives", g.primitives},
              {"ops", g.ops},
              {"smooth_edits", g.smooth_edits},
              {"animated_edits", g.animated_edits},
              {"max_blend", g.max_blend},
              {"max_lipschitz", g.max_lipschitz},
              {"bounds", to_json(g.bounds)}};
    if (g.surface_cells) j["surface_cells"] = to_json(*g.surface_cells);
    return j;
}

std::string bounds_text(const Aabb& b) {
    if (b.empty()) return "empty";
    return fmt::format("[{:.3f}, {:.3f}, {:.3f}] .. [{:.3f}, {:.3f}, {:.3f}]", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y,
                       b.hi.z);
}

std::string histogram_text(const std::map<std::string, int>& h) {
    std::string out;
    for (const auto& [k, v] : h)
        if (v > 0) out += fmt::format("{}{} {}", out.empty() ? "" : ", ", k, v);
    return out.empty() ? "none" : out;
}

std::string to_text(const GeometrySummary& g) {
    std::string out = fmt::format("  geometry {}: {} edits ({} smooth, {} animated, max blend {})\n", g.name, g.edits,
                                  g.smooth_edits, g.animated_edits, g.max_blend);
    out += fmt::format("    primitives: {}\n", histogram_text(g.primitives));
    out += fmt::format("    ops: {}\n", histogram_text(g.ops));
    out += fmt::format("    bounds: {}\n", bounds_text(g.bounds));
    if (const auto& c = g.surface_cells)
        out += fmt::format("    surface cells at leaf size {} (branching {}, {} levels, host reference): {} leaves; "
                           "per level {}\n",
                           c->leaf_size, c->branching, c->levels, c->per_level.empty() ? 0 : c->per_level.back(),
                           json(c->per_level).dump());
    return out;
}

}  // namespace

SceneSummary scene_summary(const Scene& input) {
    const Scene s = scene_at(input, input.time);
    SceneSummary out;
    out.name = s.name;
    out.time = s.time;
    for (std::size_t gi = 0; gi < s.geometries.size(); ++gi)
        out.geometries.push_back(geometry_summary(s.geometries[gi], input.geometries[gi]));
    for (const Object& o : s.objects) {
        const Aabb b = bounds(s, o);
        out.bounds.grow(b);
        out.objects.push_back({o.name, s.geometries[o.geometry].name, o.transform.scale, b});
    }
    out.eye = s.camera.eye_position();
    out.target = s.camera.target;
    out.fov_deg = s.camera.fov_deg;
    return out;
}

json to_json(const SceneSummary& s) {
    json geometries = json::array(), objects = json::array();
    for (const GeometrySummary& g : s.geometries) geometries.push_back(to_json(g));
    for (const ObjectSummary& o : s.objects)
        objects.push_back({{"name", o.name}, {"geometry", o.geometry}, {"scale", o.scale}, {"bounds", to_json(o.bounds)}});
    json j = {{"name", s.name},
              {"time", s.time},
              {"geometries", geometries},
              {"objects", objects},
              {"bounds", to_json(s.bounds)},
              {"camera", {{"eye", {s.eye.x, s.eye.y, s.eye.z}},
                          {"target", {s.target.x, s.target.y, s.target.z}},
                          {"fov_deg", s.fov_deg}}}};
    if (!s.file.empty()) j["file"] = s.file;
    return j;
}

std::string to_text(const SceneSummary& s) {
    std::string out = fmt::format("scene {} at t = {} s\n", s.name, s.time);
    for (const GeometrySummary& g : s.geometries) out += to_text(g);
    for (const ObjectSummary& o : s.objects)
        out += fmt::format("  object {} -> {} (scale {}), bounds {}\n", o.name, o.geometry, o.scale, bounds_text(o.bounds));
    out += fmt::format("  world bounds: {}\n", bounds_text(s.bounds));
    return out;
}

}  // namespace sdfbrick
