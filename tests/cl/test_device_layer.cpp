// Tests of the OpenCL device layer (host/cl): error names, device selection, devices and queues,
// kernel sources with includes, programs and their caches, buffers, arguments and launches.
#include <gtest/gtest.h>

#include <CL/cl.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <optional>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cl/buffer.h"
#include "cl/cl_error.h"
#include "cl/device.h"
#include "cl/kernel_source.h"
#include "cl/launch.h"
#include "cl/program.h"
#include "core/errors.h"
#include "core/files.h"
#include "test_support.h"

namespace sdfbrick::ocl {
namespace {

using test::ScopedEnv;

// Reads kernels from dir for the scope's lifetime.
class ScopedKernelDir {
public:
    explicit ScopedKernelDir(const std::filesystem::path& dir) { set_kernel_dir(dir); }
    ~ScopedKernelDir() { set_kernel_dir(std::nullopt); }
    ScopedKernelDir(const ScopedKernelDir&) = delete;
    ScopedKernelDir& operator=(const ScopedKernelDir&) = delete;
};

std::size_t count_of(const std::string& text, const std::string& part) {
    std::size_t count = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) {
        ++count;
    }
    return count;
}

// ---------------------------------------------------------------------------------------------- errors

TEST(ClErrors, NamesKnownAndUnknownCodes) {
    EXPECT_STREQ(error_name(CL_SUCCESS), "CL_SUCCESS");
    EXPECT_STREQ(error_name(CL_OUT_OF_RESOURCES), "CL_OUT_OF_RESOURCES");
    EXPECT_STREQ(error_name(-11), "CL_BUILD_PROGRAM_FAILURE");
    EXPECT_STREQ(error_name(-68), "CL_INVALID_DEVICE_PARTITION_COUNT");
    EXPECT_STREQ(error_name(-1001), "CL_PLATFORM_NOT_FOUND_KHR");
    EXPECT_STREQ(error_name(12345), "unknown OpenCL error");
    EXPECT_STREQ(error_name(-20), "unknown OpenCL error");
}

TEST(ClErrors, MessageSaysWhatWasBeingDone) {
    const ClError error(CL_OUT_OF_RESOURCES, "enqueueing kernel eval_points on pthread-cpu");
    EXPECT_STREQ(error.what(), "OpenCL error CL_OUT_OF_RESOURCES (-5) while enqueueing kernel eval_points on pthread-cpu");
    EXPECT_EQ(error.code(), CL_OUT_OF_RESOURCES);
    EXPECT_EQ(error.doing(), "enqueueing kernel eval_points on pthread-cpu");
    EXPECT_STREQ(ClError(CL_INVALID_VALUE, "x", "some detail").what(),
                 "OpenCL error CL_INVALID_VALUE (-30) while x: some detail");

    EXPECT_NO_THROW(check(CL_SUCCESS, "nothing"));
    EXPECT_NO_THROW(check(CL_SUCCESS, []() -> std::string { throw std::logic_error("described on success"); }));
    EXPECT_THROW(check(CL_INVALID_VALUE, [] { return std::string("lazily described"); }), ClError);
    try {
        check(CL_INVALID_KERNEL, "launching k");
        FAIL() << "check did not throw";
    } catch (const ClError& e) {
        EXPECT_EQ(e.code(), CL_INVALID_KERNEL);
        EXPECT_EQ(e.doing(), "launching k");
    }
}

TEST(ClHandles, CopyRetainsMoveTransfersDestructorReleases) {
    Device& device = test::device();
    cl_int status = CL_SUCCESS;
    MemObject original(clCreateBuffer(device.context(), CL_MEM_READ_WRITE, 64, nullptr, &status));
    ASSERT_EQ(status, CL_SUCCESS);
    const auto references = [](const MemObject& m) {
        cl_uint count = 0;
        EXPECT_EQ(clGetMemObjectInfo(m.get(), CL_MEM_REFERENCE_COUNT, sizeof(count), &count, nullptr), CL_SUCCESS);
        return count;
    };
    EXPECT_EQ(references(original), 1u);
    {
        const MemObject copy = original;
        EXPECT_EQ(copy.get(), original.get());
        EXPECT_EQ(references(original), 2u);
        MemObject moved = std::move(original);
        EXPECT_FALSE(original);  // NOLINT(bugprone-use-after-move): a moved-from handle is empty
        EXPECT_EQ(references(moved), 2u);
        original = std::move(moved);
    }
    EXPECT_EQ(references(original), 1u);
}

// ------------------------------------------------------------------------------------------- selection

DeviceInfo fake(std::size_t index, std::string type, std::string name, std::string platform, std::size_t platform_index) {
    DeviceInfo d;
    d.index = index;
    d.type = std::move(type);
    d.name = std::move(name);
    d.platform_name = std::move(platform);
    d.platform_index = platform_index;
    return d;
}

const std::vector<DeviceInfo>& fake_devices() {
    static const std::vector<DeviceInfo> devices = {
        fake(0, "cpu", "pthread-skylake-avx512", "Portable Computing Language", 0),
        fake(1, "gpu", "NVIDIA H100 80GB HBM3", "NVIDIA CUDA", 1),
        fake(2, "gpu", "gfx1100 Radeon RX 7900", "AMD Accelerated Parallel Processing", 2),
        fake(3, "accelerator", "Intel FPGA Emulation Device", "Intel(R) FPGA Emulation Platform", 3),
    };
    return devices;
}

using Indices = std::vector<std::size_t>;

TEST(ClDeviceSelection, IndicesTypesAndNames) {
    const ScopedEnv no_env(kDeviceEnv, std::nullopt);
    const auto& d = fake_devices();
    EXPECT_EQ(select_devices("0", d), (Indices{0}));
    EXPECT_EQ(select_devices("3", d), (Indices{3}));
    EXPECT_EQ(select_devices("gpu", d), (Indices{1, 2}));
    EXPECT_EQ(select_devices("GPU", d), (Indices{1, 2}));
    EXPECT_EQ(select_devices("cpu", d), (Indices{0}));
    EXPECT_EQ(select_devices("accelerator", d), (Indices{3}));
    EXPECT_EQ(select_devices("all", d), (Indices{0, 1, 2, 3}));
    EXPECT_EQ(select_devices("h100", d), (Indices{1}));
    EXPECT_EQ(select_devices("Portable", d), (Indices{0}));     // platform name
    EXPECT_EQ(select_devices("nvidia cuda", d), (Indices{1}));  // platform name, any case
    EXPECT_EQ(select_devices("name:RADEON", d), (Indices{2}));
    EXPECT_EQ(select_devices("name: 80GB", d), (Indices{1}));
}

TEST(ClDeviceSelection, ListsAreUniqueAndInEnumerationOrder) {
    const ScopedEnv no_env(kDeviceEnv, std::nullopt);
    const auto& d = fake_devices();
    EXPECT_EQ(select_devices("2,0", d), (Indices{0, 2}));
    EXPECT_EQ(select_devices(" 1 , 0 ", d), (Indices{0, 1}));
    EXPECT_EQ(select_devices("gpu,1,h100", d), (Indices{1, 2}));
    EXPECT_EQ(select_devices("all,cpu", d), (Indices{0, 1, 2, 3}));
}

void expect_input_error(std::string_view spec, const std::vector<DeviceInfo>& devices,
                        const std::vector<std::string>& expected_parts) {
    try {
        select_devices(spec, devices);
        ADD_FAILURE() << "spec '" << spec << "' was accepted";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        for (const std::string& part : expected_parts) {
            EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
        }
    }
}

TEST(ClDeviceSelection, UnmatchedItemsAreInputErrors) {
    const ScopedEnv no_env(kDeviceEnv, std::nullopt);
    const auto& d = fake_devices();
    expect_input_error("foo", d,
                       {"no OpenCL device matches 'foo'", "0 pthread-skylake-avx512", "1 NVIDIA H100 80GB HBM3"});
    expect_input_error("4", d, {"no OpenCL device matches '4'"});
    expect_input_error("99999999999999999999999", d, {"no OpenCL device matches '99999999999999999999999'"});
    expect_input_error("0,foo", d, {"'foo'"});
    expect_input_error("0,,1", d, {"empty item"});
    expect_input_error("name:gpu", d, {"'name:gpu'"});  // "name:" matches names only, not types
}

TEST(ClDeviceSelection, EmptySpecUsesEnvironmentThenFirstGpu) {
    const auto& d = fake_devices();
    {
        const ScopedEnv no_env(kDeviceEnv, std::nullopt);
        EXPECT_EQ(select_devices("", d), (Indices{1}));
        EXPECT_EQ(select_devices("  ", d), (Indices{1}));
        const std::vector<DeviceInfo> no_gpu = {d[0], d[3]};
        EXPECT_EQ(select_devices("", no_gpu), (Indices{0}));
    }
    {
        const ScopedEnv env(kDeviceEnv, "cpu,3");
        EXPECT_EQ(select_devices("", d), (Indices{0, 3}));
        EXPECT_EQ(select_devices("2", d), (Indices{2}));  // an explicit spec wins
    }
    {
        const ScopedEnv env(kDeviceEnv, "");
        EXPECT_EQ(select_devices("", d), (Indices{1}));
    }
    {
        const ScopedEnv env(kDeviceEnv, "bogus");
        expect_input_error("", d, {"no OpenCL device matches 'bogus'", "SDFBRICK_DEVICE"});
    }
}

// ------------------------------------------------------------------------------------- devices, queues

TEST(ClDevices, ListFindsDevicesWithSaneFacts) {
    const std::vector<DeviceInfo> devices = list_devices();
    ASSERT_FALSE(devices.empty());
    for (std::size_t i = 0; i < devices.size(); ++i) {
        const DeviceInfo& d = devices[i];
        EXPECT_EQ(d.index, i);
        EXPECT_FALSE(d.name.empty());
        EXPECT_FALSE(d.platform_name.empty());
        EXPECT_TRUE(d.type == "gpu" || d.type == "cpu" || d.type == "accelerator" || d.type == "other") << d.type;
        EXPECT_GT(d.compute_units, 0u);
        EXPECT_GT(d.global_mem_bytes, 0u);
        EXPECT_GT(d.max_alloc_bytes, 0u);
        EXPECT_GT(d.max_work_group_size, 0u);
        EXPECT_FALSE(d.max_work_item_sizes.empty());
        EXPECT_FALSE(d.extensions.empty());
        // Vendor attributes exist only where the vendor extension is listed.
        const bool any_nv = d.nv_compute_capability_major || d.nv_compute_capability_minor || d.nv_warp_size ||
                            d.nv_registers_per_block || d.nv_integrated_memory || d.nv_kernel_exec_timeout;
        const bool any_amd = d.amd_wavefront_width || d.amd_simd_per_compute_unit ||
                             d.amd_local_mem_per_compute_unit || d.amd_gfxip_major || d.amd_gfxip_minor;
        EXPECT_TRUE(!any_nv || d.has_extension("cl_nv_device_attribute_query"));
        EXPECT_TRUE(!any_amd || d.has_extension("cl_amd_device_attribute_query"));

        const nlohmann::json j = d.to_json();
        EXPECT_EQ(j.at("name"), d.name);
        EXPECT_EQ(j.at("compute_units"), d.compute_units);
        EXPECT_EQ(j.at("extensions").size(), d.extensions.size());
        EXPECT_EQ(j.contains("nvidia"), any_nv);
        EXPECT_EQ(j.contains("amd"), any_amd);
    }
    const std::string table = devices_table(devices);
    EXPECT_EQ(table.rfind("#", 0), 0u) << table;
    EXPECT_NE(table.find("CUs"), std::string::npos) << table;
    EXPECT_NE(table.find(devices[0].name), std::string::npos) << table;
    EXPECT_EQ(static_cast<std::size_t>(std::count(table.begin(), table.end(), '\n')), devices.size() + 1) << table;
}

TEST(ClDevices, OpenCpuSetHasProfilingQueues) {
    DeviceSet set = DeviceSet::open("cpu");
    ASSERT_GE(set.size(), 1u);
    std::size_t visited = 0;
    set.for_each([&](Device& device) {
        ++visited;
        EXPECT_EQ(device.info().type, "cpu");
        cl_command_queue_properties properties = 0;
        ASSERT_EQ(clGetCommandQueueInfo(device.queue(), CL_QUEUE_PROPERTIES, sizeof(properties), &properties, nullptr),
                  CL_SUCCESS);
        EXPECT_NE(properties & CL_QUEUE_PROFILING_ENABLE, 0u);
        cl_context context = nullptr;
        ASSERT_EQ(clGetCommandQueueInfo(device.queue(), CL_QUEUE_CONTEXT, sizeof(context), &context, nullptr),
                  CL_SUCCESS);
        EXPECT_EQ(context, device.context());
        device.finish();
    });
    EXPECT_EQ(visited, set.size());
    // Devices of one platform share one context.
    for (const Device& device : set) {
        EXPECT_TRUE(set[0].info().platform_index != device.info().platform_index ||
                    set[0].context() == device.context());
    }
}

TEST(ClDevices, KernelLaunchIsProfiled) {
    Device& device = test::device();
    const Program program = build_program(device, "test_layer.cl");
    const Kernel kernel = make_kernel(program, "scale_add");

    constexpr std::uint32_t n = 1000;
    std::vector<float> input(n);
    std::iota(input.begin(), input.end(), 0.0f);
    Buffer<float> in(device, std::span<const float>(input), CL_MEM_READ_ONLY);
    Buffer<float> out(device, n, CL_MEM_WRITE_ONLY);
    set_args(kernel.get(), in, out, 2.0f, 0.5f, n);
    const Event event = enqueue(device, kernel.get(), "scale_add", 1024, 64);
    const EventTimes times = event_times(event);
    EXPECT_GE(times.queued_to_start_ms, 0.0);
    EXPECT_GE(times.submit_to_start_ms, 0.0);
    EXPECT_GE(times.start_to_end_ms, 0.0);
    EXPECT_LE(times.submit_to_start_ms, times.queued_to_start_ms);

    const std::vector<float> result = out.read();
    for (std::uint32_t i = 0; i < n; ++i) {
        ASSERT_EQ(result[i], static_cast<float>(i) * 2.0f + 0.5f) << i;
    }
}

TEST(ClDevices, LocalMemoryAnd2DLaunch) {
    Device& device = test::device();
    const Kernel kernel = make_kernel(build_program(device, "test_layer.cl"), "reverse_groups");
    constexpr std::size_t group = 16;
    std::vector<std::uint32_t> input(4 * group);
    std::iota(input.begin(), input.end(), 0u);
    Buffer<std::uint32_t> in(device, std::span<const std::uint32_t>(input));
    Buffer<std::uint32_t> out(device, input.size());
    set_args(kernel.get(), in, out, LocalMemory{group * sizeof(std::uint32_t)});
    event_times(enqueue(device, kernel.get(), "reverse_groups", {input.size(), 1, 1},
                        std::array<std::size_t, 3>{group, 1, 1}, 2));
    const std::vector<std::uint32_t> result = out.read();
    for (std::size_t i = 0; i < input.size(); ++i) {
        const std::size_t base = i / group * group;
        ASSERT_EQ(result[i], input[base + group - 1 - (i - base)]) << i;
    }
}

TEST(ClDevices, EmptyLaunchGivesAValidEvent) {
    Device& device = test::device();
    const Kernel kernel = make_kernel(build_program(device, "test_layer.cl"), "scale_add");
    Buffer<float> empty(device, 0);
    set_args(kernel.get(), empty, empty, 1.0f, 0.0f, 0u);
    const EventTimes times = event_times(enqueue(device, kernel.get(), "scale_add", 0));
    EXPECT_GE(times.start_to_end_ms, 0.0);
}

TEST(ClDevices, BadLaunchNamesKernelAndSizes) {
    Device& device = test::device();
    const Kernel kernel = make_kernel(build_program(device, "test_layer.cl"), "scale_add");
    Buffer<float> buffer(device, 8);
    set_args(kernel.get(), buffer, buffer, 1.0f, 0.0f, 8u);
    try {
        enqueue(device, kernel.get(), "my_stage", 10, 4);  // 10 is not a multiple of 4 in OpenCL 1.2
        FAIL() << "the launch was accepted";
    } catch (const ClError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("my_stage"), std::string::npos) << message;
        EXPECT_NE(message.find("global 10, local 4"), std::string::npos) << message;
        EXPECT_NE(message.find(device.info().name), std::string::npos) << message;
    }
    EXPECT_THROW(enqueue(device, kernel.get(), "my_stage", {8, 1, 1}, std::nullopt, 4), ClError);
}

