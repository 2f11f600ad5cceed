// The launches of one construction, named by stage and level, resolved to device times once the
// queue has drained. (Issue 5's scheduler grows out of this.)
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "cl/handles.h"

namespace sdfbrick::build {

// One launch: stage ("count", "scan", ...), level (-1 = not per level), kernel name and its range.
struct Launch {
    std::string stage;
    int level = -1;
    std::string kernel;
    std::size_t global = 0;
    std::size_t local = 0;
    double device_ms = 0.0;  // START -> END, filled by Timeline::resolve
    double queue_ms = 0.0;   // QUEUED -> START
};

class Timeline {
public:
    void add(std::string stage, int level, std::string kernel, std::size_t global, std::size_t local,
             ocl::Event event);
    // Waits for every recorded event and fills the times. Idempotent.
    const std::vector<Launch>& resolve();
    // Total device time of the launches of a stage (level -1: every level).
    double stage_ms(const std::string& stage, int level = -1) const;
    double total_ms() const;
    const std::vector<Launch>& launches() const { return launches_; }
    void clear();

private:
    std::vector<Launch> launches_;
    std::vector<ocl::Event> events_;  // events_[i] belongs to launches_[i] until resolved
};

}  // namespace sdfbrick::build
