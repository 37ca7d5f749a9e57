// fsw/stereo: fitDisparityPlane and fillDisparityPlane on samples of a known plane, with
// noise and outliers. Runs on every target.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "vtm/core/random.hpp"
#include "vtm/stereo/disparity_plane.hpp"

namespace vtm::stereo {
namespace {

// The mission pair's plane (docs/app.md): d = 0.06 x + 1.5 y - 415.
constexpr double kA = 0.06;
constexpr double kB = 1.5;
constexpr double kC = -415.0;

// n samples of the plane over a 1024 x 512 area with uniform noise of +-noise px; every
// `outlier_every`-th sample (0: none) moved by 40..100 px.
std::vector<Vec3> planeSamples(std::uint64_t seed, int n, double noise, int outlier_every) {
    Random rng(seed);
    std::vector<Vec3> s;
    for (int i = 0; i < n; ++i) {
        const double x = 1024.0 * rng.uniform01();
        const double y = 512.0 * rng.uniform01();
        double d = kA * x + kB * y + kC + noise * (2.0 * rng.uniform01() - 1.0);
        if (outlier_every > 0 && i % outlier_every == 0) {
            d += 40.0 + 60.0 * rng.uniform01();
        }
        s.emplace_back(x, y, d);
    }
    return s;
}

Status fit(const std::vector<Vec3>& samples, DisparityPlane& plane) {
    std::vector<double> scratch(samples.size());
    return fitDisparityPlane(Span<const Vec3>(samples.data(), samples.size()),
                             Span<double>(scratch.data(), scratch.size()), plane);
}

// Largest |plane - truth| over the area, px.
double worstError(const DisparityPlane& p) {
    double worst = 0.0;
    for (const double x : {0.0, 1024.0}) {
        for (const double y : {0.0, 512.0}) {
            worst = std::fmax(worst, std::fabs(p.a * x + p.b * y + p.c - (kA * x + kB * y + kC)));
        }
    }
    return worst;
}

TEST(DisparityPlane, RecoversThePlaneFromNoisySamples) {
    DisparityPlane p;
    ASSERT_TRUE(fit(planeSamples(1, 50, 2.0, 0), p).isOk());
    EXPECT_LT(worstError(p), 1.5);
    EXPECT_EQ(p.used, 50);
    EXPECT_GT(p.residual_px, 0.3);  // uniform +-2 px: median |residual| about 1 px
    EXPECT_LT(p.residual_px, 1.5);
}

TEST(DisparityPlane, RefitsDropTheOutliers) {
    const std::vector<Vec3> samples = planeSamples(2, 60, 1.0, 5);  // 12 of 60 off by 40..100 px
    DisparityPlane p;
    ASSERT_TRUE(fit(samples, p).isOk());
    EXPECT_EQ(p.used, 48);  // the 48 samples on the plane, none of the 12 off it
    EXPECT_LT(worstError(p), 1.5);  // one least-squares fit over all 60 is off by ~14 px
}

TEST(DisparityPlane, ThreeSamplesGiveTheirPlaneAndALineIsDegenerate) {
    const std::vector<Vec3> three = {Vec3(0, 0, kC), Vec3(1000, 0, kA * 1000 + kC), Vec3(0, 500, kB * 500 + kC)};
    DisparityPlane p;
    ASSERT_TRUE(fit(three, p).isOk());
    EXPECT_LT(worstError(p), 1e-6);
    const std::vector<Vec3> line = {Vec3(0, 0, 1), Vec3(10, 10, 2), Vec3(20, 20, 3), Vec3(30, 30, 4)};
    EXPECT_EQ(fit(line, p).code(), StatusCode::kDegenerate);
}

TEST(DisparityPlane, BadInputsAreNamed) {
    DisparityPlane p;
    const std::vector<Vec3> two = {Vec3(0, 0, 1), Vec3(1, 0, 1)};
    const Status few = fit(two, p);
    EXPECT_EQ(few.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::string(few.reason()).find("fewer than 3"), std::string::npos);
    std::vector<Vec3> bad = planeSamples(3, 10, 0.0, 0);
    bad[4].z() = std::nan("");
    const Status nan = fit(bad, p);
    EXPECT_EQ(nan.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(nan.detail(), 4);
    double scratch[2];
    const std::vector<Vec3> ok = planeSamples(4, 10, 0.0, 0);
    EXPECT_EQ(fitDisparityPlane(Span<const Vec3>(ok.data(), ok.size()), Span<double>(scratch, 2), p).code(),
              StatusCode::kInvalidArgument);
}

TEST(DisparityPlane, FillRoundsAndClampsToTheBounds) {
    std::vector<std::int16_t> out(64 * 32);
    const ImageView<std::int16_t> view(out.data(), 64, 32);
    const DisparityPlane p{0.5, 2.0, -10.2, 3, 0.0};
    ASSERT_TRUE(fillDisparityPlane(p, -5, 40, view).isOk());
    for (std::int32_t y = 0; y < 32; ++y) {
        for (std::int32_t x = 0; x < 64; ++x) {
            const double d = std::floor(0.5 * x + 2.0 * y - 10.2 + 0.5);
            ASSERT_EQ(view.row(y)[x], static_cast<std::int16_t>(std::fmin(40.0, std::fmax(-5.0, d)))) << x << "," << y;
        }
    }
    EXPECT_EQ(fillDisparityPlane(p, 5, -5, view).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(fillDisparityPlane(p, -3000, 0, view).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(fillDisparityPlane(p, 0, 1, ImageView<std::int16_t>()).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vtm::stereo
