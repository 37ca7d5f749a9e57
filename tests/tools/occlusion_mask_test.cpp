// Non-occluded masks on synthetic rows whose occlusions are worked out by hand.
//
// Scene (one row, 10 px): background at disparity 2 everywhere, a nearer box at
// disparity 5 on left columns 6..9. In the right image (column = x - d) the box covers
// columns 1..4, the background is seen at column 0 (from left x = 2) and 5..9. So:
//   left x = 0, 1: right column -2, -1, outside the image       -> occluded
//   left x = 2:    column 0, background visible                  -> evaluate
//   left x = 3..5: columns 1..3, behind the box (3 = 5 - 2 px)   -> occluded
//   left x = 6..9: the box itself, columns 1..4                  -> evaluate
// The row-visibility rule allows 1 px (the README's rule): x = 3, 4 land at 1 and 2,
// within 1 px of the box's leftmost column 1, and count as visible; x = 5 (3) does not.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "vtm/ground/occlusion_mask.hpp"

namespace vtm::ground {
namespace {

const std::vector<std::uint8_t> kExpected = {0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
const std::vector<std::uint8_t> kExpectedVisibility = {0, 0, 255, 255, 255, 0, 255, 255, 255, 255};

FloatImage row(const std::vector<float>& d) {
    FloatImage img(static_cast<std::int32_t>(d.size()), 1);
    img.pixels = d;
    return img;
}

FloatImage boxLeft() { return row({2, 2, 2, 2, 2, 2, 5, 5, 5, 5}); }
// Right-view truth of the same scene: box at right columns 1..4, background elsewhere.
FloatImage boxRight() { return row({2, 5, 5, 5, 5, 2, 2, 2, 2, 2}); }

TEST(VisibilityMask, BoxInFrontOfBackground) {
    EXPECT_EQ(visibilityMask(boxLeft()).pixels, kExpectedVisibility);
}

TEST(LeftRightCheckMask, BoxInFrontOfBackground) {
    const Result<GreyImage> m = leftRightCheckMask(boxLeft(), boxRight());
    ASSERT_TRUE(m.ok) << m.error;
    EXPECT_EQ(m.value.pixels, kExpected);
}

TEST(VisibilityMask, SlantedSurfaceDoesNotHideItself) {
    // d rises 0.5 px per pixel: the surface is compressed in the right view (samples
    // 0.5 px apart) but nothing is in front of anything. Only x = 0 and 1 (right
    // positions -1 and -0.5, left of the image) are out.
    std::vector<float> d;
    for (int x = 0; x < 10; ++x) {
        d.push_back(1.0F + 0.5F * static_cast<float>(x));
    }
    const GreyImage m = visibilityMask(row(d));
    EXPECT_EQ(m.pixels, (std::vector<std::uint8_t>{0, 0, 255, 255, 255, 255, 255, 255, 255, 255}));
}

TEST(VisibilityMask, UnknownPixelsAreExcludedAndHideNothing) {
    // Same box, but its truth unknown (0): the background behind it counts as visible.
    const GreyImage m = visibilityMask(row({2, 2, 2, 2, 2, 2, 0, 0, 0, std::numeric_limits<float>::infinity()}));
    EXPECT_EQ(m.pixels, (std::vector<std::uint8_t>{0, 0, 255, 255, 255, 255, 0, 0, 0, 0}));
}

TEST(LeftRightCheckMask, ToleranceRoundingAndUnknownRightTruth) {
    // x = 0: d = 0, truth unknown                          -> left out
    // x = 1, d = 1: column 0 holds 2.0 (1 px off)         -> visible (tolerance is inclusive)
    // x = 2, d = 1: column 1 holds 2.25 (1.25 px off)     -> occluded
    // x = 3, d = 0.5: position 2.5 rounds (halves up) to column 3, which holds 0.5 -> visible
    //                 (rounding down would hit column 2 = 9 and call it occluded)
    // x = 4, d = 1: column 3 holds 0.5 (0.5 px off)       -> visible
    const FloatImage left = row({0, 1, 1, 0.5F, 1});
    const FloatImage right = row({2, 2.25F, 9, 0.5F, 0});
    const Result<GreyImage> m = leftRightCheckMask(left, right);
    ASSERT_TRUE(m.ok) << m.error;
    EXPECT_EQ(m.value.pixels, (std::vector<std::uint8_t>{0, 255, 0, 255, 255}));

    // Right truth unknown where the left pixel lands: cannot verify, left out.
    const Result<GreyImage> u = leftRightCheckMask(row({0, 1}), row({0, 0}));
    ASSERT_TRUE(u.ok) << u.error;
    EXPECT_EQ(u.value.pixels, (std::vector<std::uint8_t>{0, 0}));
}

TEST(LeftRightCheckMask, RefusesDifferentSizes) {
    const Result<GreyImage> m = leftRightCheckMask(row({1, 1}), row({1, 1, 1}));
    EXPECT_FALSE(m.ok);
    EXPECT_NE(m.error.find("left ground truth is 2x1 but right ground truth is 3x1"), std::string::npos) << m.error;
}

TEST(MaskFraction, CountsNonzero) {
    GreyImage m(4, 1);
    m.pixels = {0, 255, 1, 0};
    EXPECT_DOUBLE_EQ(maskFraction(m), 0.5);
}

}  // namespace
}  // namespace vtm::ground
