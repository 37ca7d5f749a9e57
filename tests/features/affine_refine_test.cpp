// refineAffine: image B is image A's continuous texture under a known affine map
// (rotation 12 deg, scale 1.15, shear 0.08, a subpixel translation) and a photometric
// change (B = 0.8 A + 25). Truth: a feature at A's pixel p maps to q0 + M (p - p0).
// Started 0.7 px away from the truth with a warp 4 % wrong (what the template matcher's
// plane-induced warp from odometry gives), the fit must land on the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "floor_int.hpp"
#include "no_heap_guard.hpp"
#include "test_images.hpp"
#include "vtm/features/features.hpp"

namespace vtm::features {
namespace {

using test::Image;
using test::Texture;

constexpr std::int32_t kW = 200, kH = 180;
constexpr double kPad = 60.0;
constexpr double kGain = 0.8, kOffset = 25.0;

struct AffinePair {
    Texture texture{5U, 260, 1};
    Mat2 m;                       // A-pixel offsets -> B-pixel offsets
    Vec2 p0{100.0, 90.0};         // A's pixel that maps to q0
    Vec2 q0{103.3, 88.6};
    Image a{kW, kH};
    Image b{kW, kH};
    AffinePair() {
        const double ang = 12.0 * 3.14159265358979 / 180.0;
        Mat2 rot;
        rot << std::cos(ang), -std::sin(ang), std::sin(ang), std::cos(ang);
        Mat2 shear;
        shear << 1.0, 0.08, 0.0, 1.0;
        m = 1.15 * rot * shear;
        const Mat2 m_inv = m.inverse();
        for (std::int32_t y = 0; y < kH; ++y) {
            for (std::int32_t x = 0; x < kW; ++x) {
                a.at(x, y) = test::toGrey(texture.at(x + kPad, y + kPad));
                const Vec2 p = p0 + m_inv * (Vec2(x, y) - q0);  // A's position seen at B's (x, y)
                b.at(x, y) = test::toGrey(kGain * texture.at(p.x() + kPad, p.y() + kPad) + kOffset);
            }
        }
    }
    Vec2 truth(const Vec2& pa) const { return q0 + m * (pa - p0); }
};

// Features on a grid whose windows stay inside both images.
std::vector<Vec2> gridPoints() {
    std::vector<Vec2> pts;
    for (double y = 60.3; y <= 120.0; y += 11.0) {
        for (double x = 60.7; x <= 140.0; x += 11.0) {
            pts.emplace_back(x, y);
        }
    }
    return pts;
}

TEST(AffineRefine, ConvergesToTheTruthFromAFourPercentWrongWarp) {
    const AffinePair pair;
    const Mat2 start_warp = pair.m * 1.04;
    const AffineRefineConfig config;
    double worst = 0.0, worst_start = 0.0, worst_gain = 0.0;
    std::int32_t max_steps = 0;
    const std::vector<Vec2> pts = gridPoints();
    for (const Vec2& pa : pts) {
        const Vec2 start = pair.truth(pa) + Vec2(0.7, -0.6);
        AffineMatch am;
        vtm::test::NoHeapScope guard;
        ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, start, start_warp, config, am).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
        ASSERT_EQ(am.outcome, AffineOutcome::kAccepted) << pa.transpose();
        worst = std::max(worst, (am.pixel_b - pair.truth(pa)).norm());
        worst_start = std::max(worst_start, (start - pair.truth(pa)).norm());
        worst_gain = std::max(worst_gain, std::fabs(am.gain - kGain));
        max_steps = std::max(max_steps, am.steps);
        EXPECT_GT(am.score, 0.99);
        EXPECT_LT((am.warp - pair.m).cwiseAbs().maxCoeff(), 0.02) << pa.transpose();
    }
    std::printf("[ measure  ] %zu features: worst error %.4f px (start %.3f px), worst gain error %.4f, steps <= %d\n",
                pts.size(), worst, worst_start, worst_gain, max_steps);
    // A 15 x 15 window on 8-bit samples of a texture with a node every 2 px: a twentieth
    // of a pixel is what the quantisation and bilinear resampling leave. Resampling B
    // between its pixels also smooths it, which the gain absorbs (a few per cent low).
    EXPECT_LT(worst, 0.05);
    EXPECT_LT(worst_gain, 0.05);
}

TEST(AffineRefine, ResultIsTheSameFromDifferentStarts) {
    const AffinePair pair;
    const Vec2 pa(97.4, 85.2);
    AffineMatch m1, m2;
    const AffineRefineConfig config;
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, pair.truth(pa) + Vec2(-0.9, 0.4), pair.m, config, m1)
                    .isOk());
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, pair.truth(pa) + Vec2(0.5, 0.8), Mat2::Identity(),
                             config, m2)
                    .isOk());
    ASSERT_EQ(m1.outcome, AffineOutcome::kAccepted);
    ASSERT_EQ(m2.outcome, AffineOutcome::kAccepted);
    EXPECT_LT((m1.pixel_b - m2.pixel_b).norm(), 1.0e-3);
}

