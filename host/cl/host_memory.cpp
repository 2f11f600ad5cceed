#include "cl/host_memory.h"

#include <sys/mman.h>
#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

namespace sdfbrick::ocl {

bool host_can_map(std::size_t bytes) {
    void* probe = ::mmap(nullptr, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (probe == MAP_FAILED) return false;
    ::munmap(probe, bytes);
    return true;
}

namespace {

// A "Name:   N kB" line of a /proc file, in bytes.
std::optional<std::uint64_t> proc_kib(const char* file, const std::string& name) {
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(name + ":", 0) != 0) continue;
        std::istringstream words(line.substr(name.size() + 1));
        std::uint64_t kib = 0;
        if (words >> kib) return kib * 1024;
    }
    return std::nullopt;
}

}  // namespace

std::optional<std::uint64_t> host_memory_available() {
    std::optional<std::uint64_t> available = proc_kib("/proc/meminfo", "MemAvailable");
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const std::uint64_t used = proc_kib("/proc/self/status", "VmSize").value_or(0);
        const std::uint64_t left = limit.rlim_cur > used ? limit.rlim_cur - used : 0;
        available = available ? std::min(*available, left) : left;
    }
    return available;
}

}  // namespace sdfbrick::ocl
