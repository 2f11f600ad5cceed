// Exclusive prefix sums of uint32 values on the device, of any length (no fixed cap): a block scan
// per work-group, the block totals scanned recursively, then the block offsets added.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/scheduler.h"
#include "cl/buffer.h"
#include "cl/device.h"
#include "cl/handles.h"
#include "cl/program.h"

namespace sdfbrick::construct {

class Scan {
public:
    explicit Scan(ocl::Device& device);

    // out[i] = in[0] + ... + in[i-1] for i < n; returns the total in[0] + ... + in[n-1], which it reads
    // back (one blocking read). in and out may be the same buffer. Throws InputError when a sum does
    // not fit in 32 bits. Launches go through scheduler under (stage, level).
    std::uint64_t exclusive(const ocl::Buffer<cl_uint>& in, ocl::Buffer<cl_uint>& out, std::size_t n,
                            measure::Scheduler& scheduler, measure::Stage stage, int level);

    // The same over n values, the bit counts of words[0, n - 1) and a 0 last (so out[n - 1] is the
    // total): one launch fewer than counting them first. words and out must be different buffers.
    std::uint64_t exclusive_popcounts(const ocl::Buffer<cl_uint>& words, ocl::Buffer<cl_uint>& out, std::size_t n,
                                      measure::Scheduler& scheduler, measure::Stage stage, int level);

    // Values handled by one work-group.
    std::size_t block_size() const { return local_ * 4; }

private:
    // in: the values, or with popcounts the words whose bit counts are the first n - 1 values.
    std::uint64_t run(const ocl::Buffer<cl_uint>& in, bool popcounts, ocl::Buffer<cl_uint>& out, std::size_t n,
                      measure::Scheduler& scheduler, measure::Stage stage, int level);
    void scan_level(const ocl::Buffer<cl_uint>& in, bool popcounts, ocl::Buffer<cl_uint>& out, std::size_t n,
                    std::size_t depth, measure::Scheduler& scheduler, measure::Stage stage, int level);

    ocl::Device& device_;
    ocl::Program program_;
    ocl::Kernel blocks_, popcount_blocks_, add_;
    std::size_t local_ = 256;
    ocl::Buffer<cl_uint> overflow_;  // [0] the kernels' overflow flag, [1] the last input, [2] the last output
    std::vector<ocl::Buffer<cl_uint>> sums_;     // block totals per recursion depth
    std::vector<ocl::Buffer<cl_uint>> offsets_;  // their exclusive scans
};

}  // namespace sdfbrick::construct
