#include "measure/scheduler.h"

#include <chrono>
#include <utility>

#include <fmt/format.h>

#include "cl/launch.h"
#include "core/errors.h"

namespace sdfbrick::measure {

std::uint64_t Launch::work_items() const {
    std::uint64_t n = 1;
    for (cl_uint d = 0; d < dims; ++d) n *= global[d];
    return n;
}

std::size_t Launch::group_size() const {
    if (!local) return 0;
    std::size_t n = 1;
    for (cl_uint d = 0; d < dims; ++d) n *= (*local)[d];
    return n;
}

std::uint64_t Launch::groups() const {
    if (!local) return 0;
    std::uint64_t n = 1;
    for (cl_uint d = 0; d < dims; ++d) n *= ((*local)[d] ? (global[d] + (*local)[d] - 1) / (*local)[d] : 0);
    return n;
}

nlohmann::json to_json(const Launch& l) {
    const std::vector<std::size_t> global(l.global.begin(), l.global.begin() + l.dims);
    nlohmann::json local = nullptr;
    if (l.local) local = std::vector<std::size_t>(l.local->begin(), l.local->begin() + l.dims);
    return {{"stage", to_string(l.stage)}, {"level", l.level}, {"kernel", l.kernel}, {"global", global}, {"local", local},
            {"device_ms", l.device_ms}, {"queue_ms", l.queue_ms}, {"submit_ms", l.submit_ms},
            {"enqueue_ms", l.enqueue_ms}, {"attributes", to_json(l.attributes)}};
}

void Scheduler::launch(Stage stage, int level, cl_kernel kernel, std::array<std::size_t, 3> global,
                       std::optional<std::array<std::size_t, 3>> local, cl_uint dims,
                       std::array<std::size_t, 3> offset) {
    Launch l;
    l.stage = stage;
    l.level = level;
    l.attributes = kernel_attributes(*device_, kernel);
    l.kernel = l.attributes.kernel;
    l.dims = dims;
    l.global = global;
    l.local = local;
    if (l.group_size() > l.attributes.work_group_size_limit)  // e.g. too many registers for the group
        throw InputError(fmt::format("a work-group of {} work-items is more than kernel {} allows on {} (at most {}, "
                                     "CL_KERNEL_WORK_GROUP_SIZE): choose a smaller work-group for this kernel",
                                     l.group_size(), l.kernel, device_->info().name, l.attributes.work_group_size_limit));
    const auto start = std::chrono::steady_clock::now();
    events_.push_back(ocl::enqueue(*device_, kernel, l.kernel, global, local, dims, offset));
    l.enqueue_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    launches_.push_back(std::move(l));
}

void Scheduler::launch(Stage stage, int level, cl_kernel kernel, std::size_t global,
                       std::optional<std::size_t> local) {
    std::optional<std::array<std::size_t, 3>> local3;
    if (local) local3 = std::array<std::size_t, 3>{*local, 1, 1};
    launch(stage, level, kernel, {global, 1, 1}, local3, 1);
}

const std::vector<Launch>& Scheduler::resolve() {
    for (std::size_t i = 0; i < launches_.size(); ++i) {
        if (events_[i].get() == nullptr) continue;
        const ocl::EventTimes t = ocl::event_times(events_[i], "kernel " + launches_[i].kernel);
        launches_[i].device_ms = t.start_to_end_ms;
        launches_[i].queue_ms = t.queued_to_start_ms;
        launches_[i].submit_ms = t.submit_to_start_ms;
        events_[i] = ocl::Event();
    }
    return launches_;
}

double Scheduler::stage_ms(Stage stage, int level, std::size_t first) const {
    double ms = 0.0;
    for (std::size_t i = first; i < launches_.size(); ++i)
        if (launches_[i].stage == stage && (level < 0 || launches_[i].level == level)) ms += launches_[i].device_ms;
    return ms;
}

double Scheduler::total_ms(std::size_t first) const {
    double ms = 0.0;
    for (std::size_t i = first; i < launches_.size(); ++i) ms += launches_[i].device_ms;
    return ms;
}

}  // namespace sdfbrick::measure
