// Typed device buffers. Buffer<T> owns a cl_mem of count elements of T on one Device; reads and
// writes are blocking and go through the device's queue. A buffer made with ocl::pooled takes its
// memory from the device's MemoryPool where a kept object fits (cl/memory_pool.h) and gives it back
// when it goes; its capacity may then exceed its size. A zero-element buffer is valid (OpenCL
// forbids zero-byte allocations, so one element is allocated and size() stays 0). A buffer larger
// than the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE is refused (CL_INVALID_BUFFER_SIZE) on every device;
// on a CPU device, so is one the host has no memory left for (cl/host_memory.h).
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "cl/device.h"
#include "cl/host_memory.h"
#include "cl/memory_pool.h"
#include "core/fault.h"
#include "cl/handles.h"

namespace sdfbrick::ocl {

// Tag: a buffer whose memory comes from and goes back to its device's MemoryPool.
struct Pooled {};
inline constexpr Pooled pooled{};

template <class T>
class Buffer {
    static_assert(std::is_trivially_copyable_v<T>, "a device buffer holds trivially copyable elements");

public:
    // flags: CL_MEM_READ_WRITE, CL_MEM_READ_ONLY, CL_MEM_WRITE_ONLY (no host pointer flags).
    Buffer(Device& device, std::size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE)
        : device_(&device), count_(count) {
        if (count > std::numeric_limits<std::size_t>::max() / sizeof(T)) {
            throw std::length_error(fmt::format("a buffer of {} elements of {} bytes does not fit in memory",
                                                count, sizeof(T)));
        }
        const std::size_t allocated = count == 0 ? sizeof(T) : count * sizeof(T);
        const DeviceInfo& info = device.info();
        // The limit is enforced here for every device: some drivers (NVIDIA's) accept larger buffers
        // where others refuse them, and a run must not depend on which device it met first.
        cl_int status = allocated > info.max_alloc_bytes ? CL_INVALID_BUFFER_SIZE : CL_SUCCESS;
        std::string injected;
        if (status == CL_SUCCESS && fault::should_fail(fault::Point::alloc, info.index)) {
            status = CL_MEM_OBJECT_ALLOCATION_FAILURE;
            injected = ", " + fault::describe(fault::Point::alloc, info.index);
        }
        if (status == CL_SUCCESS && info.type == "cpu" && !host_can_map(allocated + kHostMemoryMargin)) {
            status = CL_MEM_OBJECT_ALLOCATION_FAILURE;  // see cl/host_memory.h: the driver would abort later
            injected = ", the host cannot map that much more memory";
        }
        if (status == CL_SUCCESS) {
            memory_ = MemObject(clCreateBuffer(device.context(), flags, allocated, nullptr, &status));
            capacity_ = allocated;
            if (status == CL_SUCCESS) device.memory_pool()->count_allocation(allocated);
        }
        if (status != CL_SUCCESS) {
            throw ClError(status, fmt::format("allocating a buffer of {} bytes ({} elements of {} bytes) on {} "
                                              "(largest allocation {} bytes, global memory {} bytes{})",
                                              allocated, count, sizeof(T), info.name, info.max_alloc_bytes,
                                              info.global_mem_bytes, injected));
        }
    }

    // count elements (read-write) from the device's pool where kept memory fits, else newly
    // allocated with some headroom (pooled_capacity) and the same checks as above.
    Buffer(Pooled, Device& device, std::size_t count) : device_(&device), count_(count) {
        const std::size_t limit = device.info().max_alloc_bytes;
        const bool fits = count <= limit / sizeof(T);  // else the plain constructor below refuses it
        const std::size_t wanted = count == 0 ? sizeof(T) : count * sizeof(T);
        if (fits) memory_ = device.memory_pool()->take(wanted, capacity_);
        if (!memory_) {
            Buffer fresh(device, fits ? pooled_capacity(wanted, limit) / sizeof(T) : count);
            memory_ = std::move(fresh.memory_);
            capacity_ = fresh.capacity_;
        }
        pool_ = device.memory_pool();
    }