TEST(AffineRefine, RejectsWhatItCannotFit) {
    const AffinePair pair;
    const AffineRefineConfig config;
    const Vec2 pa(100.0, 90.0);
    AffineMatch am;
    // Flat B: nothing to fit.
    Image flat(kW, kH);
    for (auto& v : flat.pixels) {
        v = 90;
    }
    ASSERT_TRUE(refineAffine(pair.a.view(), flat.view(), pa, pair.truth(pa), pair.m, config, am).isOk());
    EXPECT_EQ(am.outcome, AffineOutcome::kSingular);
    EXPECT_EQ(am.pixel_b, pair.truth(pa));  // the start is handed back
    // Windows that leave an image.
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), Vec2(5.0, 90.0), pair.truth(pa), pair.m, config, am).isOk());
    EXPECT_EQ(am.outcome, AffineOutcome::kLeftImage);
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, Vec2(190.0, 90.0), pair.m, config, am).isOk());
    EXPECT_EQ(am.outcome, AffineOutcome::kLeftImage);
    // A degenerate starting warp.
    Mat2 thin;
    thin << 1.0, 0.0, 0.0, 0.01;
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, pair.truth(pa), thin, config, am).isOk());
    EXPECT_EQ(am.outcome, AffineOutcome::kBadWarp);
    // The truth lies 1.5 px from the start, the caller allows 1 px.
    AffineRefineConfig tight = config;
    tight.max_shift_px = 1.0;
    ASSERT_TRUE(refineAffine(pair.a.view(), pair.b.view(), pa, pair.truth(pa) + Vec2(1.2, 0.9), pair.m, tight, am)
                    .isOk());
    EXPECT_EQ(am.outcome, AffineOutcome::kMovedTooFar);
    // An unrelated texture: whatever the fit does, it is not accepted.
    const Texture other(99U, 260, 1);
    Image noise(kW, kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            noise.at(x, y) = test::toGrey(other.at(x + kPad, y + kPad));
        }
    }
    ASSERT_TRUE(refineAffine(pair.a.view(), noise.view(), pa, pair.truth(pa), pair.m, config, am).isOk());
    EXPECT_NE(am.outcome, AffineOutcome::kAccepted);
    EXPECT_EQ(am.pixel_b, pair.truth(pa));
}

TEST(AffineRefine, BadInputsGiveTheDocumentedStatus) {
    const AffinePair pair;
    AffineMatch am;
    AffineRefineConfig config;
    const Vec2 pa(100.0, 90.0);
    config.max_steps = 0;
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), pa, pa, pair.m, config, am).code(), StatusCode::kInvalidConfig);
    config = AffineRefineConfig{};
    config.max_shift_px = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), pa, pa, pair.m, config, am).code(), StatusCode::kInvalidConfig);
    config = AffineRefineConfig{};
    config.min_score = 1.5f;
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), pa, pa, pair.m, config, am).code(), StatusCode::kInvalidConfig);
    config = AffineRefineConfig{};
    const Vec2 nan(std::numeric_limits<double>::quiet_NaN(), 1.0);
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), nan, pa, pair.m, config, am).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), pa, nan, pair.m, config, am).code(),
              StatusCode::kInvalidArgument);
    Mat2 bad = pair.m;
    bad(1, 0) = std::numeric_limits<double>::infinity();
    EXPECT_EQ(refineAffine(pair.a.view(), pair.b.view(), pa, pa, bad, config, am).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(refineAffine(ImageView<const std::uint8_t>(), pair.b.view(), pa, pa, pair.m, config, am).code(),
              StatusCode::kInvalidArgument);
}

// The samplers' floor without a library call (floor_int.hpp) equals std::floor: integers,
// halves, values next to an integer on both sides, negatives, the int32 ends.
TEST(FloorToInt, EqualsStdFloor) {
    const double values[] = {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.999999999999, -2.999999999999, 255.0, 255.5,
                             -1.0e-300, 1.0e-300, 2147483646.5, -2147483647.5, -2147483648.0};
    for (const double v : values) {
        EXPECT_EQ(detail::floorToInt(v), static_cast<std::int32_t>(std::floor(v))) << v;
        for (const double w : {std::nextafter(v, -1.0e10), std::nextafter(v, 1.0e10)}) {
            if (w > -2147483648.0 && w < 2147483647.0) {
                EXPECT_EQ(detail::floorToInt(w), static_cast<std::int32_t>(std::floor(w))) << w;
            }
        }
    }
}

}  // namespace
}  // namespace vtm::features
