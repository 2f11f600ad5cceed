#include "cl/device.h"

#include <CL/cl_ext.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cl/program.h"
#include "core/errors.h"

// Vendor attribute queries, in case the installed headers lack them.
#ifndef CL_PLATFORM_NOT_FOUND_KHR
#define CL_PLATFORM_NOT_FOUND_KHR -1001
#endif
#ifndef CL_DEVICE_COMPUTE_CAPABILITY_MAJOR_NV
#define CL_DEVICE_COMPUTE_CAPABILITY_MAJOR_NV 0x4000
#endif
#ifndef CL_DEVICE_COMPUTE_CAPABILITY_MINOR_NV
#define CL_DEVICE_COMPUTE_CAPABILITY_MINOR_NV 0x4001
#endif
#ifndef CL_DEVICE_REGISTERS_PER_BLOCK_NV
#define CL_DEVICE_REGISTERS_PER_BLOCK_NV 0x4002
#endif
#ifndef CL_DEVICE_WARP_SIZE_NV
#define CL_DEVICE_WARP_SIZE_NV 0x4003
#endif
#ifndef CL_DEVICE_KERNEL_EXEC_TIMEOUT_NV
#define CL_DEVICE_KERNEL_EXEC_TIMEOUT_NV 0x4005
#endif
#ifndef CL_DEVICE_INTEGRATED_MEMORY_NV
#define CL_DEVICE_INTEGRATED_MEMORY_NV 0x4006
#endif
#ifndef CL_DEVICE_SIMD_PER_COMPUTE_UNIT_AMD
#define CL_DEVICE_SIMD_PER_COMPUTE_UNIT_AMD 0x4040
#endif
#ifndef CL_DEVICE_WAVEFRONT_WIDTH_AMD
#define CL_DEVICE_WAVEFRONT_WIDTH_AMD 0x4043
#endif
#ifndef CL_DEVICE_LOCAL_MEM_SIZE_PER_COMPUTE_UNIT_AMD
#define CL_DEVICE_LOCAL_MEM_SIZE_PER_COMPUTE_UNIT_AMD 0x4047
#endif
#ifndef CL_DEVICE_GFXIP_MAJOR_AMD
#define CL_DEVICE_GFXIP_MAJOR_AMD 0x404A
#endif
#ifndef CL_DEVICE_GFXIP_MINOR_AMD
#define CL_DEVICE_GFXIP_MINOR_AMD 0x404B
#endif

namespace sdfbrick::ocl {

namespace {

std::string_view trim(std::string_view s) {
    const auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0 || c == '\0'; };
    while (!s.empty() && is_space(s.front())) {
        s.remove_prefix(1);
    }
    while (!s.empty() && is_space(s.back())) {
        s.remove_suffix(1);
    }
    return s;
}

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); });
    return out;
}

std::string platform_string(cl_platform_id platform, cl_platform_info param, std::string_view what,
                            std::size_t platform_index) {
    const auto doing = [&] { return fmt::format("querying the {} of platform {}", what, platform_index); };
    std::size_t size = 0;
    check(clGetPlatformInfo(platform, param, 0, nullptr, &size), doing());
    std::string text(size, '\0');
    check(clGetPlatformInfo(platform, param, size, text.data(), nullptr), doing());
    return std::string(trim(text));
}

// Queries of one device; error messages name the device by its place in the enumeration.
class DeviceQuery {
public:
    DeviceQuery(cl_device_id id, std::size_t index) : id_(id), index_(index) {}

    std::string text(cl_device_info param, std::string_view what) const {
        std::size_t size = 0;
        check(clGetDeviceInfo(id_, param, 0, nullptr, &size), doing(what));
        std::string text(size, '\0');
        check(clGetDeviceInfo(id_, param, size, text.data(), nullptr), doing(what));
        return std::string(trim(text));
    }

    template <class T>
    T value(cl_device_info param, std::string_view what) const {
        T value{};
        check(clGetDeviceInfo(id_, param, sizeof(T), &value, nullptr), doing(what));
        return value;
    }

