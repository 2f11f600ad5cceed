// The shared structs (kernels/sdf_types.h) must have the same size and field offsets on the host
// and on the device: the device reports its layout through tests/kernels/layout_probe.cl.
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "cl/buffer.h"
#include "cl/launch.h"
#include "cl/program.h"
#include "sdf_types.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

// The host's view, in the order layout_probe.cl writes them.
std::vector<cl_uint> host_layout() {
    return {sizeof(SdfTransform),
            sizeof(SdfEdit),
            sizeof(SdfBounds),
            sizeof(SdfBrick),
            offsetof(SdfEdit, transform.translation),
            offsetof(SdfEdit, transform.scale),
            offsetof(SdfEdit, transform.rotation),
            offsetof(SdfEdit, params),
            offsetof(SdfEdit, blend),
            offsetof(SdfEdit, inv_lipschitz),
            offsetof(SdfEdit, primitive),
            offsetof(SdfEdit, op),
            offsetof(SdfBounds, lo),
            offsetof(SdfBounds, hi),
            offsetof(SdfBrick, coord),
            offsetof(SdfBrick, level),
            offsetof(SdfBrick, edit_offset),
            offsetof(SdfBrick, edit_count),
            offsetof(SdfBrick, child_mask),
            sizeof(SdfCamera),
            offsetof(SdfCamera, forward),
            offsetof(SdfCamera, right),
            offsetof(SdfCamera, up),
            offsetof(SdfCamera, width),
            offsetof(SdfCamera, height),
            sizeof(SdfBvhNode),
            offsetof(SdfBvhNode, hi0),
            offsetof(SdfBvhNode, lo1),
            offsetof(SdfBvhNode, hi1),
            offsetof(SdfBvhNode, child),
            sizeof(SdfBvhWideNode),
            offsetof(SdfBvhWideNode, lo_y),
            offsetof(SdfBvhWideNode, hi_x),
            offsetof(SdfBvhWideNode, child),
            sizeof(SdfInstance),
            offsetof(SdfInstance, translation),
            offsetof(SdfInstance, scale),
            offsetof(SdfInstance, geometry),
            sizeof(SdfBrickGeometry),
            offsetof(SdfBrickGeometry, inv_voxel),
            offsetof(SdfBrickGeometry, dequant),
            offsetof(SdfBrickGeometry, root),
            offsetof(SdfBrickGeometry, brick_offset),
            sizeof(SdfShading),
            offsetof(SdfShading, light_color),
            offsetof(SdfShading, shadow_spread),
            offsetof(SdfShading, ao_radius),
            offsetof(SdfShading, ray_offset),
            offsetof(SdfShading, shadow_rays),
            offsetof(SdfShading, ao_rays),
            sizeof(SdfMeshGrid),
            offsetof(SdfMeshGrid, cell),
            offsetof(SdfMeshGrid, inv_cell),
            offsetof(SdfMeshGrid, dims),
            offsetof(SdfMeshGrid, offset),
            offsetof(SdfMeshGrid, tiles),
            offsetof(SdfMeshGrid, coarse),
            offsetof(SdfMeshGrid, centres),
            sizeof(SdfPrepared),
            offsetof(SdfPrepared, inv_scale),
            offsetof(SdfPrepared, q),
            offsetof(SdfPrepared, prm),
            offsetof(SdfPrepared, out_scale),
            offsetof(SdfPrepared, blend),
            offsetof(SdfPrepared, blend_q),
            offsetof(SdfPrepared, kind),
            0xC0FFEEu};
}

TEST(KernelsLayout, HostSizesHaveNoPadding) {
    static_assert(sizeof(SdfTransform) == 8 * 4);
    static_assert(sizeof(SdfEdit) == 16 * 4);
    static_assert(sizeof(SdfBounds) == 6 * 4);
    static_assert(sizeof(SdfBrick) == 8 * 4);
    static_assert(sizeof(SdfCamera) == 14 * 4);
    static_assert(sizeof(SdfBvhNode) == 16 * 4);  // four 16-byte loads in sdf_trace.h
    static_assert(offsetof(SdfBvhNode, child) == 48);
    static_assert(sizeof(SdfBvhWideNode) == 32 * 4);  // eight 16-byte loads in sdf_trace.h
    static_assert(offsetof(SdfBvhWideNode, hi_x) == 48 && offsetof(SdfBvhWideNode, child) == 96);
    static_assert(sizeof(SdfInstance) == 16 * 4);
    static_assert(sizeof(SdfBrickGeometry) == 8 * 4);
    static_assert(sizeof(SdfShading) == 12 * 4);
    static_assert(sizeof(SdfMeshGrid) == 12 * 4);  // the mesh pool holds headers as 12 floats each
    static_assert(sizeof(SdfPrepared) == sizeof(SdfEdit));  // the staged chunks' local memory, as tuned
    static_assert(alignof(SdfEdit) == 4 && alignof(SdfBrick) == 4);
}