// ------------------------------------------------------------------------------------- kernel sources

TEST(ClKernelSources, IncludesAreExpandedOnceWithLineDirectives) {
    const std::filesystem::path dir = test::temp_dir("device_layer_includes");
    test::write_text(dir / "a.cl", "#include \"b.h\"\n#include \"b.h\"  // twice\nA_MARK\n");
    test::write_text(dir / "b.h", "B_MARK\n  #  include \"c.h\"\nB_END\n");
    test::write_text(dir / "c.h", "C_MARK\n#include \"b.h\"\n");  // a cycle back to b.h
    const ScopedKernelDir kernels(dir);

    const std::string source = load_kernel_source("a.cl");
    EXPECT_EQ(count_of(source, "B_MARK"), 1u) << source;
    EXPECT_EQ(count_of(source, "C_MARK"), 1u) << source;
    EXPECT_EQ(count_of(source, "A_MARK"), 1u) << source;
    const std::string expected = "#line 1 \"a.cl\"\n"
                                 "#line 1 \"b.h\"\n"
                                 "B_MARK\n"
                                 "#line 1 \"c.h\"\n"
                                 "C_MARK\n"
                                 "// #include \"b.h\": already included above\n"
                                 "#line 3 \"b.h\"\n"
                                 "B_END\n"
                                 "#line 2 \"a.cl\"\n"
                                 "// #include \"b.h\": already included above\n"
                                 "A_MARK\n";
    EXPECT_EQ(source, expected);
}

