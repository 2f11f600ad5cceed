// Programs: kernel files built for one device with fixed, deterministic options, cached in memory
// (per Device) and on disk (binaries keyed by a hash of device, driver, source and options).
//
// Every program is built with -cl-std=CL1.2, plus -cl-fp32-correctly-rounded-divide-sqrt where the
// device supports it, plus -cl-nv-verbose on NVIDIA devices (cl_nv_device_attribute_query: the build
// log then reports each kernel's registers, see measure/kernel_attributes.h), and its source starts
// with '#pragma OPENCL FP_CONTRACT OFF' (on PoCL it ends with an empty kernel named after the device,
// so that two PoCL devices never share a program hash: see program.cpp). Options that
// change floating-point results (fast/relaxed math, mad, ...) are refused.
//
// Disk cache directory: $SDFBRICK_CACHE_DIR ("off" disables the disk cache), else
// $XDG_CACHE_HOME/sdfbrick/programs, else $HOME/.cache/sdfbrick/programs. It is kept private to the
// user: created with mode 0700; one open to group or others is made 0700 and its entries are
// discarded (its secret made anew); one owned by another user is not used (the record's cache_note
// says which happened). A cache entry that cannot be read, whose MAC does not verify (see
// CacheEntry), that the driver refuses, or whose binary defines other kernels than the entry says is
// deleted and the program is built from source: a damaged or forged cache never breaks a run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "cl/handles.h"

namespace sdfbrick::ocl {

class Device;
struct DeviceInfo;

inline constexpr const char* kCacheDirEnv = "SDFBRICK_CACHE_DIR";

enum class ProgramOrigin { compiled, disk_cache, memory_cache };
std::string_view to_string(ProgramOrigin origin);  // "compiled", "disk cache", "memory cache"

// How a program came to be, for reports.
struct BuildRecord {
    std::string kernel_file;
    std::string device_name;
    std::string options;  // the complete option string given to the compiler
    std::string key;      // 16 hex digits: FNV-1a 64 of platform, device, driver, source, options
    bool correctly_rounded_divide_sqrt = false;  // whether the options ask for it
    ProgramOrigin origin = ProgramOrigin::compiled;
    double build_ms = 0.0;  // wall time of build_program: compile, cache load, or memory look-up
    std::string log;        // the compiler's log of the build that produced the binary
    std::optional<std::filesystem::path> cache_file;  // the disk cache entry; empty when the disk cache is off
    std::string cache_note;  // why the disk cache was not used as expected (damaged entry, write failure); usually empty

    bool from_cache() const { return origin != ProgramOrigin::compiled; }
};

class Program {
public:
    Program(ProgramHandle handle, BuildRecord record) : handle_(std::move(handle)), record_(std::move(record)) {}

    cl_program get() const { return handle_.get(); }
    const ProgramHandle& handle() const { return handle_; }
    const BuildRecord& record() const { return record_; }

private:
    ProgramHandle handle_;
    BuildRecord record_;
};

// The disk cache directory now in effect (see above), or std::nullopt when the disk cache is off.
std::optional<std::filesystem::path> program_cache_dir();

// Builds kernel_file (see kernel_source.h) for device. extra_options: further compiler options,
// usually -D defines. Throws ClError on a failed build: the message names the file, the device, the
// options, and holds the full build log. Throws std::invalid_argument for a refused option.
Program build_program(Device& device, std::string_view kernel_file, std::string_view extra_options = "");

// The compiler option that caps a kernel's registers per work-item at `registers` where the device's
// compiler takes one (NVIDIA's -cl-nv-maxrregcount, cl_nv_compiler_options), with a leading space;
// "" for 0 or elsewhere. The cap changes where values live, never an operation.
std::string register_cap_option(const DeviceInfo& device, int registers);

// Throws ClError naming the kernel (and the kernels the program does define) on failure.
Kernel make_kernel(const Program& program, const char* name);

// The most work-items per work-group that kernel (named name in errors) allows on device
// (CL_KERNEL_WORK_GROUP_SIZE: its registers and local memory can lower it below the device's limit).
std::size_t kernel_work_group_limit(const Device& device, cl_kernel kernel, std::string_view name);

// The __local bytes kernel uses on device with its __local arguments as set so far
// (CL_KERNEL_LOCAL_MEM_SIZE; before any is set, its own __local arrays).
std::uint64_t kernel_local_bytes(const Device& device, cl_kernel kernel, std::string_view name);

// Rewrites locations that a compiler reports in the assembled source, ignoring its #line directives
// (NVIDIA: "<kernel>:7:23: error"), to the kernel file and line: "bad.cl:3:23: error". build_program
// applies it to every build log.
std::string map_log_locations(std::string_view log, std::string_view assembled_source);

// Disk cache entries: a short text header (format, key, sizes, MAC) then the build log and the
// binary. The MAC is SipHash-2-4 keyed with the cache directory's secret, over the program's
// identity (platform, device, driver, source, options) and the entry: an entry made by someone
// without the secret, or for another program, never reaches the driver. A binary that passes is
// still refused when it defines a kernel the source does not declare. Exposed for tests.
struct CacheEntry {
    std::string key;
    std::string log;
    std::string binary;
};
struct CacheSeal {
    std::uint64_t k0 = 0, k1 = 0;  // the secret key
    std::string identity;          // what the program's key hashes
};
std::string encode_cache_entry(const CacheEntry& entry, const CacheSeal& seal);
// std::nullopt when bytes are not a complete entry whose MAC verifies under seal.
std::optional<CacheEntry> decode_cache_entry(std::string_view bytes, const CacheSeal& seal);

// The seal of build_program(device, kernel_file, extra_options)'s disk cache entry in the cache
// directory now in effect; std::nullopt when the disk cache is off or unusable. Exposed for tests.
std::optional<CacheSeal> cache_seal(const Device& device, std::string_view kernel_file, std::string_view extra_options = "");

}  // namespace sdfbrick::ocl
