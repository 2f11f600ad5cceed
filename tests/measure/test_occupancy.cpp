// Occupancy proxies (host/measure/occupancy.h), the NVIDIA ptxas log parser and kernel attributes
// (host/measure/kernel_attributes.h). Worked examples follow cuda_occupancy.h's formula, by hand:
//   warps per block   = ceil(threads / 32)
//   blocks by warps   = max warps per SM / warps per block (0 above 1024 threads)
//   registers per warp = roundup(registers x 32, 256); blocks by registers =
//                       (65536 / 4 / registers per warp) x 4 / warps per block
//   shared per block  = roundup(shared + reserved (1 KiB from cc 8.0), 128 or 256)
//   blocks by shared  = shared per SM (largest carveout) / shared per block
//   occupancy         = min(...) x warps per block / max warps per SM
#include <gtest/gtest.h>

#include <CL/cl.h>

#include <cmath>
#include <cstdio>

#include "cl/device.h"
#include "cl/launch.h"
#include "cl/program.h"
#include "measure/kernel_attributes.h"
#include "measure/occupancy.h"
#include "test_support.h"

namespace sdfbrick::measure {
namespace {

CudaOccupancy calc(int major, int minor, int threads, int registers, std::uint64_t shared) {
    const std::optional<CudaOccupancy> r = cuda_occupancy({major, minor, threads, registers, shared});
    EXPECT_TRUE(r.has_value());
    return r.value_or(CudaOccupancy{});
}

// ------------------------------------------------------------------------------- CUDA calculator

TEST(MeasureOccupancy, Cc80FullOccupancyLimitedByWarps) {
    // 256 threads = 8 warps: 64 / 8 = 8 blocks. 32 regs: 1024 per warp, 16 warps per sub-partition,
    // 64 per SM, 64 / 8 = 8 blocks. Shared: 0 + 1 KiB reserved -> 164 KiB / 1 KiB = 164 blocks.
    // Block limit 32. min = 8 (warps and registers tie; warps is reported first) -> 64 warps = 100 %.
    const CudaOccupancy r = calc(8, 0, 256, 32, 0);
    EXPECT_EQ(r.blocks_by_warps, 8);
    EXPECT_EQ(r.blocks_by_registers, 8);
    EXPECT_EQ(r.blocks_by_shared_memory, 164);
    EXPECT_EQ(r.blocks_by_sm_limit, 32);
    EXPECT_EQ(r.active_blocks_per_sm, 8);
    EXPECT_EQ(r.active_warps_per_sm, 64);
    EXPECT_DOUBLE_EQ(r.occupancy, 1.0);
    EXPECT_EQ(r.limited_by, "warps");
}

TEST(MeasureOccupancy, Cc80HalfOccupancyLimitedByRegisters) {
    // 64 regs: 2048 per warp, 16384 / 2048 = 8 warps per sub-partition, 32 per SM, 32 / 8 = 4 blocks
    // -> 32 warps of 64 = 50 %.
    const CudaOccupancy r = calc(8, 0, 256, 64, 0);
    EXPECT_EQ(r.blocks_by_registers, 4);
    EXPECT_EQ(r.active_blocks_per_sm, 4);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.5);
    EXPECT_EQ(r.limited_by, "registers");
}

TEST(MeasureOccupancy, Cc80LimitedBySharedMemory) {
    // 128 threads = 4 warps (16 blocks by warps and by registers). Shared: 48 KiB + 1 KiB = 50176 bytes
    // (a multiple of 128); 167936 / 50176 = 3 blocks -> 12 warps of 64 = 18.75 %.
    const CudaOccupancy r = calc(8, 0, 128, 32, 48 * 1024);
    EXPECT_EQ(r.blocks_by_warps, 16);
    EXPECT_EQ(r.blocks_by_registers, 16);
    EXPECT_EQ(r.blocks_by_shared_memory, 3);
    EXPECT_EQ(r.active_blocks_per_sm, 3);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.1875);
    EXPECT_EQ(r.limited_by, "shared memory");
}