TEST(ClKernelSources, MissingFilesSayWhereTheyWereLookedFor) {
    const std::filesystem::path dir = test::temp_dir("device_layer_missing");
    test::write_text(dir / "a.cl", "// first line\n#include \"missing.h\"\n");
    {
        const ScopedKernelDir kernels(dir);
        try {
            load_kernel_source("a.cl");
            FAIL() << "a missing include was accepted";
        } catch (const std::runtime_error& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("'missing.h'"), std::string::npos) << message;
            EXPECT_NE(message.find("a.cl:2"), std::string::npos) << message;
            EXPECT_NE(message.find(dir.string()), std::string::npos) << message;
        }
    }
    try {
        load_kernel_source("no_such_kernel.cl");
        FAIL() << "a missing embedded file was accepted";
    } catch (const std::runtime_error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'no_such_kernel.cl'"), std::string::npos) << message;
        EXPECT_NE(message.find("embedded"), std::string::npos) << message;
    }
}

TEST(ClKernelSources, TestKernelsAreNotShipped) {
    for (const auto& [name, text] : embedded_kernel_sources()) {
        EXPECT_NE(name, "test_layer.cl");
        EXPECT_NE(name, "layout_probe.cl");
    }
    EXPECT_NE(load_kernel_source("layout_probe.cl").find("__kernel"), std::string::npos);
}

