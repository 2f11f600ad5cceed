#include "construct/scan.h"

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "cl/cl_error.h"
#include "cl/launch.h"
#include "core/errors.h"

namespace sdfbrick::construct {

Scan::Scan(ocl::Device& device)
    : device_(device), program_(ocl::build_program(device, "scan.cl")),
      blocks_(ocl::make_kernel(program_, "scan_blocks")),
      popcount_blocks_(ocl::make_kernel(program_, "scan_popcount_blocks")), add_(ocl::make_kernel(program_, "scan_add")),
      overflow_(device, 3) {
    const std::size_t limit = std::min({ocl::kernel_work_group_limit(device, blocks_.get(), "scan_blocks"),
                                        ocl::kernel_work_group_limit(device, popcount_blocks_.get(), "scan_popcount_blocks"),
                                        ocl::kernel_work_group_limit(device, add_.get(), "scan_add")});
    while (local_ > 1 && local_ > limit) local_ /= 2;  // stays a power of two
}

void Scan::scan_level(const ocl::Buffer<cl_uint>& in, bool popcounts, ocl::Buffer<cl_uint>& out, std::size_t n,
                      std::size_t depth, measure::Scheduler& scheduler, measure::Stage stage, int level) {
    // sums_ and offsets_ were sized by exclusive(): growing them here would move the buffers that
    // the callers up the recursion hold references to (in and out at depth > 0).
    const std::size_t blocks = (n + block_size() - 1) / block_size();
    const auto count = static_cast<cl_uint>(n);
    const ocl::LocalMemory partial{local_ * sizeof(cl_uint)};
    if (popcounts)
        ocl::set_args(popcount_blocks_.get(), in, count - 1, out, count, sums_[depth], overflow_, partial);
    else
        ocl::set_args(blocks_.get(), in, out, count, sums_[depth], overflow_, partial);
    scheduler.launch(stage, level, (popcounts ? popcount_blocks_ : blocks_).get(), blocks * local_, local_);
    if (blocks == 1) return;  // its only block offset is 0
    scan_level(sums_[depth], false, offsets_[depth], blocks, depth + 1, scheduler, stage, level);
    ocl::set_args(add_.get(), out, count, offsets_[depth], overflow_);
    scheduler.launch(stage, level, add_.get(), blocks * local_, local_);
}

std::uint64_t Scan::exclusive(const ocl::Buffer<cl_uint>& in, ocl::Buffer<cl_uint>& out, std::size_t n,
                              measure::Scheduler& scheduler, measure::Stage stage, int level) {
    if (n == 0) return 0;
    if (n > in.size()) throw std::out_of_range("Scan::exclusive: n exceeds a buffer");
    return run(in, false, out, n, scheduler, stage, level);
}

std::uint64_t Scan::exclusive_popcounts(const ocl::Buffer<cl_uint>& words, ocl::Buffer<cl_uint>& out, std::size_t n,
                                        measure::Scheduler& scheduler, measure::Stage stage, int level) {
    if (n == 0) return 0;
    if (n - 1 > words.size()) throw std::out_of_range("Scan::exclusive_popcounts: n - 1 exceeds the words");
    if (words.get() == out.get()) throw std::invalid_argument("Scan::exclusive_popcounts: the words are the output");
    return run(words, true, out, n, scheduler, stage, level);
}

std::uint64_t Scan::run(const ocl::Buffer<cl_uint>& in, bool popcounts, ocl::Buffer<cl_uint>& out, std::size_t n,
                        measure::Scheduler& scheduler, measure::Stage stage, int level) {
    if (n > out.size()) throw std::out_of_range("Scan: n exceeds the output");
    if (n > 0xffffffffu) throw InputError(fmt::format("a prefix sum over {} values exceeds 2^32 values", n));
    // One wait per scan: the overflow flag and the last input are cleared, the last input (before the
    // scan: in may be out; with popcounts it is 0) and the last output copied beside them, on the
    // device; one read brings the three back.
    const std::array<cl_uint, 2> zeros{};
    const cl_command_queue q = device_.queue();
    ocl::check(clEnqueueFillBuffer(q, overflow_.get(), zeros.data(), sizeof(zeros), 0, sizeof(zeros), 0, nullptr, nullptr),
               "clearing the scan's overflow flag");
    if (!popcounts)
        ocl::check(clEnqueueCopyBuffer(q, in.get(), overflow_.get(), (n - 1) * sizeof(cl_uint), sizeof(cl_uint),
                                       sizeof(cl_uint), 0, nullptr, nullptr),
                   "copying the scan's last input");
    // Block-total buffers for every recursion depth, allocated before the recursion starts.
    for (std::size_t m = n, depth = 0;; ++depth) {
        const std::size_t blocks = (m + block_size() - 1) / block_size();
        if (sums_.size() <= depth) {
            sums_.emplace_back(device_, 0);
            offsets_.emplace_back(device_, 0);
        }
        if (sums_[depth].size() < blocks) {
            sums_[depth] = ocl::Buffer<cl_uint>(device_, blocks);
            offsets_[depth] = ocl::Buffer<cl_uint>(device_, blocks);
        }
        if (blocks == 1) break;
        m = blocks;
    }
    scan_level(in, popcounts, out, n, 0, scheduler, stage, level);
    ocl::check(clEnqueueCopyBuffer(q, out.get(), overflow_.get(), (n - 1) * sizeof(cl_uint), 2 * sizeof(cl_uint),
                                   sizeof(cl_uint), 0, nullptr, nullptr),
               "copying the scan's last output");
    std::array<cl_uint, 3> flags{};  // overflow, last input, last output
    overflow_.read_into(flags);
    const std::uint64_t total = std::uint64_t{flags[2]} + flags[1];
    if (flags[0] != 0 || total > 0xffffffffu)
        throw InputError(fmt::format("a prefix sum in stage {} exceeds 2^32 (too many bricks or edit-list entries "
                                     "for one build: use a larger brick size)",
                                     to_string(stage)));
    return total;
}

}  // namespace sdfbrick::construct
