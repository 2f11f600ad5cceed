// Running sweep points, their resume cache, JSON output and merging shards. Each point runs the
// measured pipeline (pipeline/run.h) and, with accuracy on, the reference tracer with the same
// camera; its result is one SweepRow (sweep/row.h: the CSV and JSON columns, docs/sweep.md).
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "sweep/grid.h"
#include "sweep/row.h"
#include "tune/tuning_db.h"

namespace sdfbrick::sweep {

// Finished points, one JSON object per line ({"key": ..., "row": {...}}), appended (and flushed) as
// each point finishes, so that a killed sweep resumes where it stopped. A damaged last line (a write
// cut short) is ignored, and so is a row that does not read back. An empty path keeps the rows in
// memory only (nothing is read or written).
class ResultCache {
public:
    // Opens (or creates) the cache file at once, refusing a link or a special file there
    // (open_journal), and reads the rows it holds.
    explicit ResultCache(std::filesystem::path path);
    ~ResultCache();
    ResultCache(const ResultCache&) = delete;
    ResultCache& operator=(const ResultCache&) = delete;
    const SweepRow* find(const std::string& key) const;
    void add(const std::string& key, const SweepRow& row);
    std::size_t size() const { return rows_.size(); }

private:
    std::filesystem::path path_;
    std::map<std::string, SweepRow> rows_;
    int fd_ = -1;       // the file, opened to append
    bool cut_ = false;  // the file does not end with a line break (a write cut short)
};

struct Progress {
    std::size_t done = 0, total = 0, cached = 0;
    double elapsed_s = 0.0, eta_s = 0.0;  // eta: from the mean time of the points run so far
    std::string current;                  // the point being run
};

// Runs points on devices (matched by SweepPoint::device, see device_label), skipping those in the
// cache. tuning: may be null. progress: called before each point and once at the end.
std::vector<SweepRow> run_points(const SweepSpec& spec, const std::vector<SweepPoint>& points, ocl::DeviceSet& devices,
                            const tune::TuningDb* tuning, ResultCache& cache,
                            const std::function<void(const Progress&)>& progress);

// The name of an opened device in sweep points: its name, with " #<index>" when the set holds another
// device of the same name.
std::vector<std::string> device_labels(const ocl::DeviceSet& devices);

// The sweep's JSON document: {"command": "sweep", "spec", "shard": {"index", "count"}, "grid_points",
// "points": [rows]}.
nlohmann::json sweep_document(const SweepSpec& spec, Shard shard, std::size_t grid_points, const std::vector<SweepRow>& rows);

struct Merged {
    std::vector<SweepRow> rows;          // in grid order when every input has the same spec
    std::vector<std::string> notes; // duplicates, missing shards or points, differing specs
    bool complete = false;          // one spec, every shard present, every grid point present
};
// Joins sweep documents (the JSON files sweep writes); where names the files for messages. Throws
// InputError for a document that is not a sweep.
Merged merge(const std::vector<nlohmann::json>& documents, const std::vector<std::string>& where);

}  // namespace sdfbrick::sweep
