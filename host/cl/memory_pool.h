// Device memory kept between passes: a lane's buffers of one pass give their memory back here when
// they go, and the next pass's buffers of the same sizes take it again instead of allocating (a fresh
// allocation costs page faults on CPU devices and driver work on GPUs). Only buffers made with
// ocl::pooled use it (cl/buffer.h). Sizes are kept as allocated, never shrunk while a run lasts;
// trim() frees what no buffer took since the last trim (the sizes the run stopped needing).
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "cl/handles.h"

namespace sdfbrick::ocl {

class MemoryPool {
public:
    MemoryPool() = default;
    MemoryPool(const MemoryPool&) = delete;
    MemoryPool& operator=(const MemoryPool&) = delete;

    // A kept memory object of at least `bytes` and at most twice that, or the smallest allocation
    // (256 bytes) for less (the smallest that fits), and its capacity; an empty handle when none fits.
    MemObject take(std::size_t bytes, std::size_t& capacity);
    void give(MemObject memory, std::size_t capacity);
    // Frees the kept objects that were given back before the last trim and not taken since.
    void trim();
    std::size_t kept_bytes() const;
    std::size_t reused() const { return reused_; }  // takes served from kept memory

    // Every buffer allocated on the device (pooled or not) is counted here: a frame loop reports
    // how many allocations each frame still made once capacities settled.
    struct Allocations {
        std::uint64_t count = 0, bytes = 0;
    };
    void count_allocation(std::size_t bytes);
    Allocations allocations() const;

private:
    struct Kept {
        MemObject memory;
        std::size_t capacity = 0;
        bool recent = true;  // given back since the last trim
    };
    mutable std::mutex mutex_;
    std::vector<Kept> kept_;
    std::size_t reused_ = 0;
    Allocations allocations_;
};

// The capacity to allocate for a pooled request of `bytes`: rounded up (at most an eighth more) so
// that a later pass that needs a little more still fits, but never past `limit`.
std::size_t pooled_capacity(std::size_t bytes, std::size_t limit);

}  // namespace sdfbrick::ocl
