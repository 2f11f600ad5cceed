#include "cl/launch.h"

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "core/fault.h"

namespace sdfbrick::ocl {

namespace {

std::string kernel_name(cl_kernel kernel) {
    std::size_t size = 0;
    if (clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, 0, nullptr, &size) != CL_SUCCESS || size == 0) {
        return "(unnamed)";
    }
    std::string name(size, '\0');
    if (clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, size, name.data(), nullptr) != CL_SUCCESS) {
        return "(unnamed)";
    }
    name.resize(size - 1);
    return name;
}

std::string range_text(const std::array<std::size_t, 3>& range, cl_uint dims) {
    std::string text = std::to_string(range[0]);
    for (cl_uint d = 1; d < dims; ++d) {
        text += 'x';
        text += std::to_string(range[d]);
    }
    return text;
}

}  // namespace

namespace detail {

void set_kernel_arg(cl_kernel kernel, cl_uint index, std::size_t size, const void* value, std::string_view kind) {
    const cl_int status = clSetKernelArg(kernel, index, size, value);
    if (status != CL_SUCCESS) {
        throw ClError(status, fmt::format("setting argument {} ({}, {} bytes) of kernel '{}'", index, kind, size,
                                          kernel_name(kernel)));
    }
}

}  // namespace detail

Event enqueue(Device& device, cl_kernel kernel, std::string_view name, std::array<std::size_t, 3> global,
              std::optional<std::array<std::size_t, 3>> local, cl_uint dims, std::array<std::size_t, 3> offset) {
    if (dims < 1 || dims > 3) {
        throw ClError(CL_INVALID_WORK_DIMENSION, fmt::format("enqueueing kernel {} with {} dimensions on {} "
                                                             "(OpenCL allows 1 to 3)",
                                                             name, dims, device.info().name));
    }
    const auto doing = [&] {
        return fmt::format("enqueueing kernel {} (global {}, local {}) on {}", name, range_text(global, dims),
                           local ? range_text(*local, dims) : std::string("chosen by the driver"),
                           device.info().name);
    };
    cl_event event = nullptr;
    cl_int status = CL_SUCCESS;
    bool empty = false;
    for (cl_uint d = 0; d < dims; ++d) {
        empty = empty || global[d] == 0;
    }
    if (fault::should_fail(fault::Point::launch, device.info().index)) {
        throw ClError(CL_OUT_OF_RESOURCES, doing(), fault::describe(fault::Point::launch, device.info().index));
    }
    if (empty) {
        status = clEnqueueMarkerWithWaitList(device.queue(), 0, nullptr, &event);
    } else {
        status = clEnqueueNDRangeKernel(device.queue(), kernel, dims, offset.data(), global.data(),
                                        local ? local->data() : nullptr, 0, nullptr, &event);
    }
    if (status != CL_SUCCESS) {
        throw ClError(status, doing());
    }
    return Event(event);
}

Event enqueue(Device& device, cl_kernel kernel, std::string_view name, std::size_t global,
              std::optional<std::size_t> local) {
    std::optional<std::array<std::size_t, 3>> local3;
    if (local) {
        local3 = std::array<std::size_t, 3>{*local, 1, 1};
    }
    return enqueue(device, kernel, name, {global, 1, 1}, local3, 1);
}

EventTimes event_times(const Event& event, std::string_view what) {
    const cl_event e = event.get();
    const cl_int waited = clWaitForEvents(1, &e);
    if (waited != CL_SUCCESS && waited != CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST) {
        throw ClError(waited, fmt::format("waiting for {} to complete", what));
    }
    cl_int execution_status = CL_COMPLETE;
    check(clGetEventInfo(e, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof(execution_status), &execution_status, nullptr),
          [&] { return fmt::format("reading the status of {}", what); });
    if (execution_status < 0) {
        throw ClError(execution_status, fmt::format("executing {} (it failed on the device)", what));
    }
    const auto counter = [e, what](cl_profiling_info param, const char* point) {
        cl_ulong ns = 0;
        check(clGetEventProfilingInfo(e, param, sizeof(ns), &ns, nullptr),
              [&] { return fmt::format("reading the {} time of {}", point, what); });
        return ns;
    };
    const cl_ulong queued = counter(CL_PROFILING_COMMAND_QUEUED, "queued");
    const cl_ulong submit = counter(CL_PROFILING_COMMAND_SUBMIT, "submit");
    const cl_ulong start = counter(CL_PROFILING_COMMAND_START, "start");
    const cl_ulong end = counter(CL_PROFILING_COMMAND_END, "end");
    // Differences in integers first: absolute timestamps can exceed double's exact range.
    const auto ms = [](cl_ulong from, cl_ulong to) {
        return static_cast<double>(static_cast<std::int64_t>(to - from)) * 1e-6;
    };
    return {ms(queued, start), ms(submit, start), ms(start, end)};
}

}  // namespace sdfbrick::ocl
