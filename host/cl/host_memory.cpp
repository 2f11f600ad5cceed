#include "cl/host_memory.h"

#include <sys/mman.h>

namespace sdfbrick::ocl {

bool host_can_map(std::size_t bytes) {
    void* probe = ::mmap(nullptr, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (probe == MAP_FAILED) return false;
    ::munmap(probe, bytes);
    return true;
}

}  // namespace sdfbrick::ocl
