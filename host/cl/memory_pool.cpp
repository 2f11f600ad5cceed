#include "cl/memory_pool.h"

#include <algorithm>
#include <bit>

namespace sdfbrick::ocl {

namespace {
// The smallest pooled allocation: requests below it share one size, so that they reuse each other.
constexpr std::size_t kSmallest = 256;
}  // namespace

MemObject MemoryPool::take(std::size_t bytes, std::size_t& capacity) {
    std::lock_guard lock(mutex_);
    auto best = kept_.end();
    for (auto it = kept_.begin(); it != kept_.end(); ++it)
        if (it->capacity >= bytes && it->capacity <= std::max(2 * bytes, kSmallest) &&
            (best == kept_.end() || it->capacity < best->capacity))
            best = it;
    if (best == kept_.end()) return MemObject();
    MemObject m = std::move(best->memory);
    capacity = best->capacity;
    kept_.erase(best);
    ++reused_;
    return m;
}

void MemoryPool::give(MemObject memory, std::size_t capacity) {
    std::lock_guard lock(mutex_);
    kept_.push_back({std::move(memory), capacity, true});
}

void MemoryPool::trim() {
    std::lock_guard lock(mutex_);
    std::erase_if(kept_, [](const Kept& k) { return !k.recent; });
    for (Kept& k : kept_) k.recent = false;
}

std::size_t MemoryPool::kept_bytes() const {
    std::lock_guard lock(mutex_);
    std::size_t n = 0;
    for (const Kept& k : kept_) n += k.capacity;
    return n;
}

std::size_t pooled_capacity(std::size_t bytes, std::size_t limit) {
    if (bytes < 4096) return std::min(limit, std::max(bytes, kSmallest));
    // The next of 8 steps per power of two at or above bytes.
    const std::size_t step = std::bit_floor(bytes) / 8;
    const std::size_t rounded = (bytes + step - 1) / step * step;
    return rounded <= limit ? rounded : bytes;
}

void MemoryPool::count_allocation(std::size_t bytes) {
    std::lock_guard lock(mutex_);
    ++allocations_.count;
    allocations_.bytes += bytes;
}

MemoryPool::Allocations MemoryPool::allocations() const {
    std::lock_guard lock(mutex_);
    return allocations_;
}

}  // namespace sdfbrick::ocl