    template <class T>
    std::vector<T> array(cl_device_info param, std::string_view what) const {
        std::size_t size = 0;
        check(clGetDeviceInfo(id_, param, 0, nullptr, &size), doing(what));
        std::vector<T> values(size / sizeof(T));
        check(clGetDeviceInfo(id_, param, values.size() * sizeof(T), values.data(), nullptr), doing(what));
        return values;
    }

    // A vendor attribute: empty when the driver refuses the query.
    std::optional<std::uint32_t> vendor_value(cl_device_info param) const {
        cl_uint value = 0;
        if (clGetDeviceInfo(id_, param, sizeof(value), &value, nullptr) != CL_SUCCESS) {
            return std::nullopt;
        }
        return value;
    }

    std::optional<bool> vendor_flag(cl_device_info param) const {
        const std::optional<std::uint32_t> value = vendor_value(param);
        if (!value) {
            return std::nullopt;
        }
        return *value != 0;
    }

private:
    std::string doing(std::string_view what) const { return fmt::format("querying the {} of device {}", what, index_); }

    cl_device_id id_;
    std::size_t index_;
};

std::string type_name(cl_device_type type) {
    if ((type & CL_DEVICE_TYPE_GPU) != 0) {
        return "gpu";
    }
    if ((type & CL_DEVICE_TYPE_CPU) != 0) {
        return "cpu";
    }
    if ((type & CL_DEVICE_TYPE_ACCELERATOR) != 0) {
        return "accelerator";
    }
    return "other";
}

std::string local_mem_type_name(cl_device_local_mem_type type) {
    switch (type) {
    case CL_LOCAL: return "local";
    case CL_GLOBAL: return "global";
    default: return "none";
    }
}

std::vector<std::string> split_words(std::string_view text) {
    std::vector<std::string> words;
    std::istringstream in{std::string(text)};
    for (std::string word; in >> word;) {
        words.push_back(word);
    }
    return words;
}

