#include "construct/build_parts.h"

#include <algorithm>

#include "cl/launch.h"
#include "measure/occupancy.h"

namespace sdfbrick::construct::detail {

bool fills_few_waves(const ocl::DeviceInfo& device, const measure::KernelAttributes& k, std::size_t group,
                     std::uint64_t groups) {
    if (device.type != "gpu") return false;
    const measure::Occupancy o = measure::occupancy(device, k, group, groups);
    return o.waves && *o.waves <= 2.0;
}

bool fills_few_waves(const ocl::Device& device, cl_kernel kernel, std::uint64_t unset_local_bytes, std::size_t group,
                     std::uint64_t groups) {
    if (device.info().type != "gpu") return false;
    measure::KernelAttributes k = measure::kernel_attributes(device, kernel);
    k.local_mem_bytes += unset_local_bytes;
    return fills_few_waves(device.info(), k, group, groups);
}

namespace {
// brick_evaluate's build options but PER_ITEM, which follows the work-group (evaluate_samples), and
// whether its work-items' skip test reads records in local memory.
struct EvaluationOptions {
    std::string defines;
    bool records = false;
};
EvaluationOptions evaluation_options(const BuildInputs& in, const ocl::Buffer<cl_uint>* owned) {
    const auto lanes = static_cast<std::size_t>(in.settings.lanes(in.device.info()));
    // The primitives and operations the edits use: the kernel compiles the folds of these alone (a
    // number past the masks' bits, never in a validated scene, keeps every fold). radial: a sphere
    // or capsule add or subtract among them; add_or_subtract: an add or subtract of any primitive.
    cl_uint prims = 0, ops = 0;
    bool radial = false, add_or_subtract = false;
    for (const SdfEdit& e : in.edits_host) {
        prims |= e.primitive < 32 ? 1u << e.primitive : ~0u;
        ops |= e.op < 32 ? 1u << e.op : ~0u;
        const bool skippable = e.op == SDF_OP_ADD || e.op == SDF_OP_SUBTRACT;
        add_or_subtract = add_or_subtract || skippable;
        radial = radial || ((e.primitive == SDF_PRIM_SPHERE || e.primitive == SDF_PRIM_CAPSULE) && skippable);
    }
    // The skip of far edits costs registers, so only a geometry with edits it can skip has it: sphere
    // or capsule adds or subtracts, or on one lane (GPUs) adds or subtracts of any primitive (the
    // work-item's test).
    const bool skip_far = in.settings.skip_far && (radial || (add_or_subtract && lanes == 1));
    // The work-item's skip test reads records in local memory with CPU lanes (BuildSettings::skip_records).
    const bool records = skip_far && radial && BuildSettings::skip_records(static_cast<int>(lanes));
    return {fmt::format("{} -DSDF_LANES={} -DAPRON_SHARED={} -DSKIP_FAR={} -DSKIP_RECORDS={} -DEVAL_PRIMS={}u "
                        "-DEVAL_OPS={}u",
                        in.settings.layout().defines(), lanes, owned ? 1 : 0, skip_far ? 1 : 0, records ? 1 : 0,
                        prims, ops) +
                ocl::register_cap_option(in.device.info(), in.settings.eval_registers),
            records};
}
}  // namespace

// The samples of `count` bricks (their records and lists) into pool, as brick_evaluate stores them;
// owned: per brick, the regions it evaluates (null: all). Launched as stage at level.
void evaluate_samples(BuildInputs& in, const ocl::Buffer<SdfBrick>& bricks, const ocl::Buffer<cl_uint>& lists,
                      std::uint64_t count, const ocl::Buffer<cl_uint>* owned, ocl::Buffer<std::uint8_t>& pool,
                      measure::Stage stage, int level) {
    if (count == 0) return;
    const BrickLayout layout = in.settings.layout();
    const auto lanes = static_cast<std::size_t>(in.settings.lanes(in.device.info()));
    const std::size_t most = (layout.samples_per_brick() + lanes - 1) / lanes;  // values a brick
    const EvaluationOptions options = evaluation_options(in, owned);
    const ocl::Buffer<float> level_clamp(ocl::pooled, in.device, std::span<const float>(in.plan.level_clamp));
    const std::size_t record_count = options.records ? 2 * static_cast<std::size_t>(in.settings.chunk) : 1;  // float4 each
    const auto kernel_for = [&](std::size_t group) {  // with its arguments set
        const ocl::Program program = ocl::build_program(
            in.device, "brick_evaluate.cl", fmt::format("{} -DPER_ITEM={}", options.defines, (most + group - 1) / group));
        ocl::Kernel kernel = ocl::make_kernel(program, "brick_evaluate");
        ocl::set_args(kernel.get(), in.prepared_edits, in.meshes, lists, bricks, owned ? *owned : in.empty_uints,
                      in.origin.x, in.origin.y, in.origin.z, static_cast<float>(in.plan.voxel), level_clamp,
                      in.plan.band, layout.quantise_scale(in.plan.band), static_cast<cl_uint>(in.plan.finest()),
                      in.plan.log2b, pool,
                      ocl::LocalMemory{static_cast<std::size_t>(in.settings.chunk) * sizeof(SdfPrepared)},
                      ocl::LocalMemory{record_count * sizeof(cl_float4)}, static_cast<cl_uint>(in.settings.chunk));
        return kernel;
    };
    std::size_t group = std::min<std::size_t>(in.settings.eval_group, most);
    ocl::Kernel kernel = kernel_for(group);
    // The check's candidates at a level with few of them: twice the work-items a brick (fills_few_waves).
    if (stage == measure::Stage::check && group * 2 <= most &&
        group * 2 <= ocl::kernel_work_group_limit(in.device, kernel.get(), "brick_evaluate") &&
        fills_few_waves(in.device, kernel.get(), 0, group, count)) {
        group *= 2;
        kernel = kernel_for(group);
    }
    in.scheduler.launch(stage, level, kernel.get(), count * group, group);
}

// The pool (every leaf's samples) and the leaves' boxes.
void LeafEvaluation::evaluate(const ocl::Buffer<SdfBrick>& leaves, const ocl::Buffer<cl_uint>& lists,
                              std::uint64_t leaf_count, Levels::Bytes& bytes, const AdaptiveLeaves* adaptive) {
    const BrickLayout layout = in_.settings.layout();
    in_.out.pool = std::make_unique<ocl::Buffer<std::uint8_t>>(allocate<std::uint8_t>(
        in_.device, leaf_count * layout.brick_bytes(), fmt::format("the brick pool ({} bricks)", leaf_count)));
    in_.out.aabbs =
        std::make_unique<ocl::Buffer<SdfBounds>>(allocate<SdfBounds>(in_.device, leaf_count, "the brick AABBs"));
    in_.out.shifts =
        std::make_unique<ocl::Buffer<cl_uint>>(allocate<cl_uint>(in_.device, leaf_count, "the brick shifts"));
    if (leaf_count == 0) return;
    const int leaf_level = in_.plan.domain.levels - 1;
    const auto finest = static_cast<cl_uint>(in_.plan.finest());
    const ApronSharing apron = share_aprons(leaves, leaf_count, bytes);
    evaluate_samples(in_, adaptive ? adaptive->evaluated() : leaves, lists, leaf_count, owned_.get(), *in_.out.pool,
                     measure::Stage::evaluate, leaf_level);
    if (adaptive) adaptive->put_samples(*in_.out.pool);
    if (apron.copy) {
        ocl::set_args(apron.copy->get(), *owned_, apron.neighbours, *in_.out.pool);
        in_.scheduler.launch(measure::Stage::apron, leaf_level, apron.copy->get(), leaf_count * kGroup1d, kGroup1d);
    }
    ocl::set_args(in_.programs.aabb_k.get(), leaves, static_cast<cl_uint>(leaf_count), in_.origin.x, in_.origin.y,
                  in_.origin.z, in_.out.leaf_size, finest, in_.plan.log2b, *in_.out.aabbs, *in_.out.shifts);
    in_.scheduler.launch(measure::Stage::aabb, leaf_level, in_.programs.aabb_k.get(), round_up(leaf_count, kGroup1d),
                         kGroup1d);
}

// With sharing on, which regions of its samples each leaf evaluates (owned_): its interior and the
// apron regions whose neighbour of the same level is not a leaf (brick_keys, brick_owned). Returns
// the neighbours and the copy kernel that brick_apron.cl runs after the evaluation. With sharing off
// every leaf evaluates all its samples, and there is nothing to find: owned_ stays empty.
LeafEvaluation::ApronSharing LeafEvaluation::share_aprons(const ocl::Buffer<SdfBrick>& leaves, std::uint64_t leaf_count,
                                                          Levels::Bytes& bytes) {
    const int share_edits = in_.settings.apron_share_edits;
    ApronSharing a{ocl::Buffer<cl_uint>(ocl::pooled, in_.device, 0), std::nullopt, std::nullopt};
    if (share_edits <= 0) return a;
    owned_ = std::make_unique<ocl::Buffer<cl_uint>>(allocate<cl_uint>(in_.device, leaf_count, "the apron masks"));
    a.neighbours = allocate<cl_uint>(in_.device, leaf_count * 27, "the apron neighbours");
    ocl::Buffer<cl_ulong> keys = allocate<cl_ulong>(in_.device, leaf_count, "the leaf keys");
    bytes.scratch = std::max<std::uint64_t>(bytes.scratch, owned_->bytes() + a.neighbours.bytes() + keys.bytes());
    a.program.emplace(ocl::build_program(in_.device, "brick_apron.cl", in_.settings.layout().defines()));
    const ocl::Kernel owned = ocl::make_kernel(*a.program, "brick_owned");
    const cl_kernel keys_k = in_.programs.keys_k.get();
    const auto count = static_cast<cl_uint>(leaf_count), finest = static_cast<cl_uint>(in_.plan.finest());
    const int leaf_level = in_.plan.domain.levels - 1;
    ocl::set_args(keys_k, leaves, count, finest, in_.plan.log2b, keys);
    in_.scheduler.launch(measure::Stage::apron, leaf_level, keys_k, round_up(leaf_count, kGroup1d), kGroup1d);
    ocl::set_args(owned.get(), leaves, keys, count, finest, in_.plan.log2b, static_cast<cl_uint>(share_edits), *owned_,
                  a.neighbours);
    in_.scheduler.launch(measure::Stage::apron, leaf_level, owned.get(), round_up(leaf_count, kGroup1d), kGroup1d);
    a.copy.emplace(ocl::make_kernel(*a.program, "brick_apron"));
    return a;
}

}  // namespace sdfbrick::construct::detail
