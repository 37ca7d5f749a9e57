// Evaluation metrics on hand-made cases; every expected value is worked out in the
// comments from the definitions in disparity_evaluation.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ground_test_files.hpp"
#include "vtm/ground/disparity_evaluation.hpp"

namespace vtm::ground {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Ground truth 10 px everywhere except pixel 4 (0 = unknown). Absolute errors of the
// estimate: 0, 0.5, 1.5, no match, (excluded), 2.5, 1.0, 3.0 (NaN = no match too at 8).
struct Case {
    FloatImage gt{9, 1, 1, 10.0F};
    FloatImage est{9, 1};
    Case() {
        gt.pixels[4] = 0.0F;
        est.pixels = {10.0F, 10.5F, 11.5F, kInf, 3.0F, 7.5F, 11.0F, 13.0F, std::nanf("")};
    }
};

TEST(DisparityEvaluation, HandComputedBadPixelsInvalidAndMae) {
    const Case c;
    const Result<DisparityErrors> r = evaluateDisparity(c.est, c.gt);
    ASSERT_TRUE(r.ok) << r.error;
    // Evaluated: 8 pixels (all but the unknown one). No match: pixels 3 and 8.
    EXPECT_EQ(r.value.evaluated_pixels, 8);
    EXPECT_EQ(r.value.matched_pixels, 6);
    // > 0.5: 1.5, 2.5, 1.0, 3.0 + 2 no match = 6/8 (0.5 itself is not bad: strict >).
    EXPECT_DOUBLE_EQ(r.value.bad05_percent, 75.0);
    // > 1: 1.5, 2.5, 3.0 + 2 = 5/8 (1.0 is not bad).
    EXPECT_DOUBLE_EQ(r.value.bad1_percent, 62.5);
    // > 2: 2.5, 3.0 + 2 = 4/8.
    EXPECT_DOUBLE_EQ(r.value.bad2_percent, 50.0);
    EXPECT_DOUBLE_EQ(r.value.invalid_percent, 25.0);
    // MAE over the 6 matched: (0 + 0.5 + 1.5 + 2.5 + 1.0 + 3.0) / 6 = 8.5 / 6.
    EXPECT_DOUBLE_EQ(r.value.mae_px, 8.5 / 6.0);
}

TEST(DisparityEvaluation, MaskRestrictsThePixels) {
    const Case c;
    GreyImage mask(9, 1, 1, 255);
    mask.pixels[3] = 0;  // drop one no-match pixel and the 3.0 error
    mask.pixels[7] = 0;
    const Result<DisparityErrors> r = evaluateDisparity(c.est, c.gt, &mask);
    ASSERT_TRUE(r.ok) << r.error;
    // Left: errors 0, 0.5, 1.5, 2.5, 1.0 and one no match (pixel 8): 6 pixels.
    EXPECT_EQ(r.value.evaluated_pixels, 6);
    EXPECT_DOUBLE_EQ(r.value.bad05_percent, 100.0 * 4.0 / 6.0);  // 1.5, 2.5, 1.0, no match
    EXPECT_DOUBLE_EQ(r.value.bad1_percent, 100.0 * 3.0 / 6.0);   // 1.5, 2.5, no match
    EXPECT_DOUBLE_EQ(r.value.bad2_percent, 100.0 * 2.0 / 6.0);   // 2.5, no match
    EXPECT_DOUBLE_EQ(r.value.invalid_percent, 100.0 / 6.0);
    EXPECT_DOUBLE_EQ(r.value.mae_px, 5.5 / 5.0);
}

TEST(DisparityEvaluation, InfiniteGroundTruthIsUnknownToo) {
    FloatImage gt(2, 1, 1, kInf);
    gt.pixels[1] = 4.0F;
    FloatImage est(2, 1, 1, 4.0F);
    const Result<DisparityErrors> r = evaluateDisparity(est, gt);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.evaluated_pixels, 1);
    EXPECT_DOUBLE_EQ(r.value.bad05_percent, 0.0);
    EXPECT_DOUBLE_EQ(r.value.mae_px, 0.0);
}

TEST(DisparityEvaluation, RefusesSizeMismatchAndEmptySelection) {
    const FloatImage a(3, 2, 1, 1.0F);
    const FloatImage b(2, 3, 1, 1.0F);
    Result<DisparityErrors> r = evaluateDisparity(a, b);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("disparity is 3x2 but ground truth is 2x3"), std::string::npos) << r.error;

    const GreyImage small_mask(1, 1, 1, 255);
    r = evaluateDisparity(a, a, &small_mask);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("mask is 1x1"), std::string::npos) << r.error;

    const GreyImage empty_mask(3, 2, 1, 0);
    r = evaluateDisparity(a, a, &empty_mask);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("no pixel to evaluate"), std::string::npos) << r.error;
}

TEST(GroundTruthLoader, DividesLevelsByScaleAndMarksZeroUnknown) {
    test::TempDir dir;
    test::writeBytes(dir.file("gt.pgm"), test::pgmBytes(3, 1, {0, 211, 255}));
    const Result<FloatImage> r = loadGroundTruth(dir.file("gt.pgm"), 4.0);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.at(0, 0), kInf);
    EXPECT_EQ(r.value.at(1, 0), 52.75F);
    EXPECT_EQ(r.value.at(2, 0), 63.75F);

    const Result<FloatImage> bad = loadGroundTruth(dir.file("gt.pgm"), 0.0);
    EXPECT_FALSE(bad.ok);
    EXPECT_NE(bad.error.find("scale must be a positive number"), std::string::npos) << bad.error;
}

TEST(GroundTruthLoader, ReadsPfmInPixels) {
    test::TempDir dir;
    // Hand-written: 2x1, little endian, values 0 (unknown) and 12.5.
    test::Bytes b = test::textBytes("Pf\n2 1\n-1\n");
    b.insert(b.end(), {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x48, 0x41});
    test::writeBytes(dir.file("gt.pfm"), b);
    const Result<FloatImage> r = loadGroundTruth(dir.file("gt.pfm"), 1.0);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.at(0, 0), kInf);
    EXPECT_EQ(r.value.at(1, 0), 12.5F);
}

}  // namespace
}  // namespace vtm::ground
