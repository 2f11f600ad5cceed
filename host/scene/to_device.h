// Scene to device: the float records the kernels read (kernels/sdf_types.h) made from the scene's
// double-precision model: edits (SdfEdit), the camera (SdfCamera) and the object instances
// (SdfInstance). Construction, both tracers and the BVH take them from here.
#pragma once

#include <vector>

#include "scene/scene.h"
#include "sdf_types.h"

namespace sdfbrick {

// The float record of an edit, and of every edit of a geometry in order.
SdfEdit to_device(const Edit& e);
std::vector<SdfEdit> to_device(const Geometry& g);

// Largest image the tracers accept: 3840 x 2160.
inline constexpr int kMaxWidth = 3840;
inline constexpr int kMaxHeight = 2160;

// Throws SettingError ("width" or "height") for a size outside 1..kMax*.
void validate_image_size(int width, int height);

// Camera basis computed in double, stored as floats (see SdfCamera).
SdfCamera make_camera(const Camera& camera, int width, int height);

// One SdfInstance per scene object, in the scene's order.
std::vector<SdfInstance> make_instances(const Scene& scene);

}  // namespace sdfbrick
