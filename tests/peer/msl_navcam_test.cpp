// A real Mars pair (issue 21 item 6): the Curiosity Navcam B-string pair of sol 1431
// (../shared/data/msl_navcam, README there: no calibration, nominal 45 deg field of view,
// 0.42 m baseline, parallel axes). From the nominal geometry as the prior, the flight
// modules refine the pair (general scene), rectify it and map it with the ML stereo.
// Judged against the images themselves: OpenCV SIFT matches, found independently of the
// refinement, must lie on the same row after rectification; the disparities must be
// plausible for terrain seen from a mast (they grow towards the bottom of the image).
// VTM_MSL_OUT=DIR writes the rectified pair and the disparity picture (docs/app.md).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "real_pair_support.hpp"
#include "test_data.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/rectify/rectifier.hpp"

namespace vtm {
namespace {

using test::DenseMap;
using test::denseMap;
using test::greyView;
using test::inlierPixels;
using test::matchDisparities;
using test::rowStats;
using test::RowStats;
using test::siftMatches;
using test::Workspace;
using test::writeDisparityPng;

const std::string kDir = vtm::test::testDataSet("msl_navcam");
const std::string kLeft = kDir + "NLB_524534514EDR_F0562034NCAM00280M_.jpeg";
const std::string kRight = kDir + "NRB_524534514EDR_F0562034NCAM00280M_.jpeg";
constexpr double kBaselineM = 0.42;  // README: the nominal Navcam stereo baseline
constexpr double kHfovDeg = 45.0;    // README: 45 x 45 deg
constexpr std::int32_t kSide = 1024;

// The nominal prior: parallel axes, camera 2 0.42 m to camera 1's right (X_2 = X_1 - b x).
CameraPair nominalPair() {
    CameraPair p;
    p.model_a = p.model_b = makePinhole(kSide, kSide, kHfovDeg);
    p.b_from_a.R = Mat3::Identity();
    p.b_from_a.t_m = Vec3(-kBaselineM, 0.0, 0.0);
    return p;
}

class MslNavcam : public ::testing::Test {
protected:
    void SetUp() override {
        VTM_REQUIRE_TEST_DATA(kLeft);
        left_ = cv::imread(kLeft, cv::IMREAD_GRAYSCALE);
        right_ = cv::imread(kRight, cv::IMREAD_GRAYSCALE);
        ASSERT_FALSE(left_.empty()) << kLeft;
        ASSERT_FALSE(right_.empty()) << kRight;
        ASSERT_EQ(left_.cols, kSide);
        ASSERT_EQ(left_.rows, kSide);
    }
    cv::Mat left_, right_;
};

TEST_F(MslNavcam, RefinedFromTheNominalGeometryRectifiedAndMapped) {
    // 1. Refinement: general scene (no level ground assumed), ranges 1 m .. 1 km.
    refine::Config rc;
    rc.match_margin_px = 60.0;
    Workspace rw(refine::PairRefiner::workspaceBytes(rc));
    refine::PairRefiner refiner;
    ASSERT_TRUE(refiner.init(rc, rw.arena).isOk());
    refine::Request rq;
    rq.prior = nominalPair();
    rq.image_a = greyView(left_);
    rq.image_b = greyView(right_);
    rq.range_min_m = 1.0;
    rq.range_max_m = 1000.0;
    rq.scene = refine::Scene::kGeneral;
    refine::Result res;
    const Status st = refiner.refine(rq, res);
    ASSERT_TRUE(st.isOk()) << st.reason();
    std::vector<Vec2> inl_a, inl_b;
    inlierPixels(res, inl_a, inl_b);
    EXPECT_GE(inl_a.size(), 50U);

    // 2. Rectification of the nominal and of the refined pair; rows of independent matches.
    std::vector<Vec2> sift_a, sift_b;
    siftMatches(left_, right_, sift_a, sift_b);
    ASSERT_GE(sift_a.size(), 100U) << "SIFT found too few matches to judge the rows";
    rectify::Config xc;
    xc.range_min_m = 3.0;
    xc.range_max_m = 1000.0;
    Workspace xw(rectify::Rectifier::workspaceBytes(xc));
    rectify::Rectifier rectifier;
    ASSERT_TRUE(rectifier.init(xc, xw.arena).isOk());
    rectify::RectifiedPair nominal, refined;
    ASSERT_TRUE(rectifier.compute({nominalPair()}, nominal).isOk());
    const RowStats sift_nominal = rowStats(rectifier, sift_a, sift_b);
    ASSERT_TRUE(rectifier.compute({res.refined}, refined).isOk());
    const RowStats sift_refined = rowStats(rectifier, sift_a, sift_b);
    const RowStats inliers_refined = rowStats(rectifier, inl_a, inl_b);

    // 3. ML stereo on the rectified pair, over the disparities of the refiner's inliers
    //    (their rectified x_a - x_b) widened by 8 px below and 16 px above (nearer ground
    //    than the nearest inlier); the left-right check and uniqueness on.
    const std::vector<double> inlier_d = matchDisparities(rectifier, inl_a, inl_b);
    ASSERT_GE(inlier_d.size(), 2U);
    const double d_lo = *std::min_element(inlier_d.begin(), inlier_d.end());
    const double d_hi = *std::max_element(inlier_d.begin(), inlier_d.end());
    ASSERT_LT(d_lo, d_hi);
    DenseMap dense;
    const Status ds = denseMap(rectifier, refined, left_, right_, static_cast<std::int32_t>(std::floor(d_lo)) - 8,
                               static_cast<std::int32_t>(std::ceil(d_hi)) + 16, dense);
    ASSERT_TRUE(ds.isOk()) << ds.reason();
    std::vector<double> quarter[4];
    for (std::int32_t y = 0; y < kSide; ++y) {
        for (std::int32_t x = 0; x < kSide; ++x) {
            double d = 0.0;
            if (dense.at(x, y, d)) quarter[4 * y / kSide].push_back(d);
        }
    }
    double median[4] = {0.0, 0.0, 0.0, 0.0};
    for (int t = 0; t < 4; ++t) {
        if (quarter[t].empty()) continue;
        std::nth_element(quarter[t].begin(), quarter[t].begin() + quarter[t].size() / 2, quarter[t].end());
        median[t] = quarter[t][quarter[t].size() / 2];
    }
    const double share = dense.share();

    std::printf("[ msl ] %d features, %zu matches, %zu inliers; RMS %.3f -> %.3f px; rotation change %.3f deg, "
                "direction change %.2f deg; predicted vd %.3f px\n",
                res.detection.kept, res.matches.size(), inl_a.size(), res.motion.initial_rms_px, res.motion.rms_px,
                res.rotation_change_deg, res.direction_change_deg, res.motion.epipolar_sigma_px);
    std::printf("[ msl ] SIFT matches %zu: vertical disparity after rectification, nominal: RMS %.3f px (|vd| <= 2), "
                "median |vd| %.3f, within 1 px %.1f %%; refined: RMS %.3f px, median |vd| %.3f, within 1 px %.1f %%\n",
                sift_refined.count, sift_nominal.rms_px, sift_nominal.median_abs, 100.0 * sift_nominal.within1,
                sift_refined.rms_px, sift_refined.median_abs, 100.0 * sift_refined.within1);
    std::printf("[ msl ] refiner's inliers after rectification: RMS %.3f px; disparities searched %d..%d px; mapped %.1f %% "
                "of %lld rectified pixels with content; median disparity by quarter of the rows, top to bottom "
                "%.1f / %.1f / %.1f / %.1f px (%zu / %zu / %zu / %zu disparities)\n",
                inliers_refined.rms_px, dense.d_min, dense.d_max, 100.0 * share, static_cast<long long>(dense.content),
                median[0], median[1], median[2], median[3], quarter[0].size(), quarter[1].size(), quarter[2].size(),
                quarter[3].size());
    const Vec3& t = res.refined.b_from_a.t_m;
    std::printf("[ msl ] refined b_from_a.t_m (%.4f, %.4f, %.4f) m, direction sigma %.2f deg\n", t.x(), t.y(), t.z(),
                57.29577951308232 * res.motion.direction_sigma_rad);

    // Rows: the independent matches on one row after refinement, much better than nominal.
    EXPECT_LE(sift_refined.median_abs, 0.3);
    EXPECT_GE(sift_refined.within1, 0.9);
    EXPECT_LE(sift_refined.median_abs * 5.0, sift_nominal.median_abs);
    // A mast's view of the ground: nearer (larger disparity) towards the bottom of the
    // image (the lower half; the upper holds the sky and the cliff).
    EXPECT_GT(median[3], median[2]);
    EXPECT_GE(share, 0.3);

    if (const char* dir = std::getenv("VTM_MSL_OUT")) {
        const std::string d(dir);
        cv::imwrite(d + "/msl-rectified1.png", dense.rect_a);
        cv::imwrite(d + "/msl-rectified2.png", dense.rect_b);
        writeDisparityPng(d + "/msl-disparity.png", dense, static_cast<float>(std::max(0.0, median[1] - 10.0)),
                          static_cast<float>(median[3] + 20.0));
    }
}

}  // namespace
}  // namespace vtm