TEST(MeasureOccupancy, Cc90Cases) {
    // H100. 256 threads, 40 regs: 1280 per warp (a multiple of 256), 16384 / 1280 = 12 warps per
    // sub-partition, 48 per SM, 48 / 8 = 6 blocks -> 48 of 64 warps = 75 %.
    CudaOccupancy r = calc(9, 0, 256, 40, 0);
    EXPECT_EQ(r.blocks_by_registers, 6);
    EXPECT_EQ(r.blocks_by_shared_memory, 228);  // 228 KiB / (0 + 1 KiB)
    EXPECT_DOUBLE_EQ(r.occupancy, 0.75);
    EXPECT_EQ(r.limited_by, "registers");

    // 32 threads, 16 regs: 64 blocks by warps, 128 by registers, but at most 32 resident blocks
    // -> 32 warps = 50 %.
    r = calc(9, 0, 32, 16, 0);
    EXPECT_EQ(r.blocks_by_warps, 64);
    EXPECT_EQ(r.blocks_by_registers, 128);
    EXPECT_EQ(r.active_blocks_per_sm, 32);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.5);
    EXPECT_EQ(r.limited_by, "blocks per SM");

    // 128 threads, 100 KiB shared: 102400 + 1024 = 103424 bytes; 233472 / 103424 = 2 blocks
    // -> 8 warps = 12.5 %.
    r = calc(9, 0, 128, 32, 100 * 1024);
    EXPECT_EQ(r.blocks_by_shared_memory, 2);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.125);
    EXPECT_EQ(r.limited_by, "shared memory");

    // 227 KiB is the most a block may use; one byte more does not fit.
    EXPECT_EQ(calc(9, 0, 128, 32, 227 * 1024).blocks_by_shared_memory, 1);
    EXPECT_EQ(calc(9, 0, 128, 32, 227 * 1024 + 1).active_blocks_per_sm, 0);

    // 1024 threads, 32 regs: 2 blocks by warps and by registers -> 100 %.
    EXPECT_DOUBLE_EQ(calc(9, 0, 1024, 32, 0).occupancy, 1.0);
}

TEST(MeasureOccupancy, ImpossibleBlocks) {
    // More than 255 registers per thread: no block can run.
    CudaOccupancy r = calc(8, 0, 64, 256, 0);
    EXPECT_EQ(r.blocks_by_registers, 0);
    EXPECT_EQ(r.active_blocks_per_sm, 0);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.0);
    EXPECT_EQ(r.limited_by, "registers");

    // 1024 threads x 72 regs: 2304 per warp x 32 warps = 73728 > 65536 registers per block.
    EXPECT_EQ(calc(8, 0, 1024, 72, 0).blocks_by_registers, 0);

    // A block larger than 1024 threads.
    r = calc(8, 0, 1056, 16, 0);
    EXPECT_EQ(r.blocks_by_warps, 0);
    EXPECT_EQ(r.active_blocks_per_sm, 0);
    EXPECT_EQ(r.limited_by, "warps");
}

TEST(MeasureOccupancy, PartialWarpTakesAWholeWarp) {
    // 48 threads -> 2 warps. 64 regs: 2048 per warp, 32 warps per SM -> 16 blocks (not 21, as 1.5
    // warps would give); 16 x 2 = 32 warps = 50 %.
    const CudaOccupancy r = calc(8, 0, 48, 64, 0);
    EXPECT_EQ(r.blocks_by_warps, 32);
    EXPECT_EQ(r.blocks_by_registers, 16);
    EXPECT_EQ(r.active_warps_per_sm, 32);
    EXPECT_DOUBLE_EQ(r.occupancy, 0.5);
}

