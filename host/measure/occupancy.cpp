#include "measure/occupancy.h"

#include <algorithm>
#include <array>
#include <climits>
#include <vector>

#include <fmt/format.h>

namespace sdfbrick::measure {

namespace {

constexpr std::uint64_t KiB = 1024;

// Sources:
//  - CUDA C++ Programming Guide, "Technical Specifications per Compute Capability" (CUDA 12.x): resident
//    warps and blocks per SM, 64 K registers per SM, registers per block (32 K on 5.3 and 6.2), 255
//    registers per thread, shared memory per SM and the opt-in maximum per block, the 1 KB reserved
//    per block from 8.0 ("the maximum amount of shared memory per thread block is smaller than the
//    maximum shared memory partition available per SM; the 1 KB not made available to a block is
//    reserved for system use").
//  - cuda_occupancy.h (CUDA 12.6): register allocation unit 256 per warp, shared-memory allocation
//    unit 256 bytes (cc 5-7) / 128 bytes (cc 8-9), 4 register sub-partitions per SM (2 on 6.0), the
//    same resident-block limits.
// cuda_occupancy.h checks 256 registers per thread for cc >= 7; the Programming Guide's hardware limit
// (and ptxas's) is 255, used here for every cc.
constexpr std::array<CudaSmLimits, 14> kSmLimits = {{
    // cc, warp size, threads/block, warps/SM, blocks/SM, registers/SM, registers/block, registers/thread,
    // register unit, sub-partitions, shared/SM, shared/block (opt-in), reserved/block, shared unit
    {5, 0, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 64 * KiB, 48 * KiB, 0, 256},
    {5, 2, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 96 * KiB, 48 * KiB, 0, 256},
    {5, 3, 32, 1024, 64, 32, 65536, 32768, 255, 256, 4, 64 * KiB, 48 * KiB, 0, 256},
    {6, 0, 32, 1024, 64, 32, 65536, 65536, 255, 256, 2, 64 * KiB, 48 * KiB, 0, 256},
    {6, 1, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 96 * KiB, 48 * KiB, 0, 256},
    {6, 2, 32, 1024, 64, 32, 65536, 32768, 255, 256, 4, 64 * KiB, 48 * KiB, 0, 256},
    {7, 0, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 96 * KiB, 96 * KiB, 0, 256},
    {7, 2, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 96 * KiB, 96 * KiB, 0, 256},
    {7, 5, 32, 1024, 32, 16, 65536, 65536, 255, 256, 4, 64 * KiB, 64 * KiB, 0, 256},
    {8, 0, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 164 * KiB, 163 * KiB, 1 * KiB, 128},
    {8, 6, 32, 1024, 48, 16, 65536, 65536, 255, 256, 4, 100 * KiB, 99 * KiB, 1 * KiB, 128},
    {8, 7, 32, 1024, 48, 16, 65536, 65536, 255, 256, 4, 164 * KiB, 163 * KiB, 1 * KiB, 128},
    {8, 9, 32, 1024, 48, 24, 65536, 65536, 255, 256, 4, 100 * KiB, 99 * KiB, 1 * KiB, 128},
    {9, 0, 32, 1024, 64, 32, 65536, 65536, 255, 256, 4, 228 * KiB, 227 * KiB, 1 * KiB, 128},
}};

std::int64_t round_up(std::int64_t x, std::int64_t unit) { return (x + unit - 1) / unit * unit; }

// cudaOccMaxBlocksPerSMRegsLimit without partitioned global caching.
int blocks_by_registers(const CudaSmLimits& sm, int registers_per_thread, int warps_per_block) {
    const std::int64_t per_warp = round_up(std::int64_t{registers_per_thread} * sm.warp_size, sm.register_allocation_unit);
    const std::int64_t per_block = per_warp * warps_per_block;
    // The hardware check assumes the block's warps are spread over every sub-partition.
    const std::int64_t assumed_per_block = per_warp * round_up(warps_per_block, sm.sub_partitions);
    if (registers_per_thread > sm.max_registers_per_thread || per_block > sm.max_registers_per_block ||
        assumed_per_block > sm.max_registers_per_block) {
        return 0;
    }
    if (per_warp == 0) {
        return CudaOccupancy::kUnlimited;
    }
    const std::int64_t warps_per_sub_partition = (sm.registers_per_sm / sm.sub_partitions) / per_warp;
    return static_cast<int>(warps_per_sub_partition * sm.sub_partitions / warps_per_block);
}

// cudaOccMaxBlocksPerSMSmemLimit at the default carveout, which is the SM's largest shared memory.
int blocks_by_shared_memory(const CudaSmLimits& sm, std::uint64_t shared_bytes) {
    const std::uint64_t allocated = static_cast<std::uint64_t>(
        round_up(static_cast<std::int64_t>(shared_bytes + sm.reserved_shared_per_block), sm.shared_allocation_unit));
    if (allocated > sm.max_shared_per_block + sm.reserved_shared_per_block) {
        return 0;
    }
    if (allocated == 0) {
        return CudaOccupancy::kUnlimited;
    }
    return static_cast<int>(std::min<std::uint64_t>(sm.shared_per_sm / allocated, CudaOccupancy::kUnlimited));
}

}  // namespace

const CudaSmLimits* cuda_sm_limits(int cc_major, int cc_minor) {
    const auto it = std::find_if(kSmLimits.begin(), kSmLimits.end(), [&](const CudaSmLimits& sm) {
        return sm.cc_major == cc_major && sm.cc_minor == cc_minor;
    });
    return it != kSmLimits.end() ? &*it : nullptr;
}

std::optional<CudaOccupancy> cuda_occupancy(const CudaOccupancyInputs& in) {
    const CudaSmLimits* sm = cuda_sm_limits(in.cc_major, in.cc_minor);
    if (sm == nullptr || in.threads_per_block <= 0 || in.registers_per_thread < 0 ||
        in.shared_bytes_per_block > (std::uint64_t{1} << 40)) {
        return std::nullopt;
    }
    const int warps = (in.threads_per_block + sm->warp_size - 1) / sm->warp_size;  // a partial warp takes a whole one
    CudaOccupancy r;
    r.max_warps_per_sm = sm->max_warps_per_sm;
    r.blocks_by_warps = in.threads_per_block > sm->max_threads_per_block ? 0 : sm->max_warps_per_sm / warps;
    r.blocks_by_registers = blocks_by_registers(*sm, in.registers_per_thread, warps);
    if (sm->cc_major == 6 && sm->cc_minor == 0 && r.blocks_by_registers > 0 &&
        blocks_by_registers(*cuda_sm_limits(6, 1), in.registers_per_thread, warps) == 0) {
        r.blocks_by_registers = 0;  // the calculator lets no block run on GP100 that cannot run on GP10x
    }
    r.blocks_by_shared_memory = blocks_by_shared_memory(*sm, in.shared_bytes_per_block);
    r.blocks_by_sm_limit = sm->max_blocks_per_sm;
    r.active_blocks_per_sm =
        std::min({r.blocks_by_warps, r.blocks_by_registers, r.blocks_by_shared_memory, r.blocks_by_sm_limit});
    // On a tie, the first in the calculator's order of limiting factors.
    r.limited_by = r.active_blocks_per_sm == r.blocks_by_warps       ? "warps"
                   : r.active_blocks_per_sm == r.blocks_by_registers ? "registers"
                   : r.active_blocks_per_sm == r.blocks_by_shared_memory ? "shared memory"
                                                                        : "blocks per SM";
    r.active_warps_per_sm = r.active_blocks_per_sm * warps;
    r.occupancy = static_cast<double>(r.active_warps_per_sm) / sm->max_warps_per_sm;
    return r;
}

namespace {
// The work-groups a compute unit holds by their local memory (none when it uses none or when the
// device emulates local memory in global memory).
std::optional<std::uint64_t> groups_by_local(const ocl::DeviceInfo& device, const CudaSmLimits* sm,
                                             std::uint64_t local_bytes, std::vector<std::string>& notes) {
    if (local_bytes == 0) {
        notes.push_back("no local memory used");
        return std::nullopt;
    }
    if (sm != nullptr) return static_cast<std::uint64_t>(blocks_by_shared_memory(*sm, local_bytes));
    if (device.amd_local_mem_per_compute_unit) return *device.amd_local_mem_per_compute_unit / local_bytes;
    if (device.local_mem_type == "local") return device.local_mem_bytes / local_bytes;
    notes.push_back(fmt::format("local memory is emulated in global memory on this device (local memory "
                                "type \"{}\"): no per-compute-unit limit",
                                device.local_mem_type));
    return std::nullopt;
}
}  // namespace

Occupancy occupancy(const ocl::DeviceInfo& device, const KernelAttributes& k, std::size_t group_size,
                    std::uint64_t groups_total) {
    Occupancy o;
    o.group_size = group_size;
    o.local_bytes = k.local_mem_bytes;
    o.limited_by = "unknown";
    std::vector<std::string> notes;

    if (k.work_group_size_limit > 0 && group_size > k.work_group_size_limit) {
        notes.push_back(fmt::format("a work-group of {} exceeds the kernel's limit of {}", group_size,
                                    k.work_group_size_limit));
    }
    const CudaSmLimits* sm = nullptr;
    const bool nvidia = device.nv_compute_capability_major && device.nv_compute_capability_minor;
    if (nvidia) {
        sm = cuda_sm_limits(static_cast<int>(*device.nv_compute_capability_major),
                            static_cast<int>(*device.nv_compute_capability_minor));
        if (sm == nullptr) {
            notes.push_back(fmt::format("compute capability {}.{} is not in the occupancy table",
                                        *device.nv_compute_capability_major, *device.nv_compute_capability_minor));
        }
    }

    o.groups_per_cu_by_local = groups_by_local(device, sm, o.local_bytes, notes);

    if (sm != nullptr) {
        // The calculator's default state: the largest shared-memory carveout. A driver that picks a
        // smaller carveout fits fewer blocks by shared memory.
        notes.push_back("NVIDIA figures assume the largest shared-memory carveout (the CUDA occupancy "
                        "calculator's default)");
        if (!k.registers) {
            notes.push_back("register count unknown: no \"Used N registers\" line for this kernel in the "
                            "NVIDIA build log");
        } else if (group_size == 0 || group_size > INT_MAX) {
            notes.push_back("work-group size unknown");
        } else {
            const std::optional<CudaOccupancy> r = cuda_occupancy({sm->cc_major, sm->cc_minor,
                                                                   static_cast<int>(group_size), *k.registers,
                                                                   o.local_bytes});
            if (r) {
                o.resident_groups_per_cu = static_cast<std::uint64_t>(r->active_blocks_per_sm);
                o.theoretical = r->occupancy;
                o.limited_by = r->limited_by == "shared memory" ? "local memory" : r->limited_by;
            }
        }
    } else if (!nvidia) {
        notes.push_back("resident work-groups unknown: OpenCL does not report this device's register use "
                        "and per-compute-unit slot limits");
    }

    if (o.resident_groups_per_cu) {
        if (*o.resident_groups_per_cu == 0) {
            notes.push_back("a work-group of this kernel does not fit on a compute unit");
        } else if (device.compute_units > 0) {
            o.waves = static_cast<double>(groups_total) /
                      (static_cast<double>(device.compute_units) * static_cast<double>(*o.resident_groups_per_cu));
        }
    }

    for (const std::string& note : notes) {
        o.note += (o.note.empty() ? "" : "; ") + note;
    }
    return o;
}

nlohmann::json to_json(const Occupancy& o) {
    const auto optional = [](const auto& value) { return value ? nlohmann::json(*value) : nlohmann::json(nullptr); };
    return {
        {"group_size", o.group_size},
        {"local_bytes", o.local_bytes},
        {"groups_per_cu_by_local", optional(o.groups_per_cu_by_local)},
        {"resident_groups_per_cu", optional(o.resident_groups_per_cu)},
        {"waves", optional(o.waves)},
        {"theoretical", optional(o.theoretical)},
        {"limited_by", o.limited_by},
        {"note", o.note},
    };
}

}  // namespace sdfbrick::measure