DeviceInfo query_device(cl_device_id id, std::size_t index) {
    const DeviceQuery q(id, index);
    DeviceInfo info;
    info.index = index;
    info.name = q.text(CL_DEVICE_NAME, "name");
    info.vendor = q.text(CL_DEVICE_VENDOR, "vendor");
    info.driver_version = q.text(CL_DRIVER_VERSION, "driver version");
    info.device_version = q.text(CL_DEVICE_VERSION, "OpenCL version");
    info.opencl_c_version = q.text(CL_DEVICE_OPENCL_C_VERSION, "OpenCL C version");
    info.type = type_name(q.value<cl_device_type>(CL_DEVICE_TYPE, "type"));
    info.compute_units = q.value<cl_uint>(CL_DEVICE_MAX_COMPUTE_UNITS, "compute unit count");
    info.max_clock_mhz = q.value<cl_uint>(CL_DEVICE_MAX_CLOCK_FREQUENCY, "clock frequency");
    info.native_float_width = q.value<cl_uint>(CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT, "native float vector width");
    info.global_mem_bytes = q.value<cl_ulong>(CL_DEVICE_GLOBAL_MEM_SIZE, "global memory size");
    info.max_alloc_bytes = q.value<cl_ulong>(CL_DEVICE_MAX_MEM_ALLOC_SIZE, "largest allocation size");
    info.local_mem_bytes = q.value<cl_ulong>(CL_DEVICE_LOCAL_MEM_SIZE, "local memory size");
    info.local_mem_type =
        local_mem_type_name(q.value<cl_device_local_mem_type>(CL_DEVICE_LOCAL_MEM_TYPE, "local memory type"));
    info.max_work_group_size = q.value<std::size_t>(CL_DEVICE_MAX_WORK_GROUP_SIZE, "work-group size limit");
    info.max_work_item_sizes = q.array<std::size_t>(CL_DEVICE_MAX_WORK_ITEM_SIZES, "work-item size limits");
    const auto fp_config = q.value<cl_device_fp_config>(CL_DEVICE_SINGLE_FP_CONFIG, "single precision capabilities");
    info.correctly_rounded_divide_sqrt = (fp_config & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
    info.fp32_denorms = (fp_config & CL_FP_DENORM) != 0;
    info.profiling_timer_resolution_ns =
        q.value<std::size_t>(CL_DEVICE_PROFILING_TIMER_RESOLUTION, "profiling timer resolution");
    info.extensions = split_words(q.text(CL_DEVICE_EXTENSIONS, "extensions"));

    if (info.has_extension("cl_nv_device_attribute_query")) {
        info.nv_compute_capability_major = q.vendor_value(CL_DEVICE_COMPUTE_CAPABILITY_MAJOR_NV);
        info.nv_compute_capability_minor = q.vendor_value(CL_DEVICE_COMPUTE_CAPABILITY_MINOR_NV);
        info.nv_warp_size = q.vendor_value(CL_DEVICE_WARP_SIZE_NV);
        info.nv_registers_per_block = q.vendor_value(CL_DEVICE_REGISTERS_PER_BLOCK_NV);
        info.nv_integrated_memory = q.vendor_flag(CL_DEVICE_INTEGRATED_MEMORY_NV);
        info.nv_kernel_exec_timeout = q.vendor_flag(CL_DEVICE_KERNEL_EXEC_TIMEOUT_NV);
    }
    if (info.has_extension("cl_amd_device_attribute_query")) {
        info.amd_wavefront_width = q.vendor_value(CL_DEVICE_WAVEFRONT_WIDTH_AMD);
        info.amd_simd_per_compute_unit = q.vendor_value(CL_DEVICE_SIMD_PER_COMPUTE_UNIT_AMD);
        info.amd_local_mem_per_compute_unit = q.vendor_value(CL_DEVICE_LOCAL_MEM_SIZE_PER_COMPUTE_UNIT_AMD);
        info.amd_gfxip_major = q.vendor_value(CL_DEVICE_GFXIP_MAJOR_AMD);
        info.amd_gfxip_minor = q.vendor_value(CL_DEVICE_GFXIP_MINOR_AMD);
    }
    return info;
}

struct EnumeratedDevice {
    cl_platform_id platform;
    cl_device_id id;
    DeviceInfo info;
};

std::vector<cl_platform_id> platform_ids() {
    const char* const no_platform =
        "no OpenCL platform was found; install an OpenCL driver, e.g. 'apt install pocl-opencl-icd' "
        "for the CPU, or your GPU vendor's OpenCL ICD";
    cl_uint count = 0;
    const cl_int status = clGetPlatformIDs(0, nullptr, &count);
    if (status == CL_PLATFORM_NOT_FOUND_KHR || (status == CL_SUCCESS && count == 0)) {
        throw ClError(CL_PLATFORM_NOT_FOUND_KHR, "listing OpenCL platforms", no_platform);
    }
    check(status, "listing OpenCL platforms");
    std::vector<cl_platform_id> platforms(count);
    check(clGetPlatformIDs(count, platforms.data(), nullptr), "listing OpenCL platforms");
    return platforms;
}

std::vector<EnumeratedDevice> enumerate_devices() {
    std::vector<EnumeratedDevice> devices;
    const std::vector<cl_platform_id> platforms = platform_ids();
    for (std::size_t p = 0; p < platforms.size(); ++p) {
        cl_uint count = 0;
        const cl_int status = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, nullptr, &count);
        if (status == CL_DEVICE_NOT_FOUND || (status == CL_SUCCESS && count == 0)) {
            continue;
        }
        const std::string doing = fmt::format("listing the devices of platform {}", p);
        check(status, doing);
        std::vector<cl_device_id> ids(count);
        check(clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr), doing);

        const std::string platform_name = platform_string(platforms[p], CL_PLATFORM_NAME, "name", p);
        const std::string platform_vendor = platform_string(platforms[p], CL_PLATFORM_VENDOR, "vendor", p);
        const std::string platform_version = platform_string(platforms[p], CL_PLATFORM_VERSION, "version", p);
        for (cl_device_id id : ids) {
            DeviceInfo info = query_device(id, devices.size());
            info.platform_index = p;
            info.platform_name = platform_name;
            info.platform_vendor = platform_vendor;
            info.platform_version = platform_version;
            devices.push_back({platforms[p], id, std::move(info)});
        }
    }
    return devices;
}

