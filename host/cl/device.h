// OpenCL devices: enumeration and the facts the engine reports (DeviceInfo), selection by a spec
// string, and opened devices (Device: context + profiling queue) grouped in a DeviceSet.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/handles.h"
#include "cl/memory_pool.h"

namespace sdfbrick::ocl {

class Program;

// What one device reports. Vendor attributes are queried only when the device lists the vendor's
// extension (cl_nv_device_attribute_query, cl_amd_device_attribute_query); otherwise, or when the
// query fails, they stay empty: never guessed.
struct DeviceInfo {
    std::size_t index = 0;  // global enumeration order: platforms in order, their devices in order

    std::size_t platform_index = 0;
    std::string platform_name;
    std::string platform_vendor;
    std::string platform_version;

    std::string name;
    std::string vendor;
    std::string driver_version;
    std::string device_version;    // "OpenCL 3.0 CUDA"
    std::string opencl_c_version;  // "OpenCL C 1.2 ..."
    std::string type;              // "gpu", "cpu", "accelerator" or "other"

    std::uint32_t compute_units = 0;
    std::uint32_t max_clock_mhz = 0;
    std::uint32_t native_float_width = 0;  // CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT: SIMD lanes of a CPU core
    std::uint64_t global_mem_bytes = 0;
    std::uint64_t max_alloc_bytes = 0;
    std::uint64_t local_mem_bytes = 0;
    std::string local_mem_type;  // "local" (dedicated), "global" (emulated) or "none"
    std::size_t max_work_group_size = 0;
    std::vector<std::size_t> max_work_item_sizes;

    bool correctly_rounded_divide_sqrt = false;  // CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT in SINGLE_FP_CONFIG
    bool fp32_denorms = false;                   // CL_FP_DENORM in SINGLE_FP_CONFIG
    std::size_t profiling_timer_resolution_ns = 0;
    std::vector<std::string> extensions;

    // cl_nv_device_attribute_query
    std::optional<std::uint32_t> nv_compute_capability_major;
    std::optional<std::uint32_t> nv_compute_capability_minor;
    std::optional<std::uint32_t> nv_warp_size;
    std::optional<std::uint32_t> nv_registers_per_block;
    std::optional<bool> nv_integrated_memory;
    std::optional<bool> nv_kernel_exec_timeout;

    // cl_amd_device_attribute_query
    std::optional<std::uint32_t> amd_wavefront_width;
    std::optional<std::uint32_t> amd_simd_per_compute_unit;
    std::optional<std::uint32_t> amd_local_mem_per_compute_unit;
    std::optional<std::uint32_t> amd_gfxip_major;
    std::optional<std::uint32_t> amd_gfxip_minor;

    bool has_extension(std::string_view extension) const;

    // All fields; an absent vendor attribute is omitted (the "nvidia" / "amd" objects are omitted
    // when none of their attributes is present).
    nlohmann::json to_json() const;
};

// Every device of every platform, in global enumeration order. Platforms without devices are
// skipped. Throws ClError when there is no OpenCL platform at all (the message says how to get one).
std::vector<DeviceInfo> list_devices();

// An aligned text table of the devices, one line each, with a header line.
std::string devices_table(const std::vector<DeviceInfo>& devices);

// Environment variable read when a device spec is empty.
inline constexpr const char* kDeviceEnv = "SDFBRICK_DEVICE";

// Picks devices by a spec: comma-separated items, each one of
//   a global index ("0"), a type ("gpu", "cpu", "accelerator", "all"),
//   a case-insensitive substring of the device or platform name, optionally written "name:<text>"
//   (so that a name such as "gpu" or "0" can be asked for as a name).
// An empty spec means $SDFBRICK_DEVICE if set and non-empty, else the default: the first GPU, or
// device 0 when there is no GPU. Returns unique indices in enumeration order. Throws InputError
// when an item matches no device or the spec is malformed.
std::vector<std::size_t> select_devices(std::string_view spec, const std::vector<DeviceInfo>& devices);

// An opened device: its own in-order command queue with profiling enabled, and the context that it
// shares with the other opened devices of its platform. Programs built for it are kept in memory
// for its lifetime (program.h). Use a Device from one thread at a time.
class Device {
public:
    Device(DeviceInfo info, cl_device_id id, Context context);
    ~Device();
    Device(Device&&) noexcept;
    Device& operator=(Device&&) noexcept;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceInfo& info() const { return info_; }
    cl_device_id id() const { return id_; }
    cl_context context() const { return context_.get(); }
    cl_command_queue queue() const { return queue_.get(); }

    // Blocks until every command of the queue has completed.
    void finish();

    // The memory that pooled buffers of this device keep between passes (cl/memory_pool.h).
    const std::shared_ptr<MemoryPool>& memory_pool() const { return memory_pool_; }

    // In-memory program cache, used by build_program.
    const Program* find_program(std::string_view key) const;
    // The remembered program with this handle (e.g. from CL_KERNEL_PROGRAM), or nullptr.
    const Program* find_program(cl_program handle) const;
    void remember_program(const Program& program);
    // The cache key build_program found for a request (file and options) of embedded sources: a
    // request made again skips assembling and hashing the source. nullptr when not made yet.
    const std::string* program_key(std::string_view request) const;
    void remember_program_key(std::string request, std::string key);

private:
    DeviceInfo info_;
    cl_device_id id_ = nullptr;
    Context context_;
    Queue queue_;
    std::vector<Program> programs_;
    std::map<std::string, std::string, std::less<>> program_keys_;
    std::shared_ptr<MemoryPool> memory_pool_ = std::make_shared<MemoryPool>();
};

// One or more opened devices, possibly of different platforms (one context per device).
class DeviceSet {
public:
    // Lists the devices, selects by spec (see select_devices) and opens them.
    static DeviceSet open(std::string_view spec);

    std::size_t size() const { return devices_.size(); }
    Device& operator[](std::size_t i) { return devices_.at(i); }
    const Device& operator[](std::size_t i) const { return devices_.at(i); }
    auto begin() { return devices_.begin(); }
    auto end() { return devices_.end(); }
    auto begin() const { return devices_.begin(); }
    auto end() const { return devices_.end(); }

    // Runs f(Device&) on each device in order.
    template <class F>
    void for_each(F&& f) {
        for (Device& device : devices_) {
            f(device);
        }
    }

private:
    explicit DeviceSet(std::vector<Device> devices) : devices_(std::move(devices)) {}

    std::vector<Device> devices_;
};

}  // namespace sdfbrick::ocl
