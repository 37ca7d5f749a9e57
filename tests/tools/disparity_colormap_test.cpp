// Colour map of the paper's Figure 3: largest disparity red, smallest purple, no match
// black; the hue ramp passes yellow, green, cyan and blue in that order.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "vtm/ground/disparity_colormap.hpp"

namespace vtm::ground {
namespace {

const Rgb kRed = {255, 0, 0};
const Rgb kPurple = {128, 0, 255};  // hue 270 deg: half red, full blue
const Rgb kBlack = {0, 0, 0};

TEST(DisparityColormap, EndpointsAndNoMatch) {
    EXPECT_EQ(disparityColor(60.0F, 10.0F, 60.0F), kRed);
    EXPECT_EQ(disparityColor(10.0F, 10.0F, 60.0F), kPurple);
    EXPECT_EQ(disparityColor(std::numeric_limits<float>::infinity(), 10.0F, 60.0F), kBlack);
    EXPECT_EQ(disparityColor(std::nanf(""), 10.0F, 60.0F), kBlack);
}

TEST(DisparityColormap, OutOfRangeClampsToEndColours) {
    EXPECT_EQ(disparityColor(99.0F, 10.0F, 60.0F), kRed);
    EXPECT_EQ(disparityColor(-5.0F, 10.0F, 60.0F), kPurple);
}

TEST(DisparityColormap, HueRampPassesYellowGreenCyanBlue) {
    // hue = (1 - t) * 270 deg over d in [0, 270]: d = 270 - hue.
    EXPECT_EQ(disparityColor(210.0F, 0.0F, 270.0F), (Rgb{255, 255, 0}));  // 60 deg yellow
    EXPECT_EQ(disparityColor(150.0F, 0.0F, 270.0F), (Rgb{0, 255, 0}));    // 120 deg green
    EXPECT_EQ(disparityColor(90.0F, 0.0F, 270.0F), (Rgb{0, 255, 255}));   // 180 deg cyan
    EXPECT_EQ(disparityColor(30.0F, 0.0F, 270.0F), (Rgb{0, 0, 255}));     // 240 deg blue
}

TEST(DisparityColormap, ImageHasThreeChannelsAndBlackHoles) {
    FloatImage d(3, 1);
    d.pixels = {0.0F, std::numeric_limits<float>::infinity(), 8.0F};
    const GreyImage rgb = colorizeDisparity(d, 0.0F, 8.0F);
    ASSERT_EQ(rgb.channels, 3);
    ASSERT_EQ(rgb.pixels.size(), 9U);
    EXPECT_EQ((Rgb{rgb.at(0, 0, 0), rgb.at(0, 0, 1), rgb.at(0, 0, 2)}), kPurple);
    EXPECT_EQ((Rgb{rgb.at(1, 0, 0), rgb.at(1, 0, 1), rgb.at(1, 0, 2)}), kBlack);
    EXPECT_EQ((Rgb{rgb.at(2, 0, 0), rgb.at(2, 0, 1), rgb.at(2, 0, 2)}), kRed);
}

}  // namespace
}  // namespace vtm::ground
