// The brick layout: sizes, quantisation and the kernel defines, for every sample count and format.
#include <gtest/gtest.h>

#include "construct/brick_layout.h"

namespace sdfbrick {
namespace {

using construct::BrickFormat;
using construct::BrickLayout;

TEST(ConstructBrickLayout, SizesPerSampleCountAndFormat) {
    const BrickLayout a{8, BrickFormat::int8};
    EXPECT_EQ(a.apron(), 1);
    EXPECT_EQ(a.interior(), 6);
    EXPECT_EQ(a.samples_per_brick(), 512u);
    EXPECT_EQ(a.brick_bytes(), 512u);
    const BrickLayout b{10, BrickFormat::int16};
    EXPECT_EQ(b.apron(), 2);
    EXPECT_EQ(b.interior(), 6);
    EXPECT_EQ(b.brick_bytes(), 2000u);
    EXPECT_EQ((BrickLayout{8, BrickFormat::float32}.brick_bytes()), 2048u);
}

TEST(ConstructBrickLayout, QuantisationRoundTripsTheBand) {
    const float band = 0.041666668f;
    for (BrickFormat f : {BrickFormat::int8, BrickFormat::int16}) {
        const BrickLayout l{8, f};
        // The largest stored value means the band, within one rounding of each scale.
        EXPECT_NEAR(l.levels() * l.dequantise_scale(band), band, band * 1e-6) << to_string(f);
        EXPECT_NEAR(band * l.quantise_scale(band), l.levels(), l.levels() * 1e-6) << to_string(f);
    }
    const BrickLayout fl{8, BrickFormat::float32};
    EXPECT_EQ(fl.quantise_scale(band), 1.0f);
    EXPECT_EQ(fl.dequantise_scale(band), 1.0f);
    EXPECT_EQ((BrickLayout{8, BrickFormat::int8}.quantise_scale(0.5f)), 254.0f);
    EXPECT_EQ((BrickLayout{8, BrickFormat::int16}.dequantise_scale(32767.0f)), 1.0f);
}

TEST(ConstructBrickLayout, DefinesNameSamplesApronAndFormat) {
    EXPECT_EQ((BrickLayout{8, BrickFormat::int8}.defines()), "-DSAMPLES=8 -DAPRON=1 -DFORMAT=0");
    EXPECT_EQ((BrickLayout{10, BrickFormat::int16}.defines()), "-DSAMPLES=10 -DAPRON=2 -DFORMAT=1");
    EXPECT_EQ((BrickLayout{8, BrickFormat::float32}.defines()), "-DSAMPLES=8 -DAPRON=1 -DFORMAT=2");
    for (BrickFormat f : {BrickFormat::int8, BrickFormat::int16, BrickFormat::float32})
        EXPECT_EQ(construct::format_from_string(to_string(f)), f);
    EXPECT_FALSE(construct::format_from_string("int4").has_value());
}

}  // namespace
}  // namespace sdfbrick
