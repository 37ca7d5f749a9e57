// The descent plane sweep's fast path against a brute-force OpenCV reference on the
// same planes: image 2 after the module's own anti-alias prefilter
// (PlaneSweep::prefilteredImage2), warped per plane with cv::warpPerspective (bilinear,
// WARP_INVERSE_MAP with the module's homographies), absolute differences with image 1,
// cv::boxFilter window sums, arg-min over the planes. The fast path is exact up to the
// bilinear rounding (OpenCV keeps float samples; the module rounds them to 1/16 grey
// level), so the best planes must agree on at least 99.9 % of the valid pixels and never
// differ by more than one plane.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

#include "descent_scene.hpp"  // tests/descent, on this target's include path
#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent {
namespace {

constexpr std::int32_t kSize = 128;

TEST(DescentPeer, BruteForceOpenCvSweepPicksTheSamePlanes) {
    sim::TerrainParams p;
    p.kind = sim::TerrainKind::kPlane;
    p.finest_cell_m = 0.1;
    p.samples_log2 = 6;
    p.levels = 8;
    p.plane_slope_north = 0.1;
    p.albedo_wavelength_m = 4.0;
    p.texture_longest_wavelength_m = 4.0;
    p.texture_contrast = 0.5;
    const sim::Terrain& t = test::buildTerrain(p);
    const CameraModel cam = makePinhole(kSize, kSize, 45.0);
    sim::SensorParams sensor;
    sensor.gain_dn_per_e = 0.16;
    sensor.full_well_e = 60000.0;
    sensor.vignetting = 0.05;
    const test::RenderedFrame f1 = test::render(t, cam, test::nadirPose(Vec3(0.0, 0.0, -100.0)), 0U, sensor);
    const test::RenderedFrame f2 = test::render(t, cam, test::nadirPose(Vec3(3.0, -4.0, -60.0)), 1U, sensor);

    Config c;
    c.max_width = kSize;
    c.max_height = kSize;
    c.planes = 48;
    c.depth_min_m = 80.0;
    c.depth_max_m = 125.0;
    c.score = Score::kSad;
    c.window = 7;  // a 128 x 128 pair: the default 11 leaves too few pixels inside both images
    c.min_parallax_px = 4.0;
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    PlaneSweep sweep;
    ASSERT_TRUE(sweep.init(c, arena).isOk());
    PairGeometry g{cam, f1.pose, f2.pose};
    std::vector<float> depth(kSize * kSize);
    std::vector<std::uint8_t> reason(kSize * kSize);
    ASSERT_TRUE(sweep.compute(ImageView<const std::uint16_t>(f1.image.data(), kSize, kSize),
                              ImageView<const std::uint16_t>(f2.image.data(), kSize, kSize), g,
                              SweepOutput{ImageView<float>(depth.data(), kSize, kSize), {},
                                          ImageView<std::uint8_t>(reason.data(), kSize, kSize)})
                    .isOk());

    // Reference: same prefiltered image 2, same planes, OpenCV warps and box filters.
    const ImageView<const std::uint16_t> pre = sweep.prefilteredImage2();
    cv::Mat img2(kSize, kSize, CV_32F), img1(kSize, kSize, CV_32F);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            img2.at<float>(y, x) = static_cast<float>(pre.row(y)[x]);
            img1.at<float>(y, x) = 16.0F * static_cast<float>(f1.image[static_cast<std::size_t>(y * kSize + x)]);
        }
    }
    cv::Mat best(kSize, kSize, CV_32S, cv::Scalar(-1)), bestCost(kSize, kSize, CV_32F, cv::Scalar(1e30));
    for (int k = 0; k < c.planes; ++k) {
        const Mat3 H = sweep.homography(k);
        cv::Mat M(3, 3, CV_64F);
        for (int i = 0; i < 9; ++i) {
            M.at<double>(i / 3, i % 3) = H(i / 3, i % 3);
        }
        cv::Mat warped, diff, sad;
        cv::warpPerspective(img2, warped, M, img1.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                            cv::BORDER_REPLICATE);
        cv::absdiff(img1, warped, diff);
        cv::boxFilter(diff, sad, CV_32F, cv::Size(c.window, c.window), cv::Point(-1, -1), false);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                if (sad.at<float>(y, x) < bestCost.at<float>(y, x)) {
                    bestCost.at<float>(y, x) = sad.at<float>(y, x);
                    best.at<int>(y, x) = k;
                }
            }
        }
    }
    // The fast path's plane: its refined inverse depth rounded to the plane grid.
    const double inv0 = 1.0 / sweep.planeDepth(0);
    const double step = 1.0 / sweep.planeDepth(1) - inv0;
    std::int32_t compared = 0, same = 0, apart = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const auto i = static_cast<std::size_t>(y * kSize + x);
            if (reason[i] != 0U) {
                continue;
            }
            const double k = (1.0 / static_cast<double>(depth[i]) - inv0) / step;
            const int fast = static_cast<int>(std::lround(k));
            const int ref = best.at<int>(y, x);
            ++compared;
            same += (fast == ref) ? 1 : 0;
            // A refined vertex at +-0.5 may round to the neighbour.
            apart += (std::abs(fast - ref) > 1) ? 1 : 0;
        }
    }
    ASSERT_GT(compared, kSize * kSize / 6);
    const double agreement = static_cast<double>(same) / compared;
    std::printf("descent peer: %d valid pixels, same best plane on %.3f %%, %d more than one plane apart\n",
                compared, 100.0 * agreement, apart);
    EXPECT_GE(agreement, 0.999);
    EXPECT_EQ(apart, 0);
}

}  // namespace
}  // namespace vtm::descent