TEST(MeasureOccupancy, OtherArchitectures) {
    // cc 8.6: 48 warps, 16 blocks. 128 threads, 32 regs: 12 by warps, 16 by registers, 16 by blocks
    // -> 12 x 4 = 48 warps = 100 %.
    EXPECT_DOUBLE_EQ(calc(8, 6, 128, 32, 0).occupancy, 1.0);
    // cc 7.5: 32 warps. 256 threads, 32 regs: 4 blocks by warps -> 100 %; shared unused -> unlimited.
    const CudaOccupancy r = calc(7, 5, 256, 32, 0);
    EXPECT_EQ(r.active_blocks_per_sm, 4);
    EXPECT_EQ(r.blocks_by_shared_memory, CudaOccupancy::kUnlimited);
    // cc 6.1: 1 KiB of shared memory rounds to 256-byte units: 96 KiB / 1 KiB = 96 blocks.
    EXPECT_EQ(calc(6, 1, 128, 32, 1000).blocks_by_shared_memory, 96);
}

TEST(MeasureOccupancy, UnknownComputeCapability) {
    EXPECT_FALSE(cuda_occupancy({10, 0, 256, 32, 0}).has_value());
    EXPECT_FALSE(cuda_occupancy({3, 5, 256, 32, 0}).has_value());
    EXPECT_FALSE(cuda_occupancy({8, 0, 0, 32, 0}).has_value());
    EXPECT_EQ(cuda_sm_limits(8, 1), nullptr);
    ASSERT_NE(cuda_sm_limits(9, 0), nullptr);
    EXPECT_EQ(cuda_sm_limits(9, 0)->shared_per_sm, 228u * 1024u);
}

// ------------------------------------------------------------------------------- occupancy()

KernelAttributes attributes(std::uint64_t local_bytes, std::optional<int> registers) {
    return KernelAttributes{.kernel = "k",
                            .work_group_size_limit = 1024,
                            .preferred_multiple = 32,
                            .local_mem_bytes = local_bytes,
                            .private_mem_bytes = 0,
                            .registers = registers,
                            .spill_store_bytes = std::nullopt,
                            .spill_load_bytes = std::nullopt};
}

TEST(MeasureOccupancy, NvidiaDeviceGivesWaves) {
    // 256 work-items, 40 registers, 16 KiB local: 6 blocks by registers; by local memory
    // 233472 / (16384 + 1024) = 13. Resident 6; 10000 groups / (132 x 6) = 12.626... waves.
    const Occupancy o = occupancy(test::nvidia_h100_info(), attributes(16 * 1024, 40), 256, 10000);
    EXPECT_EQ(o.group_size, 256u);
    EXPECT_EQ(o.groups_per_cu_by_local, 13u);
    EXPECT_EQ(o.resident_groups_per_cu, 6u);
    ASSERT_TRUE(o.waves.has_value());
    EXPECT_DOUBLE_EQ(*o.waves, 10000.0 / (132.0 * 6.0));
    EXPECT_DOUBLE_EQ(o.theoretical.value_or(-1), 0.75);
    EXPECT_EQ(o.limited_by, "registers");
    EXPECT_NE(o.note.find("carveout"), std::string::npos);

    // Local memory the limit: 64 KiB + 1 KiB per group -> 3 groups -> 24 warps = 37.5 %.
    const Occupancy local = occupancy(test::nvidia_h100_info(), attributes(64 * 1024, 32), 256, 10);
    EXPECT_EQ(local.resident_groups_per_cu, 3u);
    EXPECT_EQ(local.limited_by, "local memory");
    EXPECT_DOUBLE_EQ(local.theoretical.value_or(-1), 0.375);

    // Without a register count, only the local-memory figure is known.
    const Occupancy unknown = occupancy(test::nvidia_h100_info(), attributes(16 * 1024, std::nullopt), 256, 10000);
    EXPECT_EQ(unknown.groups_per_cu_by_local, 13u);
    EXPECT_FALSE(unknown.resident_groups_per_cu.has_value());
    EXPECT_FALSE(unknown.waves.has_value());
    EXPECT_FALSE(unknown.theoretical.has_value());
    EXPECT_EQ(unknown.limited_by, "unknown");
    EXPECT_NE(unknown.note.find("register count unknown"), std::string::npos);

    // An unknown compute capability: no theoretical occupancy; local memory from CL_DEVICE_LOCAL_MEM_SIZE.
    ocl::DeviceInfo future = test::nvidia_h100_info();
    future.nv_compute_capability_major = 12;
    const Occupancy f = occupancy(future, attributes(16 * 1024, 40), 256, 10000);
    EXPECT_FALSE(f.theoretical.has_value());
    EXPECT_FALSE(f.resident_groups_per_cu.has_value());
    EXPECT_EQ(f.groups_per_cu_by_local, 3u);  // 48 KiB / 16 KiB
    EXPECT_NE(f.note.find("12.0 is not in the occupancy table"), std::string::npos);
}

