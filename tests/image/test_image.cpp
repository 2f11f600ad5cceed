// Image writing: the built-in PPM and PFM writers, OpenImageIO formats where the build has them,
// and no partial file when a write fails.
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/files.h"
#include "image/image.h"
#include "test_support.h"

namespace sdfbrick {
namespace {

Image gradient_image() {
    Image img(4, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            float* p = img.at(x, y);
            p[0] = static_cast<float>(x) / 3.0f;
            p[1] = static_cast<float>(y);
            p[2] = 2.0f;  // out of range: clamped to 1 in 8-bit formats
        }
    return img;
}

TEST(Image, PpmHasHeaderAndClampedBytes) {
    const auto dir = test::temp_dir("image_ppm");
    write_image(gradient_image(), dir / "a.ppm");
    const std::string bytes = read_file(dir / "a.ppm");
    const std::string header = "P6\n4 2\n255\n";
    ASSERT_EQ(bytes.size(), header.size() + 4 * 2 * 3);
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    const auto* px = reinterpret_cast<const unsigned char*>(bytes.data() + header.size());
    EXPECT_EQ(px[0], 0);       // x = 0, red 0
    EXPECT_EQ(px[3 * 3], 255); // x = 3, red 1
    EXPECT_EQ(px[2], 255);     // blue 2.0 clamped
    EXPECT_EQ(px[3 * 4 + 1], 255);  // second row, green 1
}

TEST(Image, PfmStoresFloatsBottomRowFirst) {
    const auto dir = test::temp_dir("image_pfm");
    write_image(gradient_image(), dir / "a.pfm");
    const std::string bytes = read_file(dir / "a.pfm");
    const std::string header = "PF\n4 2\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 4 * 2 * 3 * sizeof(float));
    float first[3];
    std::memcpy(first, bytes.data() + header.size(), sizeof(first));
    EXPECT_EQ(first[1], 1.0f);  // the bottom row (y = 1) comes first
    EXPECT_EQ(first[2], 2.0f);  // floats are not clamped
}

TEST(Image, PngFollowsTheBuild) {
    const auto dir = test::temp_dir("image_png");
    if (image_io_has_oiio()) {
        write_image(gradient_image(), dir / "a.png");
        EXPECT_EQ(read_file(dir / "a.png").substr(1, 3), "PNG");
    } else {
        EXPECT_THROW(write_image(gradient_image(), dir / "a.png"), InputError);
        EXPECT_FALSE(std::filesystem::exists(dir / "a.png"));
    }
}

TEST(Image, FailedWriteLeavesNothing) {
    const auto dir = test::temp_dir("image_fail");
    EXPECT_THROW(write_image(gradient_image(), dir / "missing" / "a.ppm"), std::exception);
    EXPECT_THROW(write_image(gradient_image(), dir / "a.unknownformat"), InputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace sdfbrick