std::string format_bytes(std::uint64_t bytes) {
    constexpr std::uint64_t KiB = 1024;
    constexpr std::uint64_t MiB = KiB * 1024;
    constexpr std::uint64_t GiB = MiB * 1024;
    if (bytes >= GiB) {
        return fmt::format("{:.1f} GiB", static_cast<double>(bytes) / static_cast<double>(GiB));
    }
    if (bytes >= MiB) {
        return fmt::format("{:.1f} MiB", static_cast<double>(bytes) / static_cast<double>(MiB));
    }
    if (bytes >= KiB) {
        return fmt::format("{} KiB", bytes / KiB);
    }
    return fmt::format("{} B", bytes);
}

// The vendor attributes a table line shows, e.g. "CC 9.0, warp 32, 65536 regs/block".
std::string vendor_summary(const DeviceInfo& d) {
    std::vector<std::string> parts;
    if (d.nv_compute_capability_major && d.nv_compute_capability_minor) {
        parts.push_back(fmt::format("CC {}.{}", *d.nv_compute_capability_major, *d.nv_compute_capability_minor));
    }
    if (d.nv_warp_size) {
        parts.push_back(fmt::format("warp {}", *d.nv_warp_size));
    }
    if (d.nv_registers_per_block) {
        parts.push_back(fmt::format("{} regs/block", *d.nv_registers_per_block));
    }
    if (d.amd_gfxip_major && d.amd_gfxip_minor) {
        parts.push_back(fmt::format("gfx{}.{}", *d.amd_gfxip_major, *d.amd_gfxip_minor));
    }
    if (d.amd_wavefront_width) {
        parts.push_back(fmt::format("wave {}", *d.amd_wavefront_width));
    }
    if (d.amd_simd_per_compute_unit) {
        parts.push_back(fmt::format("{} SIMD/CU", *d.amd_simd_per_compute_unit));
    }
    return fmt::format("{}", fmt::join(parts, ", "));
}

// "0 pthread-..., 1 NVIDIA H100 ..." for error messages.
std::string short_list(const std::vector<DeviceInfo>& devices) {
    if (devices.empty()) {
        return "none";
    }
    std::vector<std::string> entries;
    for (const DeviceInfo& d : devices) {
        entries.push_back(fmt::format("{} {}", d.index, d.name));
    }
    return fmt::format("{}", fmt::join(entries, ", "));
}

bool contains_case_insensitive(std::string_view haystack, std::string_view needle) {
    return lower(haystack).find(lower(needle)) != std::string::npos;
}

// Indices (positions in devices) matched by one item of a spec.
std::vector<std::size_t> match_item(std::string_view item, const std::vector<DeviceInfo>& devices) {
    std::vector<std::size_t> matches;
    const auto select_if = [&](auto&& predicate) {
        for (std::size_t i = 0; i < devices.size(); ++i) {
            if (predicate(devices[i])) {
                matches.push_back(i);
            }
        }
    };
    constexpr std::string_view name_prefix = "name:";
    const std::string item_lower = lower(item);
    if (item_lower.starts_with(name_prefix)) {
        const std::string_view text = trim(item.substr(name_prefix.size()));
        if (!text.empty()) {
            select_if([&](const DeviceInfo& d) {
                return contains_case_insensitive(d.name, text) || contains_case_insensitive(d.platform_name, text);
            });
        }
    } else if (std::all_of(item.begin(), item.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        std::size_t index = 0;
        const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), index);
        if (error == std::errc{} && end == item.data() + item.size()) {
            select_if([&](const DeviceInfo& d) { return d.index == index; });
        }
    } else if (item_lower == "all") {
        select_if([](const DeviceInfo&) { return true; });
    } else if (item_lower == "gpu" || item_lower == "cpu" || item_lower == "accelerator") {
        select_if([&](const DeviceInfo& d) { return d.type == item_lower; });
    } else {
        select_if([&](const DeviceInfo& d) {
            return contains_case_insensitive(d.name, item) || contains_case_insensitive(d.platform_name, item);
        });
    }
    return matches;
}

}  // namespace

bool DeviceInfo::has_extension(std::string_view extension) const {
    return std::find(extensions.begin(), extensions.end(), extension) != extensions.end();
}

