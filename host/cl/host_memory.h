// Host memory for devices whose buffers live in it. A CPU driver (PoCL) allocates a buffer's storage
// in host memory lazily, at the first command that uses it, and aborts the process when that
// allocation fails. Buffer<T> therefore asks, before creating a buffer on a CPU device, whether the
// host can still map that many bytes (and a margin for the driver's own work), and refuses the
// allocation with CL_MEM_OBJECT_ALLOCATION_FAILURE when it cannot.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

namespace sdfbrick::ocl {

// The headroom asked for beyond the buffer itself.
inline constexpr std::size_t kHostMemoryMargin = std::size_t{64} << 20;

// Whether `bytes` of address space can be reserved now (an address-space limit such as ulimit -v,
// or an exhausted host). Reserves nothing: the probe is released at once.
bool host_can_map(std::size_t bytes);

// The bytes of host memory this process can still use: the kernel's estimate of what can be had
// without swapping (MemAvailable), and below an address-space limit (ulimit -v) what is left of it.
// std::nullopt when neither can be read.
std::optional<std::uint64_t> host_memory_available();

}  // namespace sdfbrick::ocl