    Buffer(Buffer&& o) noexcept
        : device_(o.device_), count_(o.count_), capacity_(o.capacity_), memory_(std::move(o.memory_)),
          pool_(std::move(o.pool_)) {}
    Buffer& operator=(Buffer&& o) noexcept {
        if (this != &o) {
            give_back();
            device_ = o.device_;
            count_ = o.count_;
            capacity_ = o.capacity_;
            memory_ = std::move(o.memory_);
            pool_ = std::move(o.pool_);
        }
        return *this;
    }
    Buffer(const Buffer&) = delete;  // two owners of one allocation would be a surprise
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer() { give_back(); }

    // Allocates data.size() elements and writes data.
    Buffer(Device& device, std::span<const T> data, cl_mem_flags flags = CL_MEM_READ_WRITE)
        : Buffer(device, data.size(), flags) {
        write(data);
    }
    // The same from the device's pool (read-write): a pass's uploads take the last pass's memory.
    Buffer(Pooled, Device& device, std::span<const T> data) : Buffer(pooled, device, data.size()) { write(data); }

    std::size_t size() const { return count_; }
    std::size_t bytes() const { return count_ * sizeof(T); }
    std::size_t capacity_bytes() const { return capacity_; }  // allocated (pooled buffers: at least bytes())
    cl_mem get() const { return memory_.get(); }
    Device& device() const { return *device_; }

    // Writes data to elements [first, first + data.size()); blocks until done.
    void write(std::span<const T> data, std::size_t first = 0) {
        check_range(first, data.size(), "writing");
        if (data.empty()) {
            return;
        }
        check(clEnqueueWriteBuffer(device_->queue(), memory_.get(), CL_TRUE, first * sizeof(T), data.size_bytes(),
                                   data.data(), 0, nullptr, nullptr),
              [&] { return transfer("writing", first, data.size()); });
    }

    // Reads elements [first, first + out.size()) into out; blocks until done.
    void read_into(std::span<T> out, std::size_t first = 0) const {
        check_range(first, out.size(), "reading");
        if (out.empty()) {
            return;
        }
        check(clEnqueueReadBuffer(device_->queue(), memory_.get(), CL_TRUE, first * sizeof(T), out.size_bytes(),
                                  out.data(), 0, nullptr, nullptr),
              [&] { return transfer("reading", first, out.size()); });
    }

    // Copies all of src (same device) to elements [first, first + src.size()) on the device; enqueued
    // on the device's in-order queue, so later commands see the copy.
    void copy_from(const Buffer<T>& src, std::size_t first = 0) {
        check_range(first, src.size(), "copying into");
        if (src.size() == 0) {
            return;
        }
        check(clEnqueueCopyBuffer(device_->queue(), src.get(), memory_.get(), 0, first * sizeof(T), src.bytes(), 0,
                                  nullptr, nullptr),
              [&] { return transfer("copying into", first, src.size()); });
    }

    std::vector<T> read() const {
        std::vector<T> values(count_);
        read_into(values);
        return values;
    }

private:
    std::string transfer(std::string_view what, std::size_t first, std::size_t count) const {
        return fmt::format("{} elements [{}, {}) of a {}-element buffer ({} bytes each) on {}", what, first,
                           first + count, count_, sizeof(T), device_->info().name);
    }

    void check_range(std::size_t first, std::size_t count, std::string_view what) const {
        if (first > count_ || count > count_ - first) {
            throw std::out_of_range(fmt::format("{} elements [{}, {}) of a buffer of {} elements", what, first,
                                                first + count, count_));
        }
    }

    void give_back() noexcept {
        if (pool_ && memory_) {
            try {
                pool_->give(std::move(memory_), capacity_);
            } catch (...) {  // no memory for the pool's list: the object is released instead
            }
        }
        memory_.reset();
        pool_.reset();
    }

    Device* device_;
    std::size_t count_;
    std::size_t capacity_ = 0;
    MemObject memory_;
    std::shared_ptr<MemoryPool> pool_;  // pooled buffers only
};

}  // namespace sdfbrick::ocl