nlohmann::json DeviceInfo::to_json() const {
    nlohmann::json j = {
        {"index", index},
        {"platform_index", platform_index},
        {"platform_name", platform_name},
        {"platform_vendor", platform_vendor},
        {"platform_version", platform_version},
        {"name", name},
        {"vendor", vendor},
        {"driver_version", driver_version},
        {"device_version", device_version},
        {"opencl_c_version", opencl_c_version},
        {"type", type},
        {"compute_units", compute_units},
        {"max_clock_mhz", max_clock_mhz},
        {"native_float_width", native_float_width},
        {"global_mem_bytes", global_mem_bytes},
        {"max_alloc_bytes", max_alloc_bytes},
        {"local_mem_bytes", local_mem_bytes},
        {"local_mem_type", local_mem_type},
        {"max_work_group_size", max_work_group_size},
        {"max_work_item_sizes", max_work_item_sizes},
        {"correctly_rounded_divide_sqrt", correctly_rounded_divide_sqrt},
        {"fp32_denorms", fp32_denorms},
        {"profiling_timer_resolution_ns", profiling_timer_resolution_ns},
        {"extensions", extensions},
    };
    const auto put = [](nlohmann::json& object, const char* key, const auto& value) {
        if (value) {
            object[key] = *value;
        }
    };
    nlohmann::json nvidia = nlohmann::json::object();
    put(nvidia, "compute_capability_major", nv_compute_capability_major);
    put(nvidia, "compute_capability_minor", nv_compute_capability_minor);
    put(nvidia, "warp_size", nv_warp_size);
    put(nvidia, "registers_per_block", nv_registers_per_block);
    put(nvidia, "integrated_memory", nv_integrated_memory);
    put(nvidia, "kernel_exec_timeout", nv_kernel_exec_timeout);
    if (!nvidia.empty()) {
        j["nvidia"] = std::move(nvidia);
    }
    nlohmann::json amd = nlohmann::json::object();
    put(amd, "wavefront_width", amd_wavefront_width);
    put(amd, "simd_per_compute_unit", amd_simd_per_compute_unit);
    put(amd, "local_mem_per_compute_unit", amd_local_mem_per_compute_unit);
    put(amd, "gfxip_major", amd_gfxip_major);
    put(amd, "gfxip_minor", amd_gfxip_minor);
    if (!amd.empty()) {
        j["amd"] = std::move(amd);
    }
    return j;
}

std::vector<DeviceInfo> list_devices() {
    std::vector<DeviceInfo> infos;
    for (EnumeratedDevice& d : enumerate_devices()) {
        infos.push_back(std::move(d.info));
    }
    return infos;
}

std::string devices_table(const std::vector<DeviceInfo>& devices) {
    const std::vector<std::string> header = {"#",  "type",      "name",      "platform",  "CUs",   "clock",
                                             "global mem", "local mem", "max WG", "driver", "vendor attributes"};
    std::vector<std::vector<std::string>> rows = {header};
    for (const DeviceInfo& d : devices) {
        rows.push_back({std::to_string(d.index), d.type, d.name, d.platform_name, std::to_string(d.compute_units),
                        fmt::format("{} MHz", d.max_clock_mhz), format_bytes(d.global_mem_bytes),
                        format_bytes(d.local_mem_bytes), std::to_string(d.max_work_group_size), d.driver_version,
                        vendor_summary(d)});
    }
    std::vector<std::size_t> widths(header.size(), 0);
    for (const auto& row : rows) {
        for (std::size_t c = 0; c < row.size(); ++c) {
            widths[c] = std::max(widths[c], row[c].size());
        }
    }
    std::string table;
    for (const auto& row : rows) {
        std::string line;
        for (std::size_t c = 0; c < row.size(); ++c) {
            line += fmt::format("{:<{}}", row[c], widths[c]);
            line += "  ";
        }
        table += trim(line);
        table += '\n';
    }
    return table;
}

