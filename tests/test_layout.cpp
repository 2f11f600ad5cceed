// The shared structs (kernels/sdf_types.h) must have the same size and field offsets on the host
// and on the device: the device reports its layout through kernels/layout_probe.cl.
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
            0xC0FFEEu};
}

TEST(Layout, HostSizesHaveNoPadding) {
    static_assert(sizeof(SdfTransform) == 8 * 4);
    static_assert(sizeof(SdfEdit) == 16 * 4);
    static_assert(sizeof(SdfBounds) == 6 * 4);
    static_assert(sizeof(SdfBrick) == 8 * 4);
    static_assert(alignof(SdfEdit) == 4 && alignof(SdfBrick) == 4);
}

TEST(Layout, DeviceMatchesHost) {
    ocl::Device& device = test::device();
    const ocl::Program program = ocl::build_program(device, "layout_probe.cl");
    const ocl::Kernel kernel = ocl::make_kernel(program, "layout_probe");
    const std::vector<cl_uint> expected = host_layout();
    ocl::Buffer<SdfEdit> edit(device, 1);
    ocl::Buffer<SdfBounds> bounds(device, 1);
    ocl::Buffer<SdfBrick> brick(device, 1);
    ocl::Buffer<cl_uint> out(device, std::vector<cl_uint>(expected.size() + 4, 0u));
    ocl::set_args(kernel.get(), edit, bounds, brick, out);
    ocl::enqueue(device, kernel.get(), "layout_probe", 1);
    const std::vector<cl_uint> got = out.read();
    const char* names[] = {"sizeof SdfTransform", "sizeof SdfEdit", "sizeof SdfBounds", "sizeof SdfBrick",
                           "SdfEdit.transform.translation", "SdfEdit.transform.scale", "SdfEdit.transform.rotation",
                           "SdfEdit.params", "SdfEdit.blend", "SdfEdit.inv_lipschitz", "SdfEdit.primitive",
                           "SdfEdit.op", "SdfBounds.lo", "SdfBounds.hi", "SdfBrick.coord", "SdfBrick.level",
                           "SdfBrick.edit_offset", "SdfBrick.edit_count", "SdfBrick.child_mask", "end marker"};
    ASSERT_EQ(std::size(names), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(got[i], expected[i]) << names[i];
}

}  // namespace
}  // namespace sdfbrick