TEST(ClKernelSources, EnvironmentDirectoryAndEmbeddedSet) {
    const ScopedEnv no_env(kKernelDirEnv, std::nullopt);
    EXPECT_FALSE(kernel_dir().has_value());
    EXPECT_NE(load_kernel_source("test_layer.cl").find("__kernel void scale_add"), std::string::npos);

    const std::filesystem::path dir = test::temp_dir("device_layer_env_dir");
    test::write_text(dir / "test_layer.cl", "ON_DISK\n");
    const ScopedEnv env(kKernelDirEnv, dir.string());
    EXPECT_EQ(kernel_dir(), dir);
    EXPECT_EQ(load_kernel_source("test_layer.cl"), "#line 1 \"test_layer.cl\"\nON_DISK\n");
}

// ------------------------------------------------------------------------------------------- programs

constexpr const char* kProbeKernel = "__kernel void probe(__global float* out) {\n"
                                     "    out[get_global_id(0)] = PROBE_VALUE;\n"
                                     "}\n";

std::string read_bytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs probe on a fresh device and returns out[0].
float run_probe(Device& device, const Program& program) {
    const Kernel kernel = make_kernel(program, "probe");
    Buffer<float> out(device, 1);
    set_args(kernel.get(), out);
    event_times(enqueue(device, kernel.get(), "probe", 1));
    return out.read()[0];
}

