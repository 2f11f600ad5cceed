// Tests of fault injection (host/core/fault.h): the SDFBRICK_FAULT grammar, counting per item and per
// device, and that each injection point fails the real code path with one clear message.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cl/buffer.h"
#include "cl/cl_error.h"
#include "core/errors.h"
#include "core/fault.h"
#include "core/files.h"
#include "test_support.h"

namespace sdfbrick::fault {
namespace {

// Sets SDFBRICK_FAULT for the scope and re-reads it; restores and re-reads it afterwards.
class ScopedFault {
public:
    explicit ScopedFault(const std::string& value) : env_(kEnv, value) { reset(); }

private:
    struct ResetLast {  // destroyed after env_ has restored the variable
        ~ResetLast() { reset(); }
    } reset_last_;
    test::ScopedEnv env_;
};

TEST(CoreFault, OffWithoutTheVariable) {
    const ScopedFault fault("");
    for (int i = 0; i < 100; ++i) EXPECT_FALSE(should_fail(Point::launch, 0));
}

TEST(CoreFault, CountsEachItemItsOwnWay) {
    const ScopedFault fault("launch@1:3,write:2,launch:4");
    EXPECT_FALSE(should_fail(Point::launch, 0));  // launch:4 sees 1
    EXPECT_FALSE(should_fail(Point::launch, 1));  // launch@1:3 sees 1, launch:4 sees 2
    EXPECT_FALSE(should_fail(Point::launch, 1));  // 2, 3
    EXPECT_TRUE(should_fail(Point::launch, 0));   // launch:4 sees 4
    EXPECT_TRUE(should_fail(Point::launch, 1));   // launch@1:3 sees 3
    EXPECT_FALSE(should_fail(Point::launch, 1));  // each item fires once
    EXPECT_FALSE(should_fail(Point::write));
    EXPECT_TRUE(should_fail(Point::write));
    EXPECT_FALSE(should_fail(Point::alloc, 1));
}

TEST(CoreFault, RefusesAMalformedValueNamingTheItem) {
    for (const char* bad : {"launch", "launch:0", "launch:x", "jump:1", "launch@x:1", "launch:-1"}) {
        const ScopedFault fault(bad);
        try {
            should_fail(Point::launch, 0);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("SDFBRICK_FAULT"), std::string::npos) << e.what();
        }
    }
}

TEST(CoreFault, AnAllocationFailsAsOutOfMemoryOnTheNamedDevice) {
    ocl::Device& device = test::device();
    const ScopedFault fault("alloc@" + std::to_string(device.info().index) + ":2");
    const ocl::Buffer<float> first(device, 16);
    try {
        const ocl::Buffer<float> second(device, 16);
        ADD_FAILURE() << "the second allocation succeeded";
    } catch (const ocl::ClError& e) {
        EXPECT_EQ(e.code(), CL_MEM_OBJECT_ALLOCATION_FAILURE);
        EXPECT_NE(std::string(e.what()).find("injected fault"), std::string::npos) << e.what();
    }
    const ocl::Buffer<float> third(device, 16);
}

TEST(CoreFault, AFailedWriteLeavesNothing) {
    const std::filesystem::path dir = test::temp_dir("core_fault_write");
    const ScopedFault fault("write:1");
    EXPECT_THROW(write_file_atomic(dir / "out.txt", "text"), InputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    write_file_atomic(dir / "out.txt", "text");
    EXPECT_EQ(read_file(dir / "out.txt"), "text");
}

}  // namespace
}  // namespace sdfbrick::fault
