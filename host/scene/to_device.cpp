#include "scene/to_device.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/gtc/quaternion.hpp>

#include "core/errors.h"

namespace sdfbrick {

SdfEdit to_device(const Edit& e) {
    SdfEdit d{};
    for (int i = 0; i < 3; ++i) d.transform.translation[i] = static_cast<float>(e.transform.translation[i]);
    d.transform.scale = static_cast<float>(e.transform.scale);
    const glm::dquat q = e.transform.rotation;
    d.transform.rotation[0] = static_cast<float>(q.x);
    d.transform.rotation[1] = static_cast<float>(q.y);
    d.transform.rotation[2] = static_cast<float>(q.z);
    d.transform.rotation[3] = static_cast<float>(q.w);
    for (int i = 0; i < 4; ++i) d.params[i] = static_cast<float>(e.params[i]);
    d.blend = static_cast<float>(e.blend);
    d.inv_lipschitz = static_cast<float>(1.0 / lipschitz(e));
    d.primitive = static_cast<sdf_u32>(e.primitive);
    d.op = static_cast<sdf_u32>(e.op);
    return d;
}

std::vector<SdfEdit> to_device(const Geometry& g) {
    std::vector<SdfEdit> out;
    out.reserve(g.edits.size());
    for (const Edit& e : g.edits) out.push_back(to_device(e));
    return out;
}

void validate_image_size(int width, int height) {
    if (width < 1 || width > kMaxWidth) {
        throw SettingError("width", fmt::format("width {} is outside 1..{}", width, kMaxWidth));
    }
    if (height < 1 || height > kMaxHeight) {
        throw SettingError("height", fmt::format("height {} is outside 1..{}", height, kMaxHeight));
    }
}

namespace {
void store(sdf_f32 (&out)[3], const glm::dvec3& v) {
    for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(v[i]);
}
}  // namespace

SdfCamera make_camera(const Camera& camera, int width, int height) {
    validate_image_size(width, height);
    const glm::dvec3 eye = camera.eye_position();
    const glm::dvec3 forward = glm::normalize(camera.target - eye);
    const glm::dvec3 up_hint = camera.kind == Camera::Kind::Orbit ? glm::dvec3(0.0, 1.0, 0.0) : camera.up;
    glm::dvec3 right = glm::cross(forward, up_hint);
    if (glm::length(right) < 1e-12) right = glm::cross(forward, glm::dvec3(0.0, 0.0, 1.0));  // looking straight up/down
    right = glm::normalize(right);
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_half = std::tan(glm::radians(camera.fov_deg) * 0.5);
    const double aspect = static_cast<double>(width) / height;
    SdfCamera c{};
    store(c.eye, eye);
    store(c.forward, forward);
    store(c.right, right * (tan_half * aspect));
    store(c.up, up * tan_half);
    c.width = static_cast<sdf_u32>(width);
    c.height = static_cast<sdf_u32>(height);
    return c;
}

std::vector<SdfInstance> make_instances(const Scene& scene) {
    std::vector<SdfInstance> out;
    out.reserve(scene.objects.size());
    for (const Object& o : scene.objects) {
        const glm::dmat3 r = glm::mat3_cast(o.transform.rotation);
        const glm::dmat3 m = glm::transpose(r) / o.transform.scale;  // world -> geometry
        SdfInstance inst{};
        for (int row = 0; row < 3; ++row) {
            for (int col = 0; col < 3; ++col) inst.world_to_geometry[3 * row + col] = static_cast<float>(m[col][row]);
        }
        store(inst.translation, o.transform.translation);
        inst.scale = static_cast<float>(o.transform.scale);
        inst.geometry = static_cast<sdf_u32>(o.geometry);
        out.push_back(inst);
    }
    return out;
}

}  // namespace sdfbrick