TEST(ClPrograms, RebuildHitsMemoryThenDiskCache) {
    const std::filesystem::path dir = test::temp_dir("device_layer_cache");
    test::write_text(dir / "kernels" / "probe.cl", std::string("#define PROBE_VALUE 3.5f\n") + kProbeKernel);
    const ScopedKernelDir kernels(dir / "kernels");
    const ScopedEnv cache(kCacheDirEnv, (dir / "cache").string());
    ASSERT_EQ(program_cache_dir(), dir / "cache");

    DeviceSet first = test::open_test_devices();
    const Program compiled = build_program(first[0], "probe.cl");
    EXPECT_EQ(compiled.record().origin, ProgramOrigin::compiled);
    EXPECT_FALSE(compiled.record().from_cache());
    EXPECT_TRUE(compiled.record().cache_note.empty()) << compiled.record().cache_note;
    ASSERT_TRUE(compiled.record().cache_file.has_value());
    EXPECT_TRUE(std::filesystem::is_regular_file(*compiled.record().cache_file));
    EXPECT_EQ(compiled.record().cache_file->parent_path(), dir / "cache");
    EXPECT_EQ(compiled.record().key.size(), 16u);
    EXPECT_EQ(compiled.record().kernel_file, "probe.cl");
    EXPECT_EQ(compiled.record().device_name, first[0].info().name);
    EXPECT_GT(compiled.record().build_ms, 0.0);
    EXPECT_EQ(compiled.record().correctly_rounded_divide_sqrt, first[0].info().correctly_rounded_divide_sqrt);
    EXPECT_EQ(compiled.record().options.find("-cl-fp32-correctly-rounded-divide-sqrt") != std::string::npos,
              first[0].info().correctly_rounded_divide_sqrt);
    EXPECT_EQ(compiled.record().options.rfind("-cl-std=CL1.2", 0), 0u) << compiled.record().options;

    const Program again = build_program(first[0], "probe.cl");
    EXPECT_EQ(again.record().origin, ProgramOrigin::memory_cache);
    EXPECT_EQ(again.get(), compiled.get());
    EXPECT_EQ(again.record().key, compiled.record().key);

    DeviceSet second = test::open_test_devices();
    const Program cached = build_program(second[0], "probe.cl");
    EXPECT_EQ(cached.record().origin, ProgramOrigin::disk_cache);
    EXPECT_TRUE(cached.record().from_cache());
    EXPECT_EQ(cached.record().key, compiled.record().key);
    EXPECT_EQ(run_probe(second[0], cached), 3.5f);

    // Other options, other key.
    const Program defined = build_program(second[0], "probe.cl", "-DUNUSED_DEFINE=1");
    EXPECT_EQ(defined.record().origin, ProgramOrigin::compiled);
    EXPECT_NE(defined.record().key, compiled.record().key);
    EXPECT_NE(defined.record().options.find("-DUNUSED_DEFINE=1"), std::string::npos);
}

TEST(ClPrograms, DamagedCacheEntriesFallBackToSource) {
    const std::filesystem::path dir = test::temp_dir("device_layer_corrupt");
    test::write_text(dir / "kernels" / "probe.cl", std::string("#define PROBE_VALUE 7.0f\n") + kProbeKernel);
    const ScopedKernelDir kernels(dir / "kernels");
    const ScopedEnv cache(kCacheDirEnv, (dir / "cache").string());

    std::filesystem::path file;
    std::string key;
    {
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        ASSERT_TRUE(program.record().cache_file.has_value());
        file = *program.record().cache_file;
        key = program.record().key;
    }
    DeviceSet opened = test::open_test_devices();
    const std::optional<CacheSeal> seal = cache_seal(opened[0], "probe.cl");
    ASSERT_TRUE(seal.has_value());
    const std::vector<std::string> damaged = {
        "garbage",                                                        // not an entry
        encode_cache_entry({key, "log", "not a program binary"}, *seal),  // a sealed entry, a bad binary
        encode_cache_entry({"0123456789abcdef", "", "x"}, *seal),         // an entry for another key
    };
    for (const std::string& bytes : damaged) {
        test::write_text(file, bytes);
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        EXPECT_EQ(program.record().origin, ProgramOrigin::compiled);
        EXPECT_NE(program.record().cache_note.find("discarded cache entry"), std::string::npos)
            << program.record().cache_note;
        EXPECT_EQ(run_probe(set[0], program), 7.0f);
        // The rebuilt binary replaced the damaged entry.
        const std::optional<CacheEntry> entry = decode_cache_entry(read_bytes(file), *seal);
        ASSERT_TRUE(entry.has_value());
        EXPECT_EQ(entry->key, key);
    }
}