TEST(KernelsLayout, DeviceMatchesHost) {
    ocl::Device& device = test::device();
    const ocl::Program program = ocl::build_program(device, "layout_probe.cl");
    const ocl::Kernel kernel = ocl::make_kernel(program, "layout_probe");
    const std::vector<cl_uint> expected = host_layout();
    ocl::Buffer<SdfEdit> edit(device, 1);
    ocl::Buffer<SdfBounds> bounds(device, 1);
    ocl::Buffer<SdfBrick> brick(device, 1);
    ocl::Buffer<SdfCamera> camera(device, 1);
    ocl::Buffer<SdfBvhNode> node(device, 1);
    ocl::Buffer<SdfBvhWideNode> wide(device, 1);
    ocl::Buffer<SdfInstance> instance(device, 1);
    ocl::Buffer<SdfBrickGeometry> geometry(device, 1);
    ocl::Buffer<SdfShading> shading(device, 1);
    ocl::Buffer<SdfMeshGrid> mesh(device, 1);
    ocl::Buffer<SdfPrepared> prepared(device, 1);
    ocl::Buffer<cl_uint> out(device, std::vector<cl_uint>(expected.size() + 4, 0u));
    ocl::set_args(kernel.get(), edit, bounds, brick, camera, node, wide, instance, geometry, shading, mesh, prepared, out);
    ocl::enqueue(device, kernel.get(), "layout_probe", 1);
    const std::vector<cl_uint> got = out.read();
    const char* names[] = {"sizeof SdfTransform", "sizeof SdfEdit", "sizeof SdfBounds", "sizeof SdfBrick",
                           "SdfEdit.transform.translation", "SdfEdit.transform.scale", "SdfEdit.transform.rotation",
                           "SdfEdit.params", "SdfEdit.blend", "SdfEdit.inv_lipschitz", "SdfEdit.primitive",
                           "SdfEdit.op", "SdfBounds.lo", "SdfBounds.hi", "SdfBrick.coord", "SdfBrick.level",
                           "SdfBrick.edit_offset", "SdfBrick.edit_count", "SdfBrick.child_mask",
                           "sizeof SdfCamera", "SdfCamera.forward", "SdfCamera.right", "SdfCamera.up",
                           "SdfCamera.width", "SdfCamera.height", "sizeof SdfBvhNode", "SdfBvhNode.hi0",
                           "SdfBvhNode.lo1", "SdfBvhNode.hi1", "SdfBvhNode.child", "sizeof SdfBvhWideNode",
                           "SdfBvhWideNode.lo_y", "SdfBvhWideNode.hi_x", "SdfBvhWideNode.child", "sizeof SdfInstance",
                           "SdfInstance.translation", "SdfInstance.scale", "SdfInstance.geometry",
                           "sizeof SdfBrickGeometry", "SdfBrickGeometry.inv_voxel", "SdfBrickGeometry.dequant",
                           "SdfBrickGeometry.root", "SdfBrickGeometry.brick_offset", "sizeof SdfShading",
                           "SdfShading.light_color", "SdfShading.shadow_spread", "SdfShading.ao_radius",
                           "SdfShading.ray_offset", "SdfShading.shadow_rays", "SdfShading.ao_rays", "sizeof SdfMeshGrid",
                           "SdfMeshGrid.cell", "SdfMeshGrid.inv_cell", "SdfMeshGrid.dims", "SdfMeshGrid.offset",
                           "SdfMeshGrid.tiles", "SdfMeshGrid.coarse", "SdfMeshGrid.centres",
                           "sizeof SdfPrepared", "SdfPrepared.inv_scale", "SdfPrepared.q", "SdfPrepared.prm",
                           "SdfPrepared.out_scale", "SdfPrepared.blend", "SdfPrepared.blend_q", "SdfPrepared.kind",
                           "end marker"};
    ASSERT_EQ(std::size(names), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(got[i], expected[i]) << names[i];
}

}  // namespace
}  // namespace sdfbrick