std::vector<std::size_t> select_devices(std::string_view spec, const std::vector<DeviceInfo>& devices) {
    std::string text(trim(spec));
    std::string origin;
    if (text.empty()) {
        const char* env = std::getenv(kDeviceEnv);
        if (env != nullptr && !trim(env).empty()) {
            text = trim(env);
            origin = fmt::format("from {}={}; ", kDeviceEnv, text);
        }
    }
    if (text.empty()) {
        if (devices.empty()) {
            throw InputError("no OpenCL device found");
        }
        const auto gpu = std::find_if(devices.begin(), devices.end(), [](const DeviceInfo& d) { return d.type == "gpu"; });
        return {gpu != devices.end() ? gpu->index : devices.front().index};
    }

    std::vector<bool> chosen(devices.size(), false);
    std::string_view rest = text;
    while (true) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = trim(rest.substr(0, comma));
        if (item.empty()) {
            throw InputError(fmt::format("empty item in the device spec '{}' ({}devices: {})", text, origin,
                                         short_list(devices)));
        }
        const std::vector<std::size_t> matches = match_item(item, devices);
        if (matches.empty()) {
            throw InputError(fmt::format("no OpenCL device matches '{}' ({}devices: {})", item, origin,
                                         short_list(devices)));
        }
        for (std::size_t i : matches) {
            chosen[i] = true;
        }
        if (comma == std::string_view::npos) {
            break;
        }
        rest.remove_prefix(comma + 1);
    }
    std::vector<std::size_t> indices;
    for (std::size_t i = 0; i < devices.size(); ++i) {
        if (chosen[i]) {
            indices.push_back(devices[i].index);
        }
    }
    return indices;
}

Device::Device(DeviceInfo info, cl_device_id id, Context context)
    : info_(std::move(info)), id_(id), context_(std::move(context)) {
    cl_int status = CL_SUCCESS;
    queue_ = Queue(clCreateCommandQueue(context_.get(), id_, CL_QUEUE_PROFILING_ENABLE, &status));
    check(status, fmt::format("creating the profiling command queue of device {} ({})", info_.index, info_.name));
}

Device::~Device() = default;
Device::Device(Device&&) noexcept = default;
Device& Device::operator=(Device&&) noexcept = default;

void Device::finish() {
    check(clFinish(queue_.get()), [&] { return fmt::format("waiting for the queue of {} to finish", info_.name); });
}

const Program* Device::find_program(std::string_view key) const {
    const auto it = std::find_if(programs_.begin(), programs_.end(),
                                 [&](const Program& p) { return p.record().key == key; });
    return it != programs_.end() ? &*it : nullptr;
}

const std::string* Device::program_key(std::string_view request) const {
    const auto it = program_keys_.find(request);
    return it != program_keys_.end() ? &it->second : nullptr;
}

void Device::remember_program_key(std::string request, std::string key) {
    program_keys_.insert_or_assign(std::move(request), std::move(key));
}

const Program* Device::find_program(cl_program handle) const {
    const auto it = std::find_if(programs_.begin(), programs_.end(),
                                 [&](const Program& p) { return p.get() == handle; });
    return it != programs_.end() ? &*it : nullptr;
}

void Device::remember_program(const Program& program) {
    if (find_program(program.record().key) == nullptr) {
        programs_.push_back(program);
    }
}

DeviceSet DeviceSet::open(std::string_view spec) {
    std::vector<EnumeratedDevice> all = enumerate_devices();
    std::vector<DeviceInfo> infos;
    for (const EnumeratedDevice& d : all) {
        infos.push_back(d.info);
    }
    const std::vector<std::size_t> selected = select_devices(spec, infos);

    // One context per device: the devices share no buffer, and a program made in a context of one
    // device has one binary (in a context of several, PoCL 3 reports no binary for all but one).
    std::vector<Device> devices;
    devices.reserve(selected.size());
    for (std::size_t i : selected) {
        const cl_context_properties properties[] = {
            CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(all[i].platform), 0};
        cl_int status = CL_SUCCESS;
        Context context(clCreateContext(properties, 1, &all[i].id, nullptr, nullptr, &status));
        check(status, fmt::format("creating a context for device {} ({})", i, all[i].info.name));
        devices.emplace_back(std::move(all[i].info), all[i].id, std::move(context));
    }
    return DeviceSet(std::move(devices));
}

}  // namespace sdfbrick::ocl