TEST(MeasureOccupancy, PoclLikeDeviceLeavesUnknowns) {
    ocl::DeviceInfo d;
    d.name = "cpu-x86-64";
    d.type = "cpu";
    d.compute_units = 2;
    d.local_mem_bytes = 4 * 1024 * 1024;
    d.local_mem_type = "global";
    const Occupancy o = occupancy(d, attributes(4096, std::nullopt), 64, 100);
    EXPECT_FALSE(o.groups_per_cu_by_local.has_value());
    EXPECT_FALSE(o.resident_groups_per_cu.has_value());
    EXPECT_FALSE(o.waves.has_value());
    EXPECT_FALSE(o.theoretical.has_value());
    EXPECT_EQ(o.limited_by, "unknown");
    EXPECT_NE(o.note.find("emulated in global memory"), std::string::npos);
    EXPECT_NE(o.note.find("resident work-groups unknown"), std::string::npos);

    const nlohmann::json j = to_json(o);
    EXPECT_TRUE(j["groups_per_cu_by_local"].is_null());
    EXPECT_TRUE(j["waves"].is_null());
    EXPECT_TRUE(j["theoretical"].is_null());
    EXPECT_EQ(j["group_size"], 64);
    EXPECT_EQ(j["local_bytes"], 4096);
}

TEST(MeasureOccupancy, AmdLikeAndNoLocalMemory) {
    ocl::DeviceInfo d;
    d.name = "gfx1100";
    d.type = "gpu";
    d.compute_units = 48;
    d.local_mem_bytes = 64 * 1024;
    d.local_mem_type = "local";
    d.amd_local_mem_per_compute_unit = 128 * 1024;
    d.amd_wavefront_width = 32;
    const Occupancy o = occupancy(d, attributes(20 * 1024, std::nullopt), 256, 1000);
    EXPECT_EQ(o.groups_per_cu_by_local, 6u);  // 131072 / 20480
    EXPECT_FALSE(o.resident_groups_per_cu.has_value());
    EXPECT_FALSE(o.theoretical.has_value());

    // Another device with dedicated local memory: CL_DEVICE_LOCAL_MEM_SIZE / local bytes.
    d.amd_local_mem_per_compute_unit.reset();
    EXPECT_EQ(occupancy(d, attributes(20 * 1024, std::nullopt), 256, 1000).groups_per_cu_by_local, 3u);

    // No local memory: no local-memory limit (empty), said in the note.
    const Occupancy none = occupancy(d, attributes(0, std::nullopt), 256, 1000);
    EXPECT_FALSE(none.groups_per_cu_by_local.has_value());
    EXPECT_NE(none.note.find("no local memory used"), std::string::npos);
}

// ------------------------------------------------------------------------------- ptxas log

