// The sweep grid: scenes x brick sizes x chunk sizes x work-group sizes x trace work-groups x
// culling x storage formats x samples (apron widths) x in-brick methods x normal methods x devices.
// Pure data and functions: expansion, keys, sharding. docs/sweep.md describes the sweep file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sdfbrick::sweep {

// One dimension's values; empty = the single default value. Chunk, group and trace group default to
// "auto": the tuning database's value for the device, else the built-in default.
struct SweepSpec {
    std::vector<std::string> scenes;  // scene files
    std::vector<double> brick_sizes;
    std::vector<double> tolerances;                // adaptive leaves; 0 = uniform (the default)
    std::vector<int> chunks;
    std::vector<int> groups;                       // evaluation work-group size
    std::vector<std::string> trace_groups;         // "16x8"
    std::vector<bool> culls;
    std::vector<std::string> formats;              // int8, int16, float
    std::vector<int> samples;                      // 8 (one-voxel apron) or 10 (two-voxel apron)
    std::vector<std::string> methods;              // sphere, analytic, hybrid
    std::vector<std::string> normals;              // central, tetra, continuous
    std::string devices;                           // a device spec (see ocl::select_devices); "" = -d or the default
    int width = 640, height = 360;                 // trace and reference image size
    int warmup = 1, repeat = 3;
    bool accuracy = true;                          // measure against the reference tracer

    // Throws InputError naming the key and the bad value.
    void validate() const;
    std::size_t size_per_device() const;  // saturates at the largest std::size_t instead of wrapping
};

// Reads a sweep file's JSON: {"scenes": [...], "brick_sizes": [...], "tolerances": [...], "chunks": [...], "groups": [...],
// "trace_groups": ["16x8"], "cull": [true, false], "formats": [...], "samples": [...], "methods": [...],
// "normals": [...], "devices": "all", "width": 640, "height": 360, "warmup": 1, "repeat": 3,
// "accuracy": true}. Unknown keys are refused (InputError naming the key). where: the file, for messages.
SweepSpec spec_from_json(const nlohmann::json& j, const std::string& where);
nlohmann::json to_json(const SweepSpec& s);

struct SweepPoint {
    std::size_t index = 0;  // position in the full grid (before sharding)
    std::string scene;
    std::string device;     // the device's name
    double brick_size = 0.0625;
    double tolerance = 0.0;
    std::optional<int> chunk, group;
    std::optional<std::string> trace_group;
    bool cull = true;
    std::string format = "int8";
    int samples = 8;
    std::string method = "sphere";
    std::string normals = "continuous";

    // Canonical text of every parameter (and the image size, repeats and accuracy switch that change
    // its results): equal keys = the same measurement. Used by the resume cache and merge.
    std::string key(const SweepSpec& spec) const;
};

// The full grid for the given device names, devices outermost, then scenes, brick sizes, ... in the
// order of SweepSpec's fields. Throws InputError when the grid is empty or larger than max_points.
std::vector<SweepPoint> expand(const SweepSpec& spec, const std::vector<std::string>& devices,
                               std::size_t max_points = 1000000);

struct Shard {
    std::size_t index = 0, count = 1;  // shard index of count, 0-based
};
// "i/n" with 0 <= i < n; throws InputError otherwise.
Shard parse_shard(const std::string& text);
// The points of one shard: every count-th point starting at index (round robin, so that each shard
// gets a share of every scene and brick size).
std::vector<SweepPoint> shard_points(const std::vector<SweepPoint>& points, Shard shard);

// "16x8" -> {16, 8}; throws InputError naming what.
std::pair<int, int> parse_group_2d(const std::string& text, const std::string& what);

}  // namespace sdfbrick::sweep