// An entry forged without the cache's secret (a valid header, a random binary, a MAC under a guessed
// key) never reaches the driver (PoCL aborts on some random binaries); a correctly sealed binary of
// another program is refused by its kernel names. Both fall back to a build from source.
TEST(ClPrograms, ForgedOrForeignCacheEntriesNeverRun) {
    const std::filesystem::path dir = test::temp_dir("device_layer_forged");
    test::write_text(dir / "kernels" / "probe.cl", std::string("#define PROBE_VALUE 5.0f\n") + kProbeKernel);
    test::write_text(dir / "kernels" / "other.cl", "__kernel void other(__global float* out) { out[0] = 1.0f; }\n");
    const ScopedKernelDir kernels(dir / "kernels");
    const ScopedEnv cache(kCacheDirEnv, (dir / "cache").string());
    std::filesystem::path file, other_file;
    std::optional<CacheSeal> seal, other_seal;
    std::string key;
    {
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        const Program other = build_program(set[0], "other.cl");
        file = *program.record().cache_file;
        other_file = *other.record().cache_file;
        key = program.record().key;
        seal = cache_seal(set[0], "probe.cl");
        other_seal = cache_seal(set[0], "other.cl");
        ASSERT_TRUE(seal && other_seal);
    }
    std::mt19937_64 random(7);
    std::string noise(100000, '\0');
    for (char& c : noise) c = static_cast<char>(random());
    const std::optional<CacheEntry> foreign = decode_cache_entry(read_bytes(other_file), *other_seal);
    ASSERT_TRUE(foreign.has_value());
    const std::vector<std::pair<std::string, std::string>> entries = {
        {"forged", encode_cache_entry({key, "", noise}, CacheSeal{0, 0, seal->identity})},
        {"foreign", encode_cache_entry({key, "", foreign->binary}, *seal)},
    };
    for (const auto& [what, bytes] : entries) {
        test::write_text(file, bytes);
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        EXPECT_EQ(program.record().origin, ProgramOrigin::compiled) << what;
        EXPECT_NE(program.record().cache_note.find("discarded cache entry"), std::string::npos)
            << what << ": " << program.record().cache_note;
        EXPECT_EQ(run_probe(set[0], program), 5.0f) << what;
    }
}

