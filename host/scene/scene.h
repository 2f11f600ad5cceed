// The scene model (host side, double precision): geometries (ordered edit lists), objects
// (instances of a geometry), camera, light, per-edit animation. docs/scene-format.md describes the
// JSON form; scene_json.h reads and writes it.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "sdf_types.h"

namespace sdfbrick {

enum class Primitive : std::uint32_t {
    Sphere = SDF_PRIM_SPHERE,
    Box = SDF_PRIM_BOX,
    RoundBox = SDF_PRIM_ROUND_BOX,
    Torus = SDF_PRIM_TORUS,
    Capsule = SDF_PRIM_CAPSULE,
    Cylinder = SDF_PRIM_CYLINDER,
    Cone = SDF_PRIM_CONE,
    Ellipsoid = SDF_PRIM_ELLIPSOID,
    Menger = SDF_PRIM_MENGER,
    Mesh = SDF_PRIM_MESH,
};
inline constexpr std::size_t kPrimitiveCount = SDF_PRIM_COUNT;
// The primitives given by a formula (all but Mesh, which needs a file): 0 .. kAnalyticPrimitiveCount - 1.
inline constexpr std::size_t kAnalyticPrimitiveCount = SDF_PRIM_MESH;

struct MeshSource;  // scene/mesh.h: a mesh edit's triangles and distance grid

enum class Op : std::uint32_t { Add = SDF_OP_ADD, Subtract = SDF_OP_SUBTRACT, Intersect = SDF_OP_INTERSECT };

std::string_view to_string(Primitive p);  // "sphere", "round_box", ...
std::string_view to_string(Op op);        // "add", "subtract", "intersect"
std::optional<Primitive> primitive_from_string(std::string_view s);
std::optional<Op> op_from_string(std::string_view s);

// Axis-aligned box; empty when lo > hi on any axis.
struct Aabb {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void grow(const glm::dvec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    void grow(const Aabb& b) { if (!b.empty()) { lo = glm::min(lo, b.lo); hi = glm::max(hi, b.hi); } }
    Aabb inflated(double r) const { return empty() ? *this : Aabb{lo - r, hi + r}; }
    glm::dvec3 centre() const { return 0.5 * (lo + hi); }
    glm::dvec3 extent() const { return hi - lo; }
};

// x_parent = rotation * (scale * x_local) + translation; rotation is a unit quaternion.
struct Transform {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // glm order: (w, x, y, z)
    double scale = 1.0;

    glm::dvec3 apply(const glm::dvec3& local) const { return rotation * (scale * local) + translation; }
    glm::dvec3 inverse_apply(const glm::dvec3& parent) const {
        return (glm::conjugate(rotation) * (parent - translation)) / scale;
    }
    // AABB (in the parent frame) of a box given in the local frame.
    Aabb apply(const Aabb& local) const;
};

// Motion of one edit over time t (seconds):
//   translation(t) = translation + velocity t + acceleration t^2 / 2, then, with wrap, the y
//   coordinate folded into [wrap_lo, wrap_hi) (falling things re-enter at the top);
//   rotation(t) = rotation about spin_axis by spin_rate * t (radians), applied after the rest rotation.
struct Animation {
    glm::dvec3 velocity{0.0};
    glm::dvec3 acceleration{0.0};
    glm::dvec3 spin_axis{0.0, 1.0, 0.0};
    double spin_rate = 0.0;
    std::optional<std::array<double, 2>> wrap_y;
};

struct Edit {
    Primitive primitive = Primitive::Sphere;
    std::array<double, 4> params{};  // meaning per primitive: see kernels/sdf_types.h
    // Mesh edits: the mesh, shared by every copy of the edit (scene_at keeps it); params[3] is its
    // index in the scene (scene/mesh.h, make_mesh_edit).
    std::shared_ptr<MeshSource> mesh;
    Transform transform;             // primitive frame -> geometry frame
    Op op = Op::Add;
    double blend = 0.0;              // smooth blend radius k (geometry units); 0 = hard
    std::optional<Animation> animation;
};

struct Geometry {
    std::string name;
    std::vector<Edit> edits;
};

struct Object {
    std::string name;
    std::size_t geometry = 0;  // index into Scene::geometries
    Transform transform;       // geometry frame -> world (rigid + uniform scale)
};

struct Camera {
    enum class Kind { Orbit, LookAt } kind = Kind::Orbit;
    // orbit: the eye circles `target` at `distance`; yaw about +y, pitch above the xz plane.
    glm::dvec3 target{0.0};
    double distance = 5.0;
    double yaw_deg = 30.0;
    double pitch_deg = 20.0;
    // look_at
    glm::dvec3 eye{0.0, 0.0, 5.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_deg = 45.0;  // vertical field of view

    glm::dvec3 eye_position() const;  // resolved eye for either kind
};

struct Light {
    glm::dvec3 direction{-0.4, -1.0, -0.3};  // direction the light travels (need not be unit in the file)
    glm::dvec3 color{1.0, 1.0, 1.0};
    double intensity = 1.0;
};

struct Scene {
    std::string name;
    double time = 0.0;  // the time the scene is evaluated at (seconds)
    std::vector<Geometry> geometries;
    std::vector<Object> objects;
    Camera camera;
    Light light;
    // What reading the file changed to make sense of it, one line each (a mesh's winding turned);
    // the CLI prints them as warnings. Not part of the scene's JSON.
    std::vector<std::string> warnings;
};

// ---- per-edit properties (scene.cpp) ----

// The primitive's Lipschitz bound L >= 1: |v(a) - v(b)| <= L |a - b| for the primitive's formula.
// Every analytic formula is 1-Lipschitz (docs/scene-format.md gives the argument; tests check it);
// a mesh's trilinear grid lookup is sqrt(3)-Lipschitz (kernels/sdf_edit.h, sdf_mesh).
double lipschitz(const Edit& e);

// AABB in the edit's local (primitive) frame of { x : primitive(x) <= c }, c >= 0.
Aabb local_level_bounds(const Edit& e, double c);
// AABB in the geometry frame of { p : edit value(p) <= c }, where the edit value is
// primitive(local(p)) * scale / L. level 0 = the solid; level `blend` = the range of influence.
Aabb level_bounds(const Edit& e, double c);
inline Aabb bounds(const Edit& e) { return level_bounds(e, 0.0); }
inline Aabb influence_bounds(const Edit& e) { return level_bounds(e, e.blend); }

// The edit as it is at time t (animation applied and dropped).
Edit edit_at(const Edit& e, double t);
Geometry geometry_at(const Geometry& g, double t);
Scene scene_at(const Scene& s, double t);

// Bounds of the solid of a geometry: the union of its add edits' influence bounds (level k sets).
// smin(F, v, k) >= max(F, v) - k, so smin <= 0 needs F <= 0 or v <= k; subtract and intersect only
// remove material. Empty when the geometry has no add edit.
Aabb bounds(const Geometry& g);
// World bounds of an object.
Aabb bounds(const Scene& s, const Object& o);

}  // namespace sdfbrick
