// The arithmetic and the compulsory global-memory traffic of the construction stages that evaluate
// edits (count, cull, evaluate), for the roofline of a build report (docs/performance.md).
#pragma once

#include <cstdint>

#include "sdf_types.h"

namespace sdfbrick::construct {

// The FP32 operations one evaluation of edit e folds into a sample in kernels/sdf_edit.h and
// sdf_build.h, each + - * / sqrt fabs fmin fmax floor counted as one FLOP (clamp as two); operations
// on the edit's own parameters (uniform across samples) are not counted. A mesh edit counts its
// trilinear lookup.
double edit_flops(const SdfEdit& e);

// One stage's work in a build: FLOPs and the bytes it must read and write in global memory at
// least (each input once, each output once; caches may serve repeated reads, so this bounds from below).
struct StageWork {
    double flop = 0.0;
    double bytes = 0.0;
    std::uint64_t evaluations = 0;  // edit evaluations
};

}  // namespace sdfbrick::construct