// The cache's folder is private: made 0700 when missing. A folder others can enter is never changed:
// the entries go to a private subfolder made in it. A file at the key's name that is not a key is
// never replaced (it may be someone's own): the disk cache is not used.
TEST(ClPrograms, CacheDirectoryIsPrivateAndNeverChanged) {
    const std::filesystem::path dir = test::temp_dir("device_layer_private");
    test::write_text(dir / "kernels" / "probe.cl", std::string("#define PROBE_VALUE 2.0f\n") + kProbeKernel);
    const ScopedKernelDir kernels(dir / "kernels");
    namespace fs = std::filesystem;
    {
        const ScopedEnv cache(kCacheDirEnv, (dir / "cache").string());
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        EXPECT_TRUE(program.record().cache_note.empty()) << program.record().cache_note;
        EXPECT_EQ(fs::status(dir / "cache").permissions() & fs::perms::all, fs::perms::owner_all);
        EXPECT_EQ(fs::status(dir / "cache" / "secret").permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
    }
    {  // a shared folder (mode 1777) holding someone's file named like the key
        fs::create_directories(dir / "shared");
        fs::permissions(dir / "shared", fs::perms::all | fs::perms::sticky_bit);
        test::write_text(dir / "shared" / "secret", "not a key\n");
        const ScopedEnv cache(kCacheDirEnv, (dir / "shared").string());
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        EXPECT_TRUE(program.record().cache_note.empty()) << program.record().cache_note;
        EXPECT_EQ(fs::status(dir / "shared").permissions(), fs::perms::all | fs::perms::sticky_bit);
        EXPECT_EQ(read_file(dir / "shared" / "secret"), "not a key\n");
        ASSERT_TRUE(program.record().cache_file.has_value());
        const fs::path private_dir = program.record().cache_file->parent_path();
        EXPECT_EQ(private_dir.parent_path(), dir / "shared");
        EXPECT_EQ(fs::symlink_status(private_dir).permissions() & fs::perms::all, fs::perms::owner_all);
        EXPECT_EQ(run_probe(set[0], program), 2.0f);
    }
    {  // a private folder of the user's own, with a file named like the key that is not one
        fs::create_directories(dir / "mine");
        fs::permissions(dir / "mine", fs::perms::owner_all, fs::perm_options::replace);
        test::write_text(dir / "mine" / "secret", "my own notes\n");
        const ScopedEnv cache(kCacheDirEnv, (dir / "mine").string());
        DeviceSet set = test::open_test_devices();
        const Program program = build_program(set[0], "probe.cl");
        EXPECT_EQ(program.record().origin, ProgramOrigin::compiled);
        EXPECT_NE(program.record().cache_note.find("not a cache key"), std::string::npos) << program.record().cache_note;
        EXPECT_FALSE(program.record().cache_file.has_value());
        EXPECT_EQ(read_file(dir / "mine" / "secret"), "my own notes\n");
        EXPECT_EQ(run_probe(set[0], program), 2.0f);
    }
}

TEST(ClPrograms, DiskCacheCanBeSwitchedOff) {
    const std::filesystem::path dir = test::temp_dir("device_layer_cache_off");
    test::write_text(dir / "probe.cl", std::string("#define PROBE_VALUE 1.0f\n") + kProbeKernel);
    const ScopedKernelDir kernels(dir);
    const ScopedEnv cache(kCacheDirEnv, "off");
    EXPECT_FALSE(program_cache_dir().has_value());
    DeviceSet set = test::open_test_devices();
    const Program program = build_program(set[0], "probe.cl");
    EXPECT_EQ(program.record().origin, ProgramOrigin::compiled);
    EXPECT_FALSE(program.record().cache_file.has_value());
}

TEST(ClPrograms, CacheDirectoryFollowsTheEnvironment) {
    const ScopedEnv cache(kCacheDirEnv, std::nullopt);
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", "/xdg");
        EXPECT_EQ(program_cache_dir(), std::filesystem::path("/xdg/sdfbrick/programs"));
    }
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", std::nullopt);
        const ScopedEnv home("HOME", "/home/someone");
        EXPECT_EQ(program_cache_dir(), std::filesystem::path("/home/someone/.cache/sdfbrick/programs"));
    }
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", std::nullopt);
        const ScopedEnv home("HOME", std::nullopt);
        EXPECT_FALSE(program_cache_dir().has_value());
    }
}

TEST(ClPrograms, CacheEntriesRoundTripAndRejectDamage) {
    const CacheSeal seal{1, 2, "identity"};
    const CacheEntry entry{"00ff00ff00ff00ff", "warning: x\n", std::string("\0\1binary\n\xff", 10)};
    const std::string bytes = encode_cache_entry(entry, seal);
    const std::optional<CacheEntry> decoded = decode_cache_entry(bytes, seal);
    ASSERT_TRUE(decoded.has_value());
    EXPECT_EQ(decoded->key, entry.key);
    EXPECT_EQ(decoded->log, entry.log);
    EXPECT_EQ(decoded->binary, entry.binary);

    EXPECT_FALSE(decode_cache_entry(bytes.substr(0, bytes.size() - 1), seal).has_value());
    EXPECT_FALSE(decode_cache_entry(bytes + "x", seal).has_value());
    std::string flipped = bytes;
    flipped.back() = static_cast<char>(flipped.back() ^ 1);
    EXPECT_FALSE(decode_cache_entry(flipped, seal).has_value());
    EXPECT_FALSE(decode_cache_entry("", seal).has_value());
    // Another secret or another program's identity: the MAC does not verify.
    EXPECT_FALSE(decode_cache_entry(bytes, CacheSeal{1, 3, "identity"}).has_value());
    EXPECT_FALSE(decode_cache_entry(bytes, CacheSeal{1, 2, "other identity"}).has_value());
}

TEST(ClPrograms, SyntaxErrorReportsFileLineAndLog) {
    const std::filesystem::path dir = test::temp_dir("device_layer_syntax");
    test::write_text(dir / "helper.h", "#define HELPER 1.0f\n");
    test::write_text(dir / "bad.cl", "#include \"helper.h\"\n"
                                     "__kernel void broken(__global float* out) {\n"
                                     "    out[0] = HELPER + undefined_thing;\n"
                                     "}\n");
    const ScopedKernelDir kernels(dir);
    const ScopedEnv cache(kCacheDirEnv, "off");
    Device& device = test::device();
    try {
        build_program(device, "bad.cl", "-DSOME_DEFINE=2");
        FAIL() << "a kernel with a syntax error built";
    } catch (const ClError& e) {
        const std::string message = e.what();
        EXPECT_EQ(e.code(), CL_BUILD_PROGRAM_FAILURE);
        EXPECT_NE(message.find("bad.cl"), std::string::npos) << message;
        EXPECT_NE(message.find("bad.cl:3"), std::string::npos) << message;  // #line kept the line number
        EXPECT_NE(message.find("undefined_thing"), std::string::npos) << message;
        EXPECT_NE(message.find("-DSOME_DEFINE=2"), std::string::npos) << message;
        EXPECT_NE(message.find(device.info().name), std::string::npos) << message;
        EXPECT_NE(message.find("build log"), std::string::npos) << message;
    }
}

