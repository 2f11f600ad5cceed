// The stages of the engine's measured work: every kernel launch is recorded under one of them (and,
// for construction, a level). Reports and JSON name them with to_string(); the names are part of
// the report schema (docs/measurement.md).
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace sdfbrick::measure {

enum class Stage {
    edit_bounds,   // construction: per-edit boxes
    dependencies,  // construction: dependency lists of smooth edits
    count,         // construction, per level: children kept per parent
    scan,          // construction, per level: prefix sums of the counts
    subdivide,     // construction, per level: the kept children, in Morton order
    cull,          // construction, per level: each child's edit list
    check,         // construction, adaptive, per level: which bricks reproduce the field within tolerance
    order,         // construction, adaptive: the leaves of every level merged in Morton order
    evaluate,      // construction: the leaf bricks' samples
    apron,         // construction: which apron samples neighbours evaluate, and their copies
    aabb,          // construction: the leaf bricks' boxes
    bvh,           // bottom-level BVHs over the leaf bricks
    tlas,          // the top level over the object instances
    trace,         // primary rays through the bricks
    shade,         // shading and its secondary rays
    reference,     // the device reference tracer (analytic edits)
    eval,          // field evaluation at points
    peaks,         // the bandwidth and FMA kernels of devices --peaks
    mesh,          // a mesh's signed distance grid (kernels/mesh_sdf.cl)
    splice,        // construction, a rebuild after an edit change: kept and rebuilt leaves merged
};

inline constexpr std::array kAllStages = {Stage::edit_bounds, Stage::dependencies, Stage::count, Stage::scan,
                                          Stage::subdivide,   Stage::cull,         Stage::check,    Stage::order,
                                          Stage::evaluate,    Stage::apron,        Stage::aabb,
                                          Stage::bvh,         Stage::tlas,         Stage::trace, Stage::shade,
                                          Stage::reference,   Stage::eval,         Stage::peaks, Stage::mesh, Stage::splice};
// The stages of construction, in the order a build runs them.
inline constexpr std::array kConstructionStages = {Stage::edit_bounds, Stage::dependencies, Stage::count,
                                                   Stage::scan,        Stage::subdivide,    Stage::cull,
                                                   Stage::check,       Stage::order,        Stage::apron,
                                                   Stage::evaluate,    Stage::aabb};

constexpr std::string_view to_string(Stage s) {
    switch (s) {
        case Stage::edit_bounds: return "edit_bounds";
        case Stage::dependencies: return "dependencies";
        case Stage::count: return "count";
        case Stage::scan: return "scan";
        case Stage::subdivide: return "subdivide";
        case Stage::cull: return "cull";
        case Stage::check: return "check";
        case Stage::order: return "order";
        case Stage::evaluate: return "evaluate";
        case Stage::apron: return "apron";
        case Stage::aabb: return "aabb";
        case Stage::bvh: return "bvh";
        case Stage::tlas: return "tlas";
        case Stage::trace: return "trace";
        case Stage::shade: return "shade";
        case Stage::reference: return "reference";
        case Stage::eval: return "eval";
        case Stage::peaks: return "peaks";
        case Stage::mesh: return "mesh";
        case Stage::splice: return "splice";
    }
    return "?";
}

constexpr std::optional<Stage> stage_from_string(std::string_view name) {
    for (Stage s : kAllStages)
        if (to_string(s) == name) return s;
    return std::nullopt;
}

}  // namespace sdfbrick::measure
