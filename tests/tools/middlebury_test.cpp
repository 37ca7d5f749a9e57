// The Middlebury loaders against the published data (shared/data/middlebury, README):
// sizes, ground-truth ranges as the README states them, and non-occluded masks that are
// plausible in size and photo-consistent. Skipped when the data directory is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ground_test_files.hpp"
#include "vtm/ground/disparity_evaluation.hpp"
#include "vtm/ground/middlebury.hpp"
#include "vtm/ground/occlusion_mask.hpp"

namespace vtm::ground {
namespace {

struct Range {
    float lo = INFINITY;
    float hi = -INFINITY;
};

Range knownRange(const FloatImage& gt) {
    Range r;
    for (float v : gt.pixels) {
        if (isKnownDisparity(v)) {
            r.lo = std::min(r.lo, v);
            r.hi = std::max(r.hi, v);
        }
    }
    return r;
}

class Middlebury : public ::testing::Test {
protected:
    // Loads a set or skips the test when the shared data is not there.
    MiddleburyPair load(const char* name) {
        const Result<MiddleburyPair> p = loadMiddleburyPair(test::testDataRoot(), name);
        if (!p.ok) {
            skipped_ = true;
            return {};
        }
        return p.value;
    }
    bool skipped_ = false;
};

#define LOAD_OR_SKIP(var, name)                                                   \
    const MiddleburyPair var = load(name);                                       \
    if (skipped_) {                                                              \
        VTM_REQUIRE_TEST_DATA(test::testDataSet("middlebury") + name);           \
        FAIL() << "Middlebury set " << name << " is there but does not load";   \
    }

TEST_F(Middlebury, GroundTruthRangesMatchTheReadme) {
    LOAD_OR_SKIP(tsukuba, "tsukuba");
    LOAD_OR_SKIP(venus, "venus");
    LOAD_OR_SKIP(teddy, "teddy");
    LOAD_OR_SKIP(cones, "cones");
    EXPECT_EQ(knownRange(tsukuba.truth.disparity_px).hi, 14.0F);  // "max d 14"
    EXPECT_EQ(knownRange(venus.truth.disparity_px).lo, 3.0F);     // "d in 3.0 .. 19.75"
    EXPECT_EQ(knownRange(venus.truth.disparity_px).hi, 19.75F);
    EXPECT_EQ(knownRange(teddy.truth.disparity_px).hi, 52.75F);  // "d up to 52.75"
    EXPECT_EQ(knownRange(cones.truth.disparity_px).hi, 55.0F);   // "d up to 55"
    // venus is dense: every pixel known.
    EXPECT_TRUE(std::all_of(venus.truth.disparity_px.pixels.begin(), venus.truth.disparity_px.pixels.end(),
                            isKnownDisparity));
}

TEST_F(Middlebury, ImagesAndTruthHaveTheReadmeSizes) {
    LOAD_OR_SKIP(tsukuba, "tsukuba");
    LOAD_OR_SKIP(teddy, "teddy");
    for (const MiddleburyPair* p : {&tsukuba, &teddy}) {
        EXPECT_TRUE(p->left.sameSize(p->right));
        EXPECT_TRUE(p->left.sameSize(p->truth.disparity_px));
        EXPECT_TRUE(p->left.sameSize(p->truth.nonoccluded));
        EXPECT_EQ(p->left.channels, 1);
    }
    EXPECT_EQ(tsukuba.left.width, 384);
    EXPECT_EQ(tsukuba.left.height, 288);
    EXPECT_EQ(teddy.left.width, 450);
    EXPECT_EQ(teddy.left.height, 375);
}

// Teddy: 98% of the left truth is known (2% unknown, 0 in disp2.png). The mask then
// loses the strip at the left edge whose match falls outside the right image (left-edge
// disparities of about 12..20 px on a 450 px row: ~3-4%) and the regions occluded at
// the depth edges of the teddy, the chimney and the boxes (a few % more). So 80..95%
// of all pixels; the data give 87%.
TEST_F(Middlebury, TeddyNonOccludedFractionIsPlausible) {
    LOAD_OR_SKIP(teddy, "teddy");
    const double f = maskFraction(teddy.truth.nonoccluded);
    EXPECT_GT(f, 0.80);
    EXPECT_LT(f, 0.95);
}

// The mask selects only pixels with known truth, and the leftmost column (x - d < 0
// for every d >= 1) is never evaluated.
TEST_F(Middlebury, MaskIsInsideKnownTruthAndExcludesLeftBorder) {
    for (const char* name : {"tsukuba", "venus", "teddy", "cones"}) {
        LOAD_OR_SKIP(p, name);
        const FloatImage& gt = p.truth.disparity_px;
        for (std::int32_t y = 0; y < gt.height; ++y) {
            EXPECT_EQ(p.truth.nonoccluded.at(0, y), 0) << name << " row " << y;
            for (std::int32_t x = 0; x < gt.width; ++x) {
                if (p.truth.nonoccluded.at(x, y) != 0) {
                    ASSERT_TRUE(isKnownDisparity(gt.at(x, y))) << name << " " << x << "," << y;
                }
            }
        }
    }
}

// What the mask means, checked against the images rather than the truth: where the mask
// says "visible", the left pixel and its right match (x - d) show the same surface, so
// their grey levels agree (a few levels); where it says "occluded", the right pixel shows
// a different surface. Measured: inside 3-6 grey levels, outside 44-71, on all four sets.
TEST_F(Middlebury, MaskedPixelsArePhotoConsistent) {
    for (const char* name : {"tsukuba", "venus", "teddy", "cones"}) {
        LOAD_OR_SKIP(p, name);
        const FloatImage& gt = p.truth.disparity_px;
        double sum[2] = {0.0, 0.0};
        double count[2] = {0.0, 0.0};
        for (std::int32_t y = 0; y < gt.height; ++y) {
            for (std::int32_t x = 0; x < gt.width; ++x) {
                const float d = gt.at(x, y);
                const auto xr = static_cast<std::int32_t>(std::floor(static_cast<double>(x) - d + 0.5));
                if (!isKnownDisparity(d) || xr < 0 || xr >= gt.width) {
                    continue;
                }
                const int in = p.truth.nonoccluded.at(x, y) != 0 ? 1 : 0;
                sum[in] += std::fabs(static_cast<double>(p.left.at(x, y)) - p.right.at(xr, y));
                count[in] += 1.0;
            }
        }
        const double inside = sum[1] / count[1];
        const double outside = sum[0] / count[0];
        EXPECT_LT(inside, 8.0) << name;
        EXPECT_GT(outside, 4.0 * inside) << name;
    }
}

TEST(MiddleburyTable, ScalesAndMaskMethodsFromTheReadme) {
    ASSERT_NE(findMiddleburySet("tsukuba"), nullptr);
    EXPECT_EQ(findMiddleburySet("tsukuba")->scale, 16.0);
    EXPECT_EQ(findMiddleburySet("venus")->scale, 8.0);
    EXPECT_EQ(findMiddleburySet("teddy")->scale, 4.0);
    EXPECT_EQ(findMiddleburySet("cones")->scale, 4.0);
    EXPECT_EQ(findMiddleburySet("teddy")->mask, MaskMethod::kLeftRightCheck);
    EXPECT_EQ(findMiddleburySet("venus")->mask, MaskMethod::kRowVisibility);
    EXPECT_EQ(findMiddleburySet("art"), nullptr);
}

TEST(MiddleburyTable, ErrorsNameTheSetAndTheDirectory) {
    Result<MiddleburyGroundTruth> r = loadMiddleburyGroundTruth("/nonexistent", "teddy");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("/nonexistent: no folder teddy"), std::string::npos) << r.error;
    r = loadMiddleburyGroundTruth("/nonexistent", "art");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("unknown Middlebury set 'art'"), std::string::npos) << r.error;
    r = loadMiddleburyGroundTruth("", "teddy");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("VTM_DATA"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace vtm::ground
