// Deterministic fault injection at the real code paths, for tests of what a failure leaves behind.
// Off unless the environment variable SDFBRICK_FAULT is set. Its value is a comma-separated list of
// items POINT[@DEVICE]:N, each making the N-th event (1-based) of that point fail:
//   alloc   a device buffer allocation        (fails as CL_MEM_OBJECT_ALLOCATION_FAILURE)
//   build   a kernel program build            (fails as CL_BUILD_PROGRAM_FAILURE)
//   launch  a kernel launch                   (fails as CL_OUT_OF_RESOURCES)
//   write   an output file write              (fails as an I/O error)
//   signal  an output file write              (SIGTERM once its temporary file holds the bytes)
// With @DEVICE (the device's global index, as `sdfbrick devices` lists it) only that device's events
// count; without it every event of the point counts. "launch@1:5,write:2" fails device 1's fifth
// launch and the second file write. Counting is per item and thread-safe.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace sdfbrick::fault {

inline constexpr const char* kEnv = "SDFBRICK_FAULT";

enum class Point { alloc, build, launch, write, signal };

std::string_view point_name(Point point);

// Counts one event of point (on the device with this global index, if any) and says whether it is
// one that must fail. Throws InputError once when SDFBRICK_FAULT is malformed.
bool should_fail(Point point, std::optional<std::size_t> device = std::nullopt);

// Reads SDFBRICK_FAULT now if it was not read yet; throws InputError when it is malformed. The CLI
// calls it before any work, so that a malformed value is refused at once (a device's first event
// would otherwise fail that device alone, and a split would go on without it).
void check();
// Re-reads SDFBRICK_FAULT and zeroes every count (tests set the variable, then call this).
void reset();

// What an injected failure's message says, so that a reader never mistakes it for a real one.
std::string describe(Point point, std::optional<std::size_t> device);

}  // namespace sdfbrick::fault
