/* fold_probe.cl: the count stage's fold without branches (sdf_fold_select on sdf_fold_params) beside
 * the combine it stands for (sdf_combine), for every edit and every (field, value) pair:
 * out[2 i] = sdf_combine, out[2 i + 1] = sdf_fold_select, i = edit * pairs + pair. For
 * tests/construct/test_brick_builder.cpp. */
#include "sdf_build.h"

__kernel void fold_probe(__global const SdfEdit* edits, __global const float* fields, __global const float* values,
                         uint edit_count, uint pairs, __global float* out) {
    const uint i = get_global_id(0);
    if (i >= edit_count * pairs) return;
    const SdfPrepared e = sdf_prepare(edits[i / pairs]);
    const float field = fields[i % pairs], v = values[i % pairs];
    out[2u * i] = sdf_combine(&e, field, v);
    out[2u * i + 1u] = sdf_fold_select(sdf_fold_params(&e), field, v);
}