TEST(MeasureOccupancy, ParsesNvidiaVerboseLog) {
    // The first function's lines as NVIDIA's OpenCL (driver 580.159.04, H100) wrote them; the others
    // in the format of older drivers and with a called function's properties in between.
    const std::string log =
        "ptxas info    : 0 bytes gmem\n"
        "ptxas info    : Compiling entry function 'brick_evaluate' for 'sm_90a'\n"
        "ptxas info    : Function properties for brick_evaluate\n"
        "ptxas         .     0 bytes stack frame, 0 bytes spill stores, 0 bytes spill loads\n"
        "ptxas info    : Used 40 registers, used 1 barriers\n"
        "ptxas info    : Compile time = 3.916 ms\n"
        "ptxas info    : Compiling entry function 'trace' for 'sm_90'\n"
        "ptxas info    : Function properties for helper\n"
        "ptxas         .     8 bytes stack frame, 4 bytes spill stores, 4 bytes spill loads\n"
        "ptxas info    : Function properties for trace\n"
        "ptxas         .     24 bytes stack frame, 16 bytes spill stores, 12 bytes spill loads\n"
        "ptxas info    : Used 128 registers, used 1 barriers, 400 bytes cmem[0]\n"
        "ptxas info    : Compiling entry function 'no_register_line' for 'sm_90'\n";
    const std::map<std::string, int> registers = parse_nv_registers(log);
    EXPECT_EQ(registers.size(), 2u);
    EXPECT_EQ(registers.at("brick_evaluate"), 40);
    EXPECT_EQ(registers.at("trace"), 128);
    EXPECT_EQ(registers.count("no_register_line"), 0u);

    const auto functions = parse_nv_ptxas(log);
    EXPECT_EQ(functions.at("brick_evaluate").spill_store_bytes, 0u);
    EXPECT_EQ(functions.at("trace").spill_store_bytes, 16u);  // its own block, not helper's
    EXPECT_EQ(functions.at("trace").spill_load_bytes, 12u);
    EXPECT_FALSE(functions.at("no_register_line").registers.has_value());

    EXPECT_TRUE(parse_nv_registers("").empty());
    EXPECT_TRUE(parse_nv_registers("warning: something\nUsed 12 registers\n").empty());  // no entry function
}

// ------------------------------------------------------------------------------- kernel attributes

TEST(MeasureKernelAttributes, ReportsLocalArgumentsOnTheTestDevice) {
    ocl::Device& device = test::device();
    const ocl::Program program = ocl::build_program(device, "test_layer.cl");
    const ocl::Kernel kernel = ocl::make_kernel(program, "reverse_groups");
    const ocl::Buffer<cl_uint> in(device, 64);
    const ocl::Buffer<cl_uint> out(device, 64);
    constexpr std::size_t kLocal = 3000;
    ocl::set_args(kernel.get(), in, out, ocl::LocalMemory{kLocal});

    const KernelAttributes a = kernel_attributes(device, kernel.get());
    EXPECT_EQ(a.kernel, "reverse_groups");
    EXPECT_GE(a.local_mem_bytes, kLocal);
    EXPECT_GT(a.work_group_size_limit, 0u);
    EXPECT_GT(a.preferred_multiple, 0u);
    if (!device.info().has_extension("cl_nv_device_attribute_query")) {
        EXPECT_FALSE(a.registers.has_value());
    } else {
        EXPECT_TRUE(a.registers.has_value());  // from the -cl-nv-verbose build log
    }
    const nlohmann::json j = to_json(a);
    EXPECT_EQ(j["kernel"], "reverse_groups");
    EXPECT_EQ(j["registers"].is_null(), !a.registers.has_value());

    // A larger __local argument is reflected at the next query.
    ocl::set_args(kernel.get(), in, out, ocl::LocalMemory{2 * kLocal});
    EXPECT_GE(kernel_attributes(device, kernel.get()).local_mem_bytes, 2 * kLocal);

    const Occupancy o = occupancy(device.info(), a, 64, 1);
    EXPECT_EQ(o.local_bytes, a.local_mem_bytes);
    std::printf("%s on %s: %s\n%s\n", a.kernel.c_str(), device.info().name.c_str(), to_json(a).dump().c_str(),
                to_json(o).dump().c_str());
}

}  // namespace
}  // namespace sdfbrick::measure
