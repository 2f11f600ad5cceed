// Occupancy proxies. OpenCL cannot count resident warps, so these estimate, from what the device and
// the kernel report, how many work-groups fit on one compute unit, how many waves a launch takes and
// (NVIDIA only) the theoretical occupancy of the CUDA occupancy calculator. Every figure whose input
// is unknown stays empty, with a note: nothing is guessed. Pure functions, no OpenCL calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "measure/kernel_attributes.h"

namespace sdfbrick::measure {

// --------------------------------------------------------------------------- CUDA occupancy calculator

// Per-SM limits of one NVIDIA compute capability.
struct CudaSmLimits {
    int cc_major = 0;
    int cc_minor = 0;
    int warp_size = 32;
    int max_threads_per_block = 1024;
    int max_warps_per_sm = 0;
    int max_blocks_per_sm = 0;
    int registers_per_sm = 0;
    int max_registers_per_block = 0;
    int max_registers_per_thread = 255;
    int register_allocation_unit = 256;  // registers, per warp
    int sub_partitions = 4;              // register file partitions (warp schedulers) per SM
    std::uint64_t shared_per_sm = 0;     // bytes, at the largest shared-memory carveout
    std::uint64_t max_shared_per_block = 0;       // bytes a block may use (opt-in maximum)
    std::uint64_t reserved_shared_per_block = 0;  // bytes the driver reserves per block (cc >= 8.0)
    int shared_allocation_unit = 0;               // bytes
};

// The limits of compute capability major.minor (5.0 to 9.0), or nullptr when it is not in the table.
const CudaSmLimits* cuda_sm_limits(int cc_major, int cc_minor);

struct CudaOccupancyInputs {
    int cc_major = 0;
    int cc_minor = 0;
    int threads_per_block = 0;
    int registers_per_thread = 0;
    std::uint64_t shared_bytes_per_block = 0;  // static plus dynamic shared (OpenCL __local) memory
};

// Resident blocks per SM allowed by each limit; kUnlimited where a resource is not used.
struct CudaOccupancy {
    static constexpr int kUnlimited = 1 << 30;
    int blocks_by_warps = 0;
    int blocks_by_registers = 0;
    int blocks_by_shared_memory = 0;
    int blocks_by_sm_limit = 0;          // the architecture's resident-block limit
    int active_blocks_per_sm = 0;        // the minimum of the above; 0: the block cannot run
    int active_warps_per_sm = 0;
    int max_warps_per_sm = 0;
    double occupancy = 0.0;              // active warps / max warps, 0..1
    std::string limited_by;              // "warps", "registers", "shared memory" or "blocks per SM"
};

// The CUDA occupancy calculator's formula (cuda_occupancy.h, cudaOccMaxActiveBlocksPerMultiprocessor)
// at the default state: largest shared-memory carveout, no partitioned global caching, one barrier
// per block. std::nullopt when the compute capability is not in the table or an input is negative
// or threads_per_block is not positive.
std::optional<CudaOccupancy> cuda_occupancy(const CudaOccupancyInputs& inputs);

// --------------------------------------------------------------------------- OpenCL occupancy proxies

struct Occupancy {
    std::size_t group_size = 0;                           // work-items per work-group
    std::uint64_t local_bytes = 0;                        // local memory per work-group
    std::optional<std::uint64_t> groups_per_cu_by_local;  // work-groups per compute unit that fit by local memory
    std::optional<std::uint64_t> resident_groups_per_cu;  // min over every known limit; empty when a needed input is unknown
    std::optional<double> waves;                          // work-groups / (compute units x resident groups)
    std::optional<double> theoretical;                    // 0..1, CUDA occupancy-calculator formula (NVIDIA only)
    std::string limited_by;  // "local memory", "registers", "warps", "blocks per SM", or "unknown"
    std::string note;        // why something is unknown ("; "-separated)
};

// Occupancy of a launch of groups_total work-groups of group_size work-items of a kernel with
// attributes k on device:
//   groups_per_cu_by_local: NVIDIA (compute capability in the table): the calculator's shared-memory
//     limit; AMD (amd_local_mem_per_compute_unit): that / local bytes; other devices with dedicated
//     local memory: CL_DEVICE_LOCAL_MEM_SIZE / local bytes; devices whose local memory is emulated in
//     global memory (PoCL, CPUs): unknown. A kernel without local memory is not limited by it:
//     empty, with the note "no local memory used".
//   resident_groups_per_cu, waves, theoretical, limited_by: NVIDIA with a known compute capability and
//     register count only (the calculator); elsewhere unknown, since OpenCL does not report the
//     register (VGPR/SGPR) use and slot limits that decide them.
Occupancy occupancy(const ocl::DeviceInfo& device, const KernelAttributes& k, std::size_t group_size,
                    std::uint64_t groups_total);

// Unknown values are JSON null.
nlohmann::json to_json(const Occupancy& occupancy);

}  // namespace sdfbrick::measure
