// What OpenCL (and, on NVIDIA, the compiler's verbose log) says about one kernel on one device: the
// inputs of the occupancy proxies (occupancy.h).
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace sdfbrick::ocl {
class Device;
}

namespace sdfbrick::measure {

struct KernelAttributes {
    std::string kernel;                      // CL_KERNEL_FUNCTION_NAME
    std::size_t work_group_size_limit = 0;   // CL_KERNEL_WORK_GROUP_SIZE
    std::size_t preferred_multiple = 0;      // CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE
    std::uint64_t local_mem_bytes = 0;       // CL_KERNEL_LOCAL_MEM_SIZE: static __local plus __local arguments as currently set
    std::uint64_t private_mem_bytes = 0;     // CL_KERNEL_PRIVATE_MEM_SIZE
    std::optional<int> registers;            // per work-item, from the NVIDIA verbose build log; empty when unknown
    std::optional<std::uint64_t> spill_store_bytes;  // from the same log; empty when unknown
    std::optional<std::uint64_t> spill_load_bytes;
};

// The attributes of kernel as its arguments are set now (call it after setting them, so that
// local_mem_bytes includes the __local arguments). Registers and spills are looked up in the build
// log of the kernel's program when the device has cl_nv_device_attribute_query (build_program then
// adds -cl-nv-verbose) and the program was built through build_program for this device; each log is
// parsed once. Throws ClError when a query fails.
KernelAttributes kernel_attributes(const ocl::Device& device, cl_kernel kernel);

// Unknown values are JSON null.
nlohmann::json to_json(const KernelAttributes& attributes);

// What ptxas --verbose says about one entry function.
struct PtxasFunction {
    std::optional<int> registers;                    // "Used N registers"
    std::optional<std::uint64_t> spill_store_bytes;  // "N bytes spill stores"
    std::optional<std::uint64_t> spill_load_bytes;   // "N bytes spill loads"
};

// Parses NVIDIA ptxas verbose output, as in an OpenCL build log built with -cl-nv-verbose:
//   ptxas info    : Compiling entry function 'brick_evaluate' for 'sm_90'
//   ptxas info    : Function properties for brick_evaluate
//   ptxas         .     0 bytes stack frame, 0 bytes spill stores, 0 bytes spill loads
//   ptxas info    : Used 40 registers, 392 bytes cmem[0]
// Lines are attributed to the entry function named by the last "Compiling entry function" line
// (spills only from that function's own "Function properties" block, not from a called
// non-inlined function's). Every entry function seen is in the map; fields whose lines are missing
// stay empty. Other text is ignored.
std::map<std::string, PtxasFunction> parse_nv_ptxas(std::string_view log);

// Entry-function name -> registers per thread; a function without a "Used N registers" line is absent.
std::map<std::string, int> parse_nv_registers(std::string_view log);

}  // namespace sdfbrick::measure
