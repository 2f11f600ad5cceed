#include "render/brick_tracer.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include <fmt/format.h>

#include "cl/digest.h"
#include "cl/launch.h"
#include "cl/program.h"
#include "core/errors.h"
#include "core/hash.h"

namespace sdfbrick::render {

SceneBricks build_scene_bricks(construct::BrickBuilder& bricks, const Scene& scene,
                               const construct::BuildSettings& settings, measure::Scheduler& scheduler) {
    SceneBricks out;
    out.settings = settings;
    for (const Geometry& g : scene.geometries) {
        out.builds.push_back(bricks.build(g, settings, scheduler));
        out.bricks += out.builds.back().leaf_count;
        out.build_ms += out.builds.back().device_ms;
    }
    return out;
}

SceneBricks build_scene_bricks(construct::BrickBuilder& bricks, bvh::BvhBuilder& bvh, const Scene& scene,
                               const construct::BuildSettings& settings, measure::Scheduler& scheduler) {
    SceneBricks out = build_scene_bricks(bricks, scene, settings, scheduler);
    prepare_tracing(bvh, scene, out, scheduler);
    return out;
}

void prepare_tracing(bvh::BvhBuilder& bvh, const Scene& scene, SceneBricks& out, measure::Scheduler& scheduler) {
    ocl::Device& device = scheduler.device();
    const construct::BuildSettings& settings = out.settings;
    out.bvh = bvh.build(scene, out.builds, settings, scheduler);

    const construct::BrickLayout layout = settings.layout();
    const std::size_t brick_bytes = layout.brick_bytes();
    if (out.builds.size() != 1) {
        out.combined_pool = std::make_unique<ocl::Buffer<std::uint8_t>>(ocl::pooled, device, out.bricks * brick_bytes);
        out.combined_shifts = std::make_unique<ocl::Buffer<cl_uint>>(ocl::pooled, device, out.bricks);
    }
    std::vector<SdfBrickGeometry> table;
    std::uint64_t first = 0;
    for (std::size_t g = 0; g < out.builds.size(); ++g) {
        const construct::GeometryBuild& b = out.builds[g];
        SdfBrickGeometry e{};
        e.voxel = static_cast<float>(settings.voxel());
        e.inv_voxel = static_cast<float>(1.0 / settings.voxel());
        e.dequant = layout.dequantise_scale(b.band);
        e.root = out.bvh.roots[g];
        e.brick_offset = static_cast<sdf_u32>(first);
        table.push_back(e);
        if (out.combined_pool) out.combined_pool->copy_from(*b.pool, first * brick_bytes);
        if (out.combined_shifts) out.combined_shifts->copy_from(*b.shifts, first);
        first += b.leaf_count;
    }
    SdfBrickGeometry none{};  // the geometry of the top level's stand-in instance when nothing has bricks
    none.voxel = none.inv_voxel = none.dequant = 1.0f;
    none.root = SDF_NO_NODE;
    table.push_back(none);
    out.geometries = std::make_unique<ocl::Buffer<SdfBrickGeometry>>(ocl::pooled, device, std::span<const SdfBrickGeometry>(table));

    double scale = 0.0;
    for (const Object& o : scene.objects) scale = scale == 0.0 ? o.transform.scale : std::min(scale, o.transform.scale);
    out.voxel_world = settings.voxel() * (scale > 0.0 ? scale : 1.0);
}

SdfShading make_shading(const Scene& scene, const SceneBricks& bricks, const TraceSettings& settings) {
    SdfShading s{};
    const glm::dvec3 to_light = -glm::normalize(scene.light.direction);
    const glm::dvec3 colour = scene.light.color * scene.light.intensity;
    for (int a = 0; a < 3; ++a) {
        s.light_dir[a] = static_cast<float>(to_light[a]);
        s.light_color[a] = static_cast<float>(colour[a]);
    }
    Aabb world;
    for (const Object& o : scene.objects) world.grow(bounds(scene, o));
    const double extent = world.empty() ? 1.0 : glm::length(world.extent());
    s.shadow_spread = 0.04f;                               // a light of ~2.3 degrees radius
    s.ao_radius = static_cast<float>(0.03 * extent);       // occlusion scale: 3% of the scene's diagonal
    s.ray_offset = static_cast<float>(2.0 * bricks.voxel_world);
    s.shadow_rays = static_cast<sdf_u32>(settings.shadow_rays);
    s.ao_rays = static_cast<sdf_u32>(settings.ao_rays);
    return s;
}

struct BrickTracer::Kernels {
    ocl::Program trace_program, shade_program;
    ocl::Kernel trace, shade;
    Kernels(ocl::Device& d, const std::string& options)
        : trace_program(ocl::build_program(d, "trace.cl", options)),
          shade_program(ocl::build_program(d, "shade.cl", options)),
          trace(ocl::make_kernel(trace_program, "trace_primary")),
          shade(ocl::make_kernel(shade_program, "shade")) {}
};

// The buffers a trace writes, kept from call to call (grown, never shrunk), with the programs that
// reduce and digest them.
struct BrickTracer::Frame {
    ocl::Buffer<SdfCamera> camera;
    ocl::Buffer<SdfShading> shading;
    ocl::Buffer<cl_float4> hit, colour;
    ocl::Buffer<cl_uint2> aux;
    ocl::Buffer<cl_ulong> totals;
    ocl::Program counts_program;
    ocl::Kernel counts;
    std::optional<ocl::DeviceDigest> digest;
    explicit Frame(ocl::Device& d)
        : camera(d, 1, CL_MEM_READ_ONLY), shading(d, 1, CL_MEM_READ_ONLY), hit(d, 0), colour(d, 0), aux(d, 0),
          totals(d, 3 * kCountGroups), counts_program(ocl::build_program(d, "trace_counts.cl")),
          counts(ocl::make_kernel(counts_program, "trace_counts")) {}
    static constexpr std::size_t kCountGroup = 64, kCountGroups = 256;  // COUNTS_GROUP; work-groups at most
    void reserve(ocl::Device& d, std::size_t pixels, bool shade) {
        if (hit.size() < pixels) hit = ocl::Buffer<cl_float4>(d, pixels);
        if (aux.size() < pixels) aux = ocl::Buffer<cl_uint2>(d, pixels);
        if (shade && colour.size() < pixels) colour = ocl::Buffer<cl_float4>(d, pixels);
    }
};

BrickTracer::BrickTracer(ocl::Device& device) : device_(device) {}
BrickTracer::~BrickTracer() = default;

namespace {

// An image's digest from the tree digests of its hit and aux bytes.
std::string image_digest(std::span<const std::uint64_t> hit_and_aux) {
    return Fnv1a64().add_values(hit_and_aux).hex();
}

}  // namespace

std::string buffer_digest(const RenderBuffer& b) {
    const std::array<std::uint64_t, 2> parts{tree_digest(std::as_bytes(std::span(b.hit))),
                                             tree_digest(std::as_bytes(std::span(b.aux)))};
    return image_digest(parts);
}

// Enqueues the sums of the counters of pixels [first, first + count); returns the work-groups.
std::size_t BrickTracer::enqueue_counts(std::size_t first, std::size_t count) {
    Frame& f = *frame_;
    if (count == 0) return 0;
    const std::size_t groups = std::min(Frame::kCountGroups, (count + Frame::kCountGroup - 1) / Frame::kCountGroup);
    ocl::set_args(f.counts.get(), f.aux, static_cast<cl_uint>(first), static_cast<cl_uint>(count), f.totals);
    ocl::enqueue(device_, f.counts.get(), "trace_counts", groups * Frame::kCountGroup, Frame::kCountGroup);
    return groups;
}

// The sums enqueue_counts made (waits for them); means over `pixels`.
WorkTotals BrickTracer::read_counts(std::size_t groups, std::size_t pixels) {
    WorkTotals w;
    w.pixels = pixels;
    std::vector<cl_ulong> sums(3 * groups);
    frame_->totals.read_into(std::span(sums));
    for (std::size_t g = 0; g < groups; ++g) {
        w.node_visits += sums[3 * g];
        w.brick_steps += sums[3 * g + 1];
        w.capped_rays += sums[3 * g + 2];
    }
    return w;
}

BrickTracer::Kernels& BrickTracer::kernels(const construct::BuildSettings& b, const TraceSettings& t) {
    const std::string options = fmt::format("{} -DMETHOD={} -DNORMALS={}", b.layout().defines(),
                                            static_cast<int>(t.method), static_cast<int>(t.normals)) +
                                ocl::register_cap_option(device_.info(), t.max_registers);
    auto& k = cache_[options];
    if (!k) k = std::make_unique<Kernels>(device_, options);
    return *k;
}

TraceResult BrickTracer::render(const Scene& scene, const SceneBricks& bricks, const SdfCamera& camera,
                                const TraceSettings& settings, measure::Scheduler& scheduler, Rows rows,
                                TraceOutputs outputs) {
    validate_image_size(settings.width, settings.height);
    if (camera.width != static_cast<sdf_u32>(settings.width) || camera.height != static_cast<sdf_u32>(settings.height))
        throw std::invalid_argument("BrickTracer::render: the camera's size differs from the settings'");
    const std::size_t gx = static_cast<std::size_t>(settings.group_x), gy = static_cast<std::size_t>(settings.group_y);
    if (gx * gy == 0 || gx * gy > device_.info().max_work_group_size)
        throw SettingError("group_x", fmt::format("group_x x group_y = {} x {} is not a work-group size {} accepts "
                                                  "(1..{} work-items)", gx, gy, device_.info().name,
                                                  device_.info().max_work_group_size));
    if (rows.end == 0) rows.end = settings.height;
    if (rows.first < 0 || rows.first > rows.end || rows.end > settings.height || rows.first % settings.group_y != 0)
        throw std::invalid_argument("BrickTracer::render: rows out of the image or not on a work-group row");
    Kernels& k = kernels(bricks.settings, settings);
    const std::size_t pixels = static_cast<std::size_t>(settings.width) * settings.height;
    if (!frame_) frame_ = std::make_unique<Frame>(device_);
    Frame& f = *frame_;
    f.reserve(device_, pixels, settings.shade);
    f.camera.write(std::span<const SdfCamera>(&camera, 1));
    const auto band = static_cast<std::size_t>(rows.end - rows.first);
    const std::array<std::size_t, 3> global{(settings.width + gx - 1) / gx * gx, (band + gy - 1) / gy * gy, 1};
    const std::array<std::size_t, 3> offset{0, static_cast<std::size_t>(rows.first), 0};
    const std::array<std::size_t, 3> local{gx, gy, 1};
    const std::size_t first_launch = scheduler.size();
    ocl::set_args(k.trace.get(), f.camera, *bricks.bvh.tlas, *bricks.bvh.instances, *bricks.geometries, *bricks.bvh.nodes,
                  bricks.pool(), bricks.shifts(), f.hit, f.aux);
    scheduler.launch(measure::Stage::trace, -1, k.trace.get(), global, local, 2, offset);
    if (settings.shade) {
        const SdfShading shading = make_shading(scene, bricks, settings);
        f.shading.write(std::span<const SdfShading>(&shading, 1));
        ocl::set_args(k.shade.get(), f.camera, *bricks.bvh.tlas, *bricks.bvh.instances, *bricks.geometries,
                      *bricks.bvh.nodes, bricks.pool(), bricks.shifts(), f.shading, f.hit, f.colour);
        scheduler.launch(measure::Stage::shade, -1, k.shade.get(), global, local, 2, offset);
    }
    TraceResult out;
    const std::size_t first = static_cast<std::size_t>(rows.first) * settings.width, count = band * settings.width;
    // The counters and the digest are enqueued together: the first read waits for both.
    const std::size_t groups = enqueue_counts(first, count);
    if (outputs.digest) {
        if (count != pixels) throw std::invalid_argument("BrickTracer::render: a digest covers whole images, not bands of rows");
        if (!f.digest) f.digest.emplace(device_);
        f.digest->enqueue(f.hit.get(), {pixels * sizeof(cl_float4), 1, 0, 1});
        f.digest->enqueue(f.aux.get(), {pixels * sizeof(cl_uint2), 1, 0, 1});
    }
    out.work = read_counts(groups, pixels);
    if (outputs.digest) out.digest = image_digest(f.digest->read_all());
    scheduler.resolve();
    out.trace_ms = scheduler.stage_ms(measure::Stage::trace, -1, first_launch);
    out.shade_ms = scheduler.stage_ms(measure::Stage::shade, -1, first_launch);
    if (outputs.image) {
        out.buffer = RenderBuffer(settings.width, settings.height);
        f.hit.read_into(std::span(out.buffer.hit).subspan(first, count), first);
        f.aux.read_into(std::span(out.buffer.aux).subspan(first, count), first);
        if (settings.shade) {
            std::vector<cl_float4> c(count);
            f.colour.read_into(std::span(c), first);
            out.colour = Image(settings.width, settings.height, 3);
            for (std::size_t i = 0; i < count; ++i)
                for (int ch = 0; ch < 3; ++ch) out.colour.pixels[3 * (first + i) + ch] = c[i].s[ch];
        }
    }
    out.warnings = trace_warnings(scene, bricks, out.work.capped_rays, pixels, settings.method);
    return out;
}

}  // namespace sdfbrick::render
