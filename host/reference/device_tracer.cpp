#include "reference/device_tracer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "cl/buffer.h"
#include "cl/launch.h"
#include "measure/scheduler.h"
#include "core/errors.h"
#include "reference/edit_bvh.h"
#include "construct/mesh_pool.h"
#include "scene/to_device.h"

namespace sdfbrick::reference {

namespace {

// Mirror of RefGeometry in kernels/reference_trace.cl (same fields, same order).
struct RefGeometry {
    float clip_lo[3];
    float clip_hi[3];
    float clamp_c;
    float min_step;
    float normal_h;
    std::uint32_t edit_offset;
    std::uint32_t edit_count;
    std::uint32_t node_offset;
    std::uint32_t node_count;
    std::uint32_t isect_offset;
    std::uint32_t isect_count;
    std::uint32_t pad;
};
static_assert(sizeof(RefGeometry) == 64, "RefGeometry must match kernels/reference_trace.cl");
static_assert(sizeof(SdfBounds) == 24 && sizeof(SdfBvhNode) == 64 && sizeof(SdfInstance) == 64 &&
              sizeof(SdfCamera) == 56 && sizeof(SdfEdit) == 64);

// Work-group of the launch: 8 x 8 pixels (the global size is padded; the kernel guards x, y).
constexpr std::size_t kTile = 8;

double max_abs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

float round_up_float(double v) {
    float f = static_cast<float>(v);
    if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

// The edit's rough size, as sdf_edit_reach (sdf_build.h) measures it: how large the numbers in
// its evaluation get, beside the point's coordinates.
double reach(const Edit& e) {
    const double p = std::max({std::abs(e.params[0]), std::abs(e.params[1]), std::abs(e.params[2]), std::abs(e.params[3])});
    return max_abs(e.transform.translation) + e.transform.scale * p;
}

bool finite(const Aabb& b) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return false;
    return true;
}

void check_settings(const ReferenceSettings& s) {
    if (s.max_steps < 1 || s.max_steps > (1 << 24))
        throw InputError(fmt::format("reference max_steps must lie in [1, 2^24], got {}", s.max_steps));
    const auto check = [](double v, const char* name, bool zero_ok) {
        if (!std::isfinite(v) || v < 0.0 || (!zero_ok && v == 0.0))
            throw InputError(fmt::format("reference {} must be {} and finite, got {}", name, zero_ok ? ">= 0" : "> 0", v));
    };
    check(s.clamp_guard, "clamp_guard", true);
    check(s.clamp_extent, "clamp_extent", true);
    check(s.min_step_rel, "min_step_rel", false);
    check(s.normal_step_rel, "normal_step_rel", false);
    if (s.min_step_rel > 0.01 || s.normal_step_rel > 0.01)
        throw InputError("reference min_step_rel and normal_step_rel must be <= 0.01 (they are relative to the geometry's size)");
}

// One geometry as the kernel reads it.
struct PreparedGeometry {
    ReferenceGeometryInfo info;
    RefGeometry record{};
    std::vector<SdfEdit> edits;
    std::vector<SdfBounds> boxes;
    std::vector<std::uint32_t> isect;
    EditBvh bvh;
};

PreparedGeometry prepare(const Geometry& g, const ReferenceSettings& s, bool with_boxes) {
    PreparedGeometry out;
    ReferenceGeometryInfo& info = out.info;
    info.name = g.name;
    info.edits = g.edits.size();
    if (g.edits.size() > SDF_MAX_EDITS)
        throw InputError(fmt::format("geometry \"{}\" has {} edits; the reference tracer takes at most {}", g.name,
                                     g.edits.size(), SDF_MAX_EDITS));
    const Aabb solid = bounds(g);
    RefGeometry& r = out.record;
    for (int i = 0; i < 3; ++i) {
        r.clip_lo[i] = 1.0f;
        r.clip_hi[i] = -1.0f;
    }
    if (solid.empty()) return out;  // no add edit: no surface, nothing to trace
    if (!finite(solid))
        throw InputError(fmt::format("geometry \"{}\": its bounds are not finite", g.name));
    info.traceable = true;
    for (const Edit& e : g.edits) info.k_max = std::max(info.k_max, static_cast<double>(static_cast<float>(e.blend)));
    const glm::dvec3 ext = solid.extent();
    const double extent = std::max({ext.x, ext.y, ext.z});
    const double mb = std::max(max_abs(solid.lo), max_abs(solid.hi));
    double c = s.clamp_guard * info.k_max + s.clamp_extent * extent;
    c = std::max(c, 0x1p-12 * (1.0 + mb));
    r.clamp_c = round_up_float(c);
    info.clamp_c = r.clamp_c;
    // The size of the coordinates (float noise scales with it): steps relative to it do not depend on C.
    info.magnitude = mb;
    r.min_step = static_cast<float>(s.min_step_rel * (1.0 + info.magnitude));
    r.normal_h = static_cast<float>(s.normal_step_rel * (1.0 + info.magnitude));
    // Every evaluated point lies within C + k_max of bounds(g) (a step past the clip box is <= C).
    const double reach_of_points = mb + info.clamp_c + info.k_max;
    info.min_step = r.min_step;
    info.normal_step = r.normal_h;

    Aabb clip;
    if (with_boxes) out.boxes.reserve(g.edits.size());
    for (std::size_t i = 0; i < g.edits.size(); ++i) {
        const Edit& e = g.edits[i];
        const double k = static_cast<float>(e.blend);
        const double margin = 0x1p-14 * (reach_of_points + reach(e));
        if (e.op == Op::Add) {
            const Aabb level = level_bounds(e, k + margin);
            const SdfBounds f = to_float_box(level);
            clip.grow(Aabb{glm::dvec3(f.lo[0], f.lo[1], f.lo[2]), glm::dvec3(f.hi[0], f.hi[1], f.hi[2])});
        }
        if (!with_boxes) continue;
        const Aabb box = level_bounds(e, static_cast<double>(r.clamp_c) + k + margin);
        if (!finite(box)) throw InputError(fmt::format("geometry \"{}\": edit {} has non-finite bounds", g.name, i));
        out.boxes.push_back(to_float_box(box));
        if (e.op == Op::Intersect) out.isect.push_back(static_cast<std::uint32_t>(i));
    }
    for (int i = 0; i < 3; ++i) {
        r.clip_lo[i] = static_cast<float>(clip.lo[i]);  // already floats
        r.clip_hi[i] = static_cast<float>(clip.hi[i]);
    }
    if (with_boxes) {
        out.bvh = build_edit_bvh(out.boxes);
        if (out.bvh.depth > 60)
            throw std::logic_error(fmt::format("edit BVH of \"{}\" is {} deep; the kernel's stack holds 64", g.name,
                                               out.bvh.depth));
        out.edits = to_device(g);
    }
    info.bvh_nodes = out.bvh.nodes.size();
    info.bvh_depth = out.bvh.depth;
    return out;
}

template <class T>
std::uint64_t bytes_of(const std::vector<T>& v) {
    return static_cast<std::uint64_t>(v.size()) * sizeof(T);
}

void check_objects(const Scene& scene) {
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        if (o.geometry >= scene.geometries.size())
            throw InputError(fmt::format("object {} (\"{}\") names geometry {}, but the scene has {}", i, o.name,
                                         o.geometry, scene.geometries.size()));
        const double sc = o.transform.scale;
        if (!std::isfinite(sc) || sc <= 0.0 || !std::isfinite(max_abs(o.transform.translation)))
            throw InputError(fmt::format("object {} (\"{}\"): its transform must be finite with scale > 0", i, o.name));
    }
}

// Every geometry's record, edits, boxes, BVH and intersect list, concatenated as the kernel reads them.
struct PackedScene {
    std::vector<RefGeometry> records;
    std::vector<SdfEdit> edits;
    std::vector<SdfBounds> boxes;
    std::vector<SdfBvhNode> nodes;
    std::vector<std::uint32_t> isect;
    std::vector<ReferenceGeometryInfo> infos;
};

PackedScene pack_geometries(const Scene& scene, const ReferenceSettings& settings) {
    PackedScene out;
    for (const Geometry& g : scene.geometries) {
        PreparedGeometry p = prepare(g, settings, true);
        RefGeometry r = p.record;
        r.edit_offset = static_cast<std::uint32_t>(out.edits.size());
        r.edit_count = static_cast<std::uint32_t>(p.info.traceable ? p.edits.size() : 0);
        r.node_offset = static_cast<std::uint32_t>(out.nodes.size());
        r.node_count = static_cast<std::uint32_t>(p.info.traceable ? p.bvh.nodes.size() : 0);
        r.isect_offset = static_cast<std::uint32_t>(out.isect.size());
        r.isect_count = static_cast<std::uint32_t>(p.info.traceable ? p.isect.size() : 0);
        if (p.info.traceable) {
            out.edits.insert(out.edits.end(), p.edits.begin(), p.edits.end());
            out.boxes.insert(out.boxes.end(), p.boxes.begin(), p.boxes.end());
            out.nodes.insert(out.nodes.end(), p.bvh.nodes.begin(), p.bvh.nodes.end());
            out.isect.insert(out.isect.end(), p.isect.begin(), p.isect.end());
        }
        out.records.push_back(r);
        out.infos.push_back(std::move(p.info));
        if (out.edits.size() > std::numeric_limits<std::uint32_t>::max() / 2)
            throw InputError("the scene's geometries hold too many edits for one reference render");
    }
    return out;
}

// Sums the per-pixel counters into result.
void add_counters(ReferenceResult& result, const std::vector<cl_uint2>& counts) {
    for (std::size_t i = 0; i < result.image.pixels(); ++i) {
        result.march_steps += result.image.aux[i].s[0];
        result.unconverged_pixels += (result.image.aux[i].s[1] & kRefFlagUnconverged) != 0;
        result.hit_pixels += result.image.is_hit(i);
        result.overflow_points += counts[i].s[0];
        result.fallback_points += counts[i].s[1];
    }
}

}  // namespace

