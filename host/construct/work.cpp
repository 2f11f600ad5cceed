#include "construct/work.h"

namespace sdfbrick::construct {

namespace {

double primitive_flops(const SdfEdit& e) {
    switch (e.primitive) {
    case SDF_PRIM_SPHERE: return 7;      // a norm of 3 (6) and a subtraction
    case SDF_PRIM_BOX: return 19;        // 3 fabs, 3 sub, 3 fmax, a norm (6), 2 fmax, fmin, add
    case SDF_PRIM_ROUND_BOX: return 20;  // a box and a subtraction
    case SDF_PRIM_TORUS: return 10;      // two lengths of 2 (4 each) and two subtractions
    case SDF_PRIM_CAPSULE: return 10;    // clamp (2), sub, norm (6), sub
    case SDF_PRIM_CYLINDER: return 16;
    case SDF_PRIM_CONE: return 31;
    case SDF_PRIM_ELLIPSOID: return 11;  // 3 divisions, norm, sub, mul
    case SDF_PRIM_MENGER: return 23 + 38 * static_cast<double>(e.params[1]);  // box and 3 divisions, then per iteration
    case SDF_PRIM_MESH: return 53;       // grid coordinates, clamp, outside distance, 7 lerps
    default: return 0;
    }
}

}  // namespace

double edit_flops(const SdfEdit& e) {
    const SdfTransform& t = e.transform;
    const bool rotated = !(t.rotation[0] == 0.0f && t.rotation[1] == 0.0f && t.rotation[2] == 0.0f && t.rotation[3] == 1.0f);
    const float out_scale = t.scale * e.inv_lipschitz;
    double flop = 3;                     // p - translation
    if (rotated) flop += 30;             // the quaternion rotation
    if (1.0f / t.scale != 1.0f) flop += 3;
    flop += primitive_flops(e);
    if (out_scale != 1.0f) flop += 1;
    flop += e.blend > 0.0f ? 8 : 1;      // smooth: |a - b|, k - ., fmax, fmin, w w q, sub; hard: fmin or fmax
    if (e.op == SDF_OP_SUBTRACT) flop += 1;
    return flop + 2;                     // the saturation clamp
}

}  // namespace sdfbrick::construct
