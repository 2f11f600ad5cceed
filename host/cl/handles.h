// RAII owners of OpenCL objects. A handle releases its object when destroyed; copying a handle
// retains the object (OpenCL reference counting), moving transfers it.
#pragma once

#include <CL/cl.h>

#include <string>
#include <utility>

#include "cl/cl_error.h"

namespace sdfbrick::ocl {

template <class T>
struct HandleTraits;

#define SDFBRICK_OCL_HANDLE_TRAITS(type, suffix, what)                             \
    template <>                                                                    \
    struct HandleTraits<type> {                                                    \
        static constexpr const char* name = what;                                  \
        static cl_int retain(type object) { return clRetain##suffix(object); }     \
        static cl_int release(type object) { return clRelease##suffix(object); }   \
    };
SDFBRICK_OCL_HANDLE_TRAITS(cl_context, Context, "context")
SDFBRICK_OCL_HANDLE_TRAITS(cl_command_queue, CommandQueue, "command queue")
SDFBRICK_OCL_HANDLE_TRAITS(cl_program, Program, "program")
SDFBRICK_OCL_HANDLE_TRAITS(cl_kernel, Kernel, "kernel")
SDFBRICK_OCL_HANDLE_TRAITS(cl_mem, MemObject, "memory object")
SDFBRICK_OCL_HANDLE_TRAITS(cl_event, Event, "event")
#undef SDFBRICK_OCL_HANDLE_TRAITS

template <class T>
class Handle {
public:
    Handle() noexcept = default;
    // Takes ownership of one reference (what clCreate* returned).
    explicit Handle(T object) noexcept : object_(object) {}
    ~Handle() { reset(); }

    Handle(const Handle& other) : object_(other.object_) {
        if (object_ != nullptr) {
            const cl_int status = HandleTraits<T>::retain(object_);
            if (status != CL_SUCCESS) {
                throw ClError(status, std::string("retaining an OpenCL ") + HandleTraits<T>::name);
            }
        }
    }
    Handle& operator=(const Handle& other) {
        if (this != &other) {
            Handle copy(other);
            swap(copy);
        }
        return *this;
    }
    Handle(Handle&& other) noexcept : object_(std::exchange(other.object_, nullptr)) {}
    Handle& operator=(Handle&& other) noexcept {
        if (this != &other) {
            reset();
            object_ = std::exchange(other.object_, nullptr);
        }
        return *this;
    }

    T get() const noexcept { return object_; }
    explicit operator bool() const noexcept { return object_ != nullptr; }
    void swap(Handle& other) noexcept { std::swap(object_, other.object_); }

    // Releases the object now (if any); the handle becomes empty.
    void reset() noexcept {
        if (object_ != nullptr) {
            HandleTraits<T>::release(object_);  // nothing useful can be done with a failed release
            object_ = nullptr;
        }
    }

private:
    T object_ = nullptr;
};

using Context = Handle<cl_context>;
using Queue = Handle<cl_command_queue>;
using ProgramHandle = Handle<cl_program>;  // program.h's Program adds the build record
using Kernel = Handle<cl_kernel>;
using MemObject = Handle<cl_mem>;
using Event = Handle<cl_event>;

}  // namespace sdfbrick::ocl