ReferenceGeometryInfo reference_geometry_info(const Geometry& g, const ReferenceSettings& settings) {
    check_settings(settings);
    return prepare(g, settings, false).info;
}

ReferenceTracer::ReferenceTracer(ocl::Device& device)
    : device_(device), program_(ocl::build_program(device, "reference_trace.cl")),
      kernel_(ocl::make_kernel(program_, "reference_trace")) {}

ReferenceResult ReferenceTracer::render(const Scene& scene, const SdfCamera& camera, const ReferenceSettings& settings) {
    const auto start = std::chrono::steady_clock::now();
    check_settings(settings);
    validate_image_size(static_cast<int>(std::min<sdf_u32>(camera.width, 1u << 30)),
                        static_cast<int>(std::min<sdf_u32>(camera.height, 1u << 30)));
    check_objects(scene);
    ReferenceResult result;
    const int width = static_cast<int>(camera.width), height = static_cast<int>(camera.height);
    result.image = RenderBuffer(width, height);
    PackedScene packed = pack_geometries(scene, settings);
    result.geometries = std::move(packed.infos);
    const std::vector<SdfInstance> instances = make_instances(scene);

    // Device buffers (a zero-element Buffer is valid: the kernel then reads none of it).
    const std::size_t pixels = result.image.pixels();
    const std::array<SdfCamera, 1> cam{camera};
    ocl::Buffer<SdfCamera> camera_buf(device_, std::span<const SdfCamera>(cam), CL_MEM_READ_ONLY);
    ocl::Buffer<SdfInstance> instance_buf(device_, std::span<const SdfInstance>(instances), CL_MEM_READ_ONLY);
    ocl::Buffer<RefGeometry> geometry_buf(device_, std::span<const RefGeometry>(packed.records), CL_MEM_READ_ONLY);
    ocl::Buffer<SdfEdit> edit_buf(device_, std::span<const SdfEdit>(packed.edits), CL_MEM_READ_ONLY);
    measure::Scheduler conversion(device_);  // mesh grids not converted yet (once per loaded scene)
    const std::vector<float> meshes = construct::mesh_pool(scene.geometries, device_, conversion);
    ocl::Buffer<float> mesh_buf(device_, std::span<const float>(meshes), CL_MEM_READ_ONLY);
    ocl::Buffer<SdfBounds> box_buf(device_, std::span<const SdfBounds>(packed.boxes), CL_MEM_READ_ONLY);
    ocl::Buffer<SdfBvhNode> node_buf(device_, std::span<const SdfBvhNode>(packed.nodes), CL_MEM_READ_ONLY);
    ocl::Buffer<std::uint32_t> isect_buf(device_, std::span<const std::uint32_t>(packed.isect), CL_MEM_READ_ONLY);
    ocl::Buffer<cl_float4> hit_buf(device_, pixels, CL_MEM_WRITE_ONLY);
    ocl::Buffer<cl_uint2> aux_buf(device_, pixels, CL_MEM_WRITE_ONLY);
    ocl::Buffer<cl_uint2> count_buf(device_, pixels, CL_MEM_WRITE_ONLY);
    result.memory = {{"camera", sizeof(SdfCamera)},
                     {"instances", bytes_of(instances)},
                     {"geometries", bytes_of(packed.records)},
                     {"edits", bytes_of(packed.edits)},
                     {"edit_boxes", bytes_of(packed.boxes)},
                     {"edit_bvh", bytes_of(packed.nodes)},
                     {"intersect_lists", bytes_of(packed.isect)},
                     {"hit", static_cast<std::uint64_t>(pixels) * sizeof(cl_float4)},
                     {"aux", static_cast<std::uint64_t>(pixels) * sizeof(cl_uint2)},
                     {"counters", static_cast<std::uint64_t>(pixels) * sizeof(cl_uint2)}};

    if (meshes.size() > 1) result.memory["mesh grids"] = bytes_of(meshes);  // one float: no mesh
    ocl::set_args(kernel_.get(), camera_buf, instance_buf, static_cast<cl_uint>(instances.size()), geometry_buf,
                  edit_buf, mesh_buf, box_buf, node_buf, isect_buf, static_cast<cl_uint>(settings.max_steps),
                  static_cast<cl_uint>(settings.exact_field ? 1 : 0), hit_buf, aux_buf, count_buf);
    const std::array<std::size_t, 3> global{(static_cast<std::size_t>(width) + kTile - 1) / kTile * kTile,
                                            (static_cast<std::size_t>(height) + kTile - 1) / kTile * kTile, 1};
    measure::Scheduler scheduler(device_);
    scheduler.launch(measure::Stage::reference, -1, kernel_.get(), global, std::array<std::size_t, 3>{kTile, kTile, 1}, 2);
    const measure::Launch& launch = scheduler.resolve().front();
    result.device_ms = launch.device_ms;
    result.queue_ms = launch.queue_ms;
    hit_buf.read_into(result.image.hit);
    aux_buf.read_into(result.image.aux);
    std::vector<cl_uint2> counts(pixels);
    count_buf.read_into(counts);
    add_counters(result, counts);
    result.host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace sdfbrick::reference
