#include "scene/scene_info.h"

#include <algorithm>

#include <fmt/format.h>

namespace sdfbrick {

using nlohmann::json;

json to_json(const Aabb& b) {
    if (b.empty()) return nullptr;
    return {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}}};
}

json scene_summary(const Scene& input) {
    const Scene s = scene_at(input, input.time);
    json geos = json::array();
    for (std::size_t gi = 0; gi < s.geometries.size(); ++gi) {
        const Geometry& g = s.geometries[gi];
        json prims = json::object(), ops = json::object();
        std::size_t smooth = 0, animated = 0;
        double max_blend = 0.0, max_lipschitz = 1.0;
        for (std::size_t i = 0; i < kPrimitiveCount; ++i) prims[std::string(to_string(static_cast<Primitive>(i)))] = 0;
        for (Op op : {Op::Add, Op::Subtract, Op::Intersect}) ops[std::string(to_string(op))] = 0;
        for (std::size_t i = 0; i < g.edits.size(); ++i) {
            const Edit& e = g.edits[i];
            prims[std::string(to_string(e.primitive))] = prims[std::string(to_string(e.primitive))].get<int>() + 1;
            ops[std::string(to_string(e.op))] = ops[std::string(to_string(e.op))].get<int>() + 1;
            smooth += e.blend > 0.0;
            animated += input.geometries[gi].edits[i].animation.has_value();
            max_blend = std::max(max_blend, e.blend);
            max_lipschitz = std::max(max_lipschitz, lipschitz(e));
        }
        geos.push_back({{"name", g.name}, {"edits", g.edits.size()}, {"primitives", prims}, {"ops", ops},
                        {"smooth_edits", smooth}, {"animated_edits", animated}, {"max_blend", max_blend},
                        {"max_lipschitz", max_lipschitz}, {"bounds", to_json(bounds(g))}});
    }
    json objs = json::array();
    Aabb world;
    for (const Object& o : s.objects) {
        const Aabb b = bounds(s, o);
        world.grow(b);
        objs.push_back({{"name", o.name}, {"geometry", s.geometries[o.geometry].name}, {"scale", o.transform.scale},
                        {"bounds", to_json(b)}});
    }
    const glm::dvec3 eye = s.camera.eye_position();
    return {{"name", s.name},
            {"time", s.time},
            {"geometries", geos},
            {"objects", objs},
            {"bounds", to_json(world)},
            {"camera", {{"eye", {eye.x, eye.y, eye.z}},
                        {"target", {s.camera.target.x, s.camera.target.y, s.camera.target.z}},
                        {"fov_deg", s.camera.fov_deg}}}};
}

namespace {
std::string bounds_text(const json& b) {
    if (b.is_null()) return "empty";
    return fmt::format("[{:.3f}, {:.3f}, {:.3f}] .. [{:.3f}, {:.3f}, {:.3f}]", b["lo"][0].get<double>(), b["lo"][1].get<double>(),
                       b["lo"][2].get<double>(), b["hi"][0].get<double>(), b["hi"][1].get<double>(), b["hi"][2].get<double>());
}
std::string histogram_text(const json& h) {
    std::string out;
    for (const auto& [k, v] : h.items())
        if (v.get<int>() > 0) out += fmt::format("{}{} {}", out.empty() ? "" : ", ", k, v.get<int>());
    return out.empty() ? "none" : out;
}
}  // namespace

std::string scene_summary_text(const json& s) {
    std::string out = fmt::format("scene {} at t = {} s\n", s["name"].get<std::string>(), s["time"].get<double>());
    for (const json& g : s["geometries"]) {
        out += fmt::format("  geometry {}: {} edits ({} smooth, {} animated, max blend {})\n", g["name"].get<std::string>(),
                           g["edits"].get<std::size_t>(), g["smooth_edits"].get<std::size_t>(),
                           g["animated_edits"].get<std::size_t>(), g["max_blend"].get<double>());
        out += fmt::format("    primitives: {}\n", histogram_text(g["primitives"]));
        out += fmt::format("    ops: {}\n", histogram_text(g["ops"]));
        out += fmt::format("    bounds: {}\n", bounds_text(g["bounds"]));
        if (g.contains("surface_cells")) {
            const json& c = g["surface_cells"];
            out += fmt::format("    surface cells at leaf size {} (branching {}, {} levels, host reference): {} leaves; per level {}\n",
                               c["leaf_size"].get<double>(), c["branching"].get<int>(), c["levels"].get<int>(),
                               c["leaves"].get<std::uint64_t>(), c["per_level"].dump());
        }
    }
    for (const json& o : s["objects"])
        out += fmt::format("  object {} -> {} (scale {}), bounds {}\n", o["name"].get<std::string>(),
                           o["geometry"].get<std::string>(), o["scale"].get<double>(), bounds_text(o["bounds"]));
    out += fmt::format("  world bounds: {}\n", bounds_text(s["bounds"]));
    return out;
}

}  // namespace sdfbrick
