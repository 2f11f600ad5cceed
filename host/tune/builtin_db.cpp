// The compiled-in layer of the tuning database: the values `sdfbrick tune` measured on known devices,
// copied from the reports in docs/measurements (the files each entry names; summary: docs/tuning.md,
// "Tuned values"). Each was a full search of its kernel's configurations over scenes/drops.json, or
// over several scenes (the H100's evaluation: drops, rubble and sculpt_dense, the cost the geometric
// mean of their times). Add an entry only from such a measurement, with its files.
#include <array>
#include <utility>

#include "tune/kernels.h"
#include "tune/tuning_db.h"

namespace sdfbrick::tune {

namespace {

struct Measured {
    const char* device;
    const char* driver;
    const char* vendor;
    const char* platform;
    const char* kernel;
    using Params = std::array<std::pair<const char*, int>, 3>;  // unused pairs have no name
    Params params;
    double time_ms;
    Params default_params;  // the defaults of the time, measured alongside
    double default_ms;
    double brick_size;
    int width, height;  // the traced image (trace_primary); 0 otherwise
    int repeat;
    const char* tuned_at;
    const char* measured;  // where, and the files that hold it
    int space = 30;        // configurations searched (all of them)
    const char* method = "sphere";  // the traced image's in-brick search (trace_primary)
    std::array<const char*, 3> scenes = {"scenes/drops.json"};  // tuned over; unused ones are null
};

constexpr const char* kH100 = "NVIDIA H100 80GB HBM3";
constexpr const char* kH200 = "NVIDIA H200";
constexpr const char* kH100Pocl = "cpu-skylake-avx512-Intel(R) Xeon(R) Processor";
constexpr const char* kHerePocl = "pthread-skylake-avx512-AMD EPYC";
constexpr const char* kPocl = "Portable Computing Language";
constexpr Measured::Params kEvaluateDefault = {{{"chunk", 64}, {"group", 128}}};
constexpr Measured::Params kTraceDefault = {{{"group_x", 16}, {"group_y", 8}}};
constexpr const char* kH100Files =
    "H100 machine, NVIDIA OpenCL; docs/measurements/tuning-h100.json, h100-tune-nvidia.txt";
constexpr const char* kH100ScenesFiles =
    "H100 machine, NVIDIA OpenCL; docs/measurements/tuning-h100-3scenes.json, h100-tune-3scenes.txt, roof/d60.sh";
constexpr std::array<const char*, 3> kThreeScenes = {"scenes/drops.json", "scenes/rubble.json",
                                                     "scenes/sculpt_dense.json"};
constexpr const char* kH100PoclFiles =
    "H100 machine (16-core Xeon), PoCL 5.0; docs/measurements/tuning-h100.json, h100-tune-pocl.txt";
constexpr const char* kH200Files =
    "H200 machine, NVIDIA OpenCL; docs/measurements/tuning-h200.json, h200-tune-nvidia.txt";
constexpr const char* kH200TraceFiles =
    "H200 machine, NVIDIA OpenCL; docs/measurements/roof/d18.sh, d18.tgz (tuning-hybrid.json, tune-hybrid.txt)";
constexpr const char* kHereEvaluateFiles =
    "2-core AMD EPYC development machine, PoCL 3.1; docs/measurements/tuning-pocl-here-2.json, pocl-here-tune-2.txt";
constexpr const char* kHereFiles =
    "2-core AMD EPYC development machine, PoCL 3.1; docs/measurements/tuning-pocl-here.json, pocl-here-tune.txt";

// In the order measured.
constexpr Measured kMeasured[] = {
    {kH100, "580.159.04", "NVIDIA Corporation", "NVIDIA CUDA", kTraceKernel, {{{"group_x", 4}, {"group_y", 8}}},
     3.382912, kTraceDefault, 3.62496, 0.0625, 3840, 2160, 5, "2026-11-22T07:05:20Z", kH100Files},
    {kHerePocl, "3.1+debian", "AuthenticAMD", kPocl, kEvaluateKernel, {{{"chunk", 64}, {"group", 8}}},
     88.540503, kEvaluateDefault, 126.637152, 0.25, 0, 0, 2, "2026-12-05T21:40:56Z", kHereEvaluateFiles},
    {kHerePocl, "3.1+debian", "AuthenticAMD", kPocl, kTraceKernel, {{{"group_x", 16}, {"group_y", 8}}},
     58.73181, kTraceDefault, 58.73181, 0.25, 640, 360, 2, "2026-11-22T07:05:39Z", kHereFiles},
    {kH100Pocl, "5.0+debian", "GenuineIntel", kPocl, kEvaluateKernel, {{{"chunk", 32}, {"group", 64}}},
     640.072271, kEvaluateDefault, 984.576531, 0.125, 0, 0, 2, "2026-11-22T07:10:38Z", kH100PoclFiles},
    {kH100Pocl, "5.0+debian", "GenuineIntel", kPocl, kTraceKernel, {{{"group_x", 8}, {"group_y", 4}}},
     45.144151, kTraceDefault, 66.751169, 0.125, 1280, 720, 2, "2026-11-22T07:10:52Z", kH100PoclFiles},
    {kH200, "580.159.04", "NVIDIA Corporation", "NVIDIA CUDA", kEvaluateKernel, {{{"chunk", 16}, {"group", 64}}},
     4.1536, kEvaluateDefault, 5.09312, 0.0625, 0, 0, 5, "2026-12-03T16:08:04Z", kH200Files},
    {kH200, "580.159.04", "NVIDIA Corporation", "NVIDIA CUDA", kTraceKernel,
     {{{"group_x", 8}, {"group_y", 16}, {"registers", 64}}}, 3.537216, kTraceDefault, 4.333632, 0.0625, 3840, 2160, 5,
     "2026-12-04T13:53:24Z", kH200TraceFiles, 90, "hybrid"},
    {kH100, "580.159.04", "NVIDIA Corporation", "NVIDIA CUDA", kEvaluateKernel,
     {{{"chunk", 32}, {"group", 64}, {"registers", 56}}}, 9.642723, kEvaluateDefault, 10.424090, 0.0625, 0, 0, 3,
     "2026-12-07T04:33:29Z", kH100ScenesFiles, 160, "sphere", kThreeScenes},
};

Config to_config(const Measured::Params& p) {
    Config c;
    for (const auto& [name, value] : p)
        if (name != nullptr) c[name] = value;
    return c;
}

Entry to_entry(const Measured& m) {
    const TunedKernel& kernel = *find_kernel(m.kernel);
    Entry e{m.device, m.driver, m.vendor, m.kernel, to_config(m.params), {}};
    e.record = {{"time_ms", m.time_ms},
                {"default_params", to_config(m.default_params)},
                {"default_ms", m.default_ms},
                {"objective", kernel.objective_text + ", min over repeats" +
                                  (m.scenes[1] ? ", geometric mean over the scenes" : "")},
                {"brick_size", m.brick_size},
                {"strategy", "full"},
                {"evaluated", m.space},
                {"space", m.space},
                {"repeat", m.repeat},
                {"tuned_at", m.tuned_at},
                {"platform", m.platform},
                {"measured", m.measured}};
    if (m.scenes[1]) {
        e.record["scenes"] = nlohmann::json::array();
        for (const char* scene : m.scenes)
            if (scene) e.record["scenes"].push_back(scene);
    } else {
        e.record["scene"] = m.scenes[0];
    }
    if (m.width > 0) {
        e.record["image"] = {m.width, m.height};
        e.record["method"] = m.method;
    }
    return e;
}

}  // namespace

const std::vector<Entry>& builtin_entries() {
    static const std::vector<Entry> entries = [] {
        std::vector<Entry> v;
        for (const Measured& m : kMeasured) v.push_back(to_entry(m));
        return v;
    }();
    return entries;
}

}  // namespace sdfbrick::tune
