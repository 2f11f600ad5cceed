// Construction stage 1 on the device (docs/construction.md): per edit, the box of its solid and of its
// influence region; then the dependencies of the smooth edits as CSR lists. A smooth edit j
// (blend > 0) depends on every earlier edit i < j whose influence box overlaps j's (closed boxes).
// No n x n work: a uniform grid over the influence boxes (kernels/edit_deps.cl describes it).
// The output does not depend on the grid, the device's work-group sizes or the order of atomics:
// every list is ascending and holds each dependency once.
#pragma once

#include <CL/cl.h>

#include <array>
#include <cstddef>
#include <cstdint>

#include "construct/scan.h"
#include "measure/scheduler.h"
#include "cl/buffer.h"
#include "cl/device.h"
#include "cl/handles.h"
#include "cl/program.h"
#include "sdf_types.h"

namespace sdfbrick::construct {

struct EditDependencies {
    ocl::Buffer<SdfBounds> bounds;     // per edit: box of the solid {value <= 0}
    ocl::Buffer<SdfBounds> influence;  // per edit: box of the influence region {value <= blend}
    ocl::Buffer<cl_uint> offsets;      // edits + 1 entries: edit j's list is indices[offsets[j], offsets[j+1])
    ocl::Buffer<cl_uint> indices;      // dependency lists, each ascending
    std::size_t total = 0;             // dependency entries
    std::size_t scratch_bytes = 0;     // peak temporary memory (grid) used while computing them
    std::size_t bytes() const;         // bytes held by the four buffers above

    // The grid that was used (for reports): cells per axis, cell side, cell references.
    std::array<std::uint32_t, 3> grid_dims{1, 1, 1};
    float grid_cell = 0.0f;
    std::size_t grid_refs = 0;
};

class DependencyBuilder {  // holds the compiled programs and a Scan; reusable across builds
public:
    DependencyBuilder(ocl::Device& device, Scan& scan);
    // stage names recorded in scheduler: "edit_bounds" and "dependencies" (level -1)
    EditDependencies compute(const ocl::Buffer<SdfEdit>& edits, std::size_t count, measure::Scheduler& scheduler);

    // Most cell references the grid may hold for n boxes (a coarser grid is chosen beyond it).
    static std::size_t max_refs(std::size_t n);

private:
    class Job;  // one compute() call's steps
    ocl::Device& device_;
    Scan& scan_;
    ocl::Program bounds_program_, deps_program_;
    ocl::Kernel edit_bounds_, grid_stats_, grid_refs_, fill_uint_, grid_count_, grid_fill_, grid_sort_,
        deps_count_, deps_write_;
    std::size_t reduce_local_ = 128;  // work-group size of grid_stats and grid_refs (a power of two)
};

}  // namespace sdfbrick::construct