TEST(ClPrograms, LogLocationsInTheAssembledSourceAreMappedToFiles) {
    const std::string assembled = "#pragma OPENCL FP_CONTRACT OFF\n"  // 1
                                  "#line 1 \"a.cl\"\n"                // 2
                                  "#line 1 \"b.h\"\n"                 // 3
                                  "int b;\n"                          // 4: b.h:1
                                  "#line 2 \"a.cl\"\n"                // 5
                                  "int x = y;\n";                     // 6: a.cl:2
    EXPECT_EQ(map_log_locations("<kernel>:6:9: error: use of undeclared identifier 'y'\n<kernel>:4:1: note", assembled),
              "a.cl:2:9: error: use of undeclared identifier 'y'\nb.h:1:1: note");
    EXPECT_EQ(map_log_locations("<kernel>:1:1: warning\n<kernel>:99:1: x\nbad.cl:3:1: y", assembled),
              "<kernel>:1:1: warning\n<kernel>:99:1: x\nbad.cl:3:1: y");  // unknown lines stay as they are
}

TEST(ClPrograms, UnsafeOptionsAreRefused) {
    Device& device = test::device();
    EXPECT_THROW(build_program(device, "test_layer.cl", "-cl-fast-relaxed-math"), std::invalid_argument);
    EXPECT_THROW(build_program(device, "test_layer.cl", "-DX=1 -cl-mad-enable"), std::invalid_argument);
    EXPECT_THROW(build_program(device, "test_layer.cl", "-cl-std=CL2.0"), std::invalid_argument);
}

TEST(ClPrograms, UnknownKernelNameListsTheProgramsKernels) {
    const Program program = build_program(test::device(), "test_layer.cl");
    try {
        make_kernel(program, "no_such_kernel");
        FAIL() << "an unknown kernel was created";
    } catch (const ClError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'no_such_kernel'"), std::string::npos) << message;
        EXPECT_NE(message.find("test_layer.cl"), std::string::npos) << message;
        EXPECT_NE(message.find("scale_add"), std::string::npos) << message;
    }
}

// -------------------------------------------------------------------------------- buffers, arguments

TEST(ClBuffers, RoundTripPartialAccessAndZeroCount) {
    Device& device = test::device();
    std::vector<std::int32_t> values(1000);
    std::iota(values.begin(), values.end(), -500);
    Buffer<std::int32_t> buffer(device, values.size());
    EXPECT_EQ(buffer.size(), 1000u);
    EXPECT_EQ(buffer.bytes(), 4000u);
    buffer.write(values);
    EXPECT_EQ(buffer.read(), values);

    const std::vector<std::int32_t> patch = {7, 8, 9};
    buffer.write(patch, 10);
    std::vector<std::int32_t> part(5);
    buffer.read_into(part, 9);
    EXPECT_EQ(part, (std::vector<std::int32_t>{values[9], 7, 8, 9, values[13]}));
    EXPECT_THROW(buffer.write(patch, 998), std::out_of_range);
    EXPECT_THROW(buffer.read_into(part, 996), std::out_of_range);

    Buffer<float> empty(device, 0);
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_EQ(empty.bytes(), 0u);
    EXPECT_NE(empty.get(), nullptr);
    EXPECT_TRUE(empty.read().empty());
    EXPECT_NO_THROW(empty.write({}));
    EXPECT_THROW(empty.write(std::vector<float>{1.0f}), std::out_of_range);
}

TEST(ClBuffers, HugeAllocationSaysHowMuchWasAsked) {
    Device& device = test::device();
    const std::size_t count = static_cast<std::size_t>(device.info().max_alloc_bytes / 4 + 1);
    try {
        Buffer<float> huge(device, count);
        FAIL() << "a buffer larger than the largest allocation was created";
    } catch (const ClError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(std::to_string(count * 4)), std::string::npos) << message;
        EXPECT_NE(message.find(std::to_string(device.info().max_alloc_bytes)), std::string::npos) << message;
    }
}

TEST(ClArguments, ErrorsNameTheArgumentIndexAndKernel) {
    Device& device = test::device();
    const Kernel kernel = make_kernel(build_program(device, "test_layer.cl"), "scale_add");
    Buffer<float> buffer(device, 4);
    try {
        set_args(kernel.get(), buffer, buffer, 1.0f, 2.0f, 4u, 5u);  // one argument too many
        FAIL() << "a sixth argument was accepted";
    } catch (const ClError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("argument 5"), std::string::npos) << message;
        EXPECT_NE(message.find("'scale_add'"), std::string::npos) << message;
    }
    try {
        set_args(kernel.get(), buffer, buffer, 1.0, 2.0f, 4u);  // double for a float parameter
        FAIL() << "an 8-byte value for a float argument was accepted";
    } catch (const ClError& e) {
        EXPECT_EQ(e.code(), CL_INVALID_ARG_SIZE);
        EXPECT_NE(std::string(e.what()).find("argument 2"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace sdfbrick::ocl
