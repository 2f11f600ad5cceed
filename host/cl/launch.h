// Kernel arguments, launches and their profiling times.
#pragma once

#include <CL/cl.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <type_traits>

#include "cl/buffer.h"
#include "cl/device.h"
#include "cl/handles.h"

namespace sdfbrick::ocl {

// A __local kernel argument of the given size.
struct LocalMemory {
    std::size_t bytes;
};

namespace detail {

// Throws ClError naming the kernel and the argument index on failure.
void set_kernel_arg(cl_kernel kernel, cl_uint index, std::size_t size, const void* value, std::string_view kind);

template <class T>
void set_arg(cl_kernel kernel, cl_uint index, const Buffer<T>& buffer) {
    const cl_mem memory = buffer.get();
    set_kernel_arg(kernel, index, sizeof(memory), &memory, "buffer");
}

inline void set_arg(cl_kernel kernel, cl_uint index, cl_mem memory) {
    set_kernel_arg(kernel, index, sizeof(memory), &memory, "buffer");
}

inline void set_arg(cl_kernel kernel, cl_uint index, LocalMemory local) {
    set_kernel_arg(kernel, index, local.bytes, nullptr, "local memory");
}

template <class T>
    requires(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)  // OpenCL has no bool arguments
void set_arg(cl_kernel kernel, cl_uint index, T value) {
    set_kernel_arg(kernel, index, sizeof(T), &value, "scalar");
}

}  // namespace detail

// Sets the kernel's arguments 0, 1, ... in order: a Buffer<T> (or a cl_mem) passes its cl_mem, an arithmetic
// value is passed by value (its C++ type must have the kernel parameter's size), LocalMemory{bytes}
// sizes a __local pointer argument.
template <class... Args>
void set_args(cl_kernel kernel, const Args&... args) {
    cl_uint index = 0;
    (detail::set_arg(kernel, index++, args), ...);
}

// Enqueues kernel over an NDRange of dims (1 to 3) dimensions on the device's queue. local:
// work-group size, or std::nullopt to let the driver choose. name: what error messages call the
// launch. offset: the global work offset (get_global_id starts there). A range with a zero dimension
// launches nothing: a marker stands in for it, so the returned event is still valid (and its times
// are ~0).
Event enqueue(Device& device, cl_kernel kernel, std::string_view name, std::array<std::size_t, 3> global,
              std::optional<std::array<std::size_t, 3>> local, cl_uint dims,
              std::array<std::size_t, 3> offset = {0, 0, 0});

// One-dimensional launch.
Event enqueue(Device& device, cl_kernel kernel, std::string_view name, std::size_t global,
              std::optional<std::size_t> local = std::nullopt);

// From the profiling counters of a completed command (the device's queue profiles every command).
struct EventTimes {
    double queued_to_start_ms = 0.0;  // queue latency: CL_PROFILING_COMMAND_QUEUED -> START
    double submit_to_start_ms = 0.0;  // CL_PROFILING_COMMAND_SUBMIT -> START
    double start_to_end_ms = 0.0;     // device time: START -> END
};

// Waits for the event, then reads its profiling counters. Throws ClError when the command failed;
// what names the command in that message ("kernel eval_points").
EventTimes event_times(const Event& event, std::string_view what = "a command");

}  // namespace sdfbrick::ocl
