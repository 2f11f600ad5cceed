// The mesh pool every kernel that evaluates edits reads (kernels/sdf_types.h, SdfMeshGrid): a header
// for each mesh index up to the largest the edits use, then the grid values of the meshes they use.
#pragma once

#include <span>
#include <vector>

#include "cl/device.h"
#include "measure/scheduler.h"
#include "scene/scene.h"

namespace sdfbrick::construct {

// The pool of the mesh edits of `geometries` (one float when there is none). A mesh whose grid has
// not been converted yet is converted on the device here (MeshGridBuilder, stage `mesh`, recorded in
// scheduler) and keeps its grid for every later call: once per loaded scene. Throws InputError when
// the pool is larger than the device allocates at once.
std::vector<float> mesh_pool(std::span<const Geometry> geometries, ocl::Device& device, measure::Scheduler& scheduler);

}  // namespace sdfbrick::construct
