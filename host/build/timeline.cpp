#include "build/timeline.h"

#include <utility>

#include "cl/launch.h"

namespace sdfbrick::build {

void Timeline::add(std::string stage, int level, std::string kernel, std::size_t global, std::size_t local,
                   ocl::Event event) {
    launches_.push_back({std::move(stage), level, std::move(kernel), global, local, 0.0, 0.0});
    events_.push_back(std::move(event));
}

const std::vector<Launch>& Timeline::resolve() {
    for (std::size_t i = 0; i < launches_.size(); ++i) {
        if (events_[i].get() == nullptr) continue;
        const ocl::EventTimes t = ocl::event_times(events_[i], "kernel " + launches_[i].kernel);
        launches_[i].device_ms = t.start_to_end_ms;
        launches_[i].queue_ms = t.queued_to_start_ms;
        events_[i] = ocl::Event();
    }
    return launches_;
}

double Timeline::stage_ms(const std::string& stage, int level) const {
    double ms = 0.0;
    for (const Launch& l : launches_)
        if (l.stage == stage && (level < 0 || l.level == level)) ms += l.device_ms;
    return ms;
}

double Timeline::total_ms() const {
    double ms = 0.0;
    for (const Launch& l : launches_) ms += l.device_ms;
    return ms;
}

void Timeline::clear() {
    launches_.clear();
    events_.clear();
}

}  // namespace sdfbrick::build
