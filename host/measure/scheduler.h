// The host scheduler (docs/measurement.md): every kernel launch of the engine goes through
// Scheduler::launch, which enqueues it, names it by stage and level, and records its global and local
// sizes, the kernel's resource attributes at launch time (local memory includes the __local
// arguments then set), and, once resolved, its profiling times.
#pragma once

#include <CL/cl.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "cl/handles.h"
#include "measure/kernel_attributes.h"
#include "measure/stage.h"

namespace sdfbrick::measure {

struct Launch {
    Stage stage = Stage::trace;
    int level = -1;  // construction level; -1 = not per level
    std::string kernel;
    cl_uint dims = 1;
    std::array<std::size_t, 3> global{0, 1, 1};
    std::optional<std::array<std::size_t, 3>> local;  // empty: chosen by the driver
    KernelAttributes attributes;
    double enqueue_ms = 0.0;  // host wall time of the enqueue call
    // Profiling times, filled by Scheduler::resolve:
    double device_ms = 0.0;   // START -> END
    double queue_ms = 0.0;    // QUEUED -> START (queue latency)
    double submit_ms = 0.0;   // SUBMIT -> START

    std::uint64_t work_items() const;
    std::size_t group_size() const;  // work-items per group; 0 when the driver chose
    std::uint64_t groups() const;    // work-groups launched; 0 when the driver chose the group size
};

// {"stage", "level", "kernel", "global", "local" (null: the driver's), "device_ms", "queue_ms", "submit_ms",
//  "enqueue_ms", "attributes"}
nlohmann::json to_json(const Launch& l);

class Scheduler {
public:
    explicit Scheduler(ocl::Device& device) : device_(&device) {}
    ocl::Device& device() const { return *device_; }

    // Enqueues kernel (arguments already set) over dims dimensions and records the launch. local:
    // the work-group size, or empty to let the driver choose. A range with a zero dimension launches
    // nothing (see ocl::enqueue) but is still recorded. offset: the global work offset. Throws
    // InputError when the work-group is larger than the kernel allows on the device
    // (CL_KERNEL_WORK_GROUP_SIZE).
    void launch(Stage stage, int level, cl_kernel kernel, std::array<std::size_t, 3> global,
                std::optional<std::array<std::size_t, 3>> local, cl_uint dims,
                std::array<std::size_t, 3> offset = {0, 0, 0});
    void launch(Stage stage, int level, cl_kernel kernel, std::size_t global,
                std::optional<std::size_t> local = std::nullopt);

    // Waits for every launch and fills its times (throws ClError naming the kernel when one failed).
    // Idempotent.
    const std::vector<Launch>& resolve();
    // Device time of the resolved launches of a stage (level -1: all levels), and of all launches,
    // counting the launches from index `first` on (a builder's own share of a shared recorder).
    double stage_ms(Stage stage, int level = -1, std::size_t first = 0) const;
    double total_ms(std::size_t first = 0) const;
    // Launches recorded so far (the index the next launch gets).
    std::size_t size() const { return launches_.size(); }
    const std::vector<Launch>& launches() const { return launches_; }

private:
    ocl::Device* device_;
    std::vector<Launch> launches_;
    std::vector<ocl::Event> events_;  // events_[i] belongs to launches_[i] until resolved
};

}  // namespace sdfbrick::measure
