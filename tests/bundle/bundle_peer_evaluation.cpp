// Peer: OpenCV's stitching bundle adjuster cv::detail::BundleAdjusterRay (rotation only, one
// focal length per camera) and the module on a rotation-only sub-problem: one tier of 8 rig
// stations turned about the left eye's centre, the approximate attitudes 1 degree off per axis,
// positions exact; OpenCV gets the left eyes' matches (its model: one centre), the module the
// same tie points in both eyes with the positions held (zero prior variance) and a 1 rad prior
// on the attitude (no information). Relative rotations between all pairs of left eyes against
// the truth (the gauge differs: OpenCV turns its result so that one camera is the identity).
// Host only (label accuracy); docs/bundle.md "Peer".
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/stitching/detail/motion_estimators.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "panorama_network.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"

namespace vtm::bundle {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

// RMS (deg) of the angle between estimated and true relative rotations over all pairs.
double relativeRms(const std::vector<Mat3>& est, const std::vector<Mat3>& truth) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < est.size(); ++i) {
        for (std::size_t j = i + 1; j < est.size(); ++j) {
            const double a = rotationAngleRad(est[i].transpose() * est[j], truth[i].transpose() * truth[j]);
            sum += a * a;
            ++n;
        }
    }
    return std::sqrt(sum / n) * kDeg;
}

std::vector<Mat3> openCvRotations(const test::Network& net, const test::NetworkSpec& spec) {
    const std::size_t images = net.approx.size();
    std::vector<cv::detail::ImageFeatures> features(images);
    std::vector<std::vector<int>> keyOf(images, std::vector<int>(net.points_m.size(), -1));
    for (std::size_t i = 0; i < images; ++i) {
        features[i].img_idx = static_cast<int>(i);
        features[i].img_size = cv::Size(spec.image_px, spec.image_px);
    }
    for (const TieObservation& o : net.observations) {
        if (o.image.eye != Eye::kLeft) continue;
        // OpenCV's principal point is (w/2, h/2); ours (w-1)/2: pixels shift by half a pixel.
        auto& f = features[o.image.station];
        keyOf[o.image.station][o.point] = static_cast<int>(f.keypoints.size());
        f.keypoints.emplace_back(static_cast<float>(o.pixel_px.x() + 0.5), static_cast<float>(o.pixel_px.y() + 0.5), 1.0f);
    }
    std::vector<cv::detail::MatchesInfo> pairs(images * images);
    for (std::size_t i = 0; i < images; ++i) {
        for (std::size_t j = 0; j < images; ++j) {
            cv::detail::MatchesInfo& m = pairs[i * images + j];
            m.src_img_idx = static_cast<int>(i);
            m.dst_img_idx = static_cast<int>(j);
            if (i == j) continue;
            for (std::size_t p = 0; p < net.points_m.size(); ++p) {
                if (keyOf[i][p] >= 0 && keyOf[j][p] >= 0) m.matches.emplace_back(keyOf[i][p], keyOf[j][p], 0.0f);
            }
            m.inliers_mask.assign(m.matches.size(), 1U);
            m.num_inliers = static_cast<int>(m.matches.size());
            m.confidence = m.num_inliers >= 6 ? 2.0 : 0.0;
            m.H = cv::Mat::eye(3, 3, CV_64F);
        }
    }
    std::vector<cv::detail::CameraParams> cameras(images);
    for (std::size_t i = 0; i < images; ++i) {
        cameras[i].focal = net.approx[i].rig.model_a.fx_px;
        cameras[i].ppx = spec.image_px * 0.5;
        cameras[i].ppy = spec.image_px * 0.5;
        cameras[i].aspect = 1.0;
        cv::Mat r(3, 3, CV_32F);
        for (int k = 0; k < 9; ++k) r.at<float>(k / 3, k % 3) = static_cast<float>(net.approx[i].site_from_a.R(k / 3, k % 3));
        cameras[i].R = r;
    }
    cv::Ptr<cv::detail::BundleAdjusterBase> adjuster = cv::makePtr<cv::detail::BundleAdjusterRay>();
    adjuster->setConfThresh(1.0);
    EXPECT_TRUE((*adjuster)(features, pairs, cameras));
    std::vector<Mat3> out(images);
    for (std::size_t i = 0; i < images; ++i) {
        cv::Mat r;
        cameras[i].R.convertTo(r, CV_64F);
        for (int k = 0; k < 9; ++k) out[i](k / 3, k % 3) = r.at<double>(k / 3, k % 3);
    }
    return out;
}

TEST(BundlePeerEvaluation, RotationOnlyPanoramaAgainstOpenCvBundleAdjusterRay) {
    std::printf("[ MEASURED ] seed | approx | module | OpenCV (RMS of relative-rotation errors over all pairs, deg)\n");
    double sumModule = 0.0;
    double sumCv = 0.0;
    for (std::uint64_t seed = 1U; seed <= 5U; ++seed) {
        test::NetworkSpec spec;
        spec.azimuths = 8;
        spec.tiers = 1;
        spec.hfov_deg = 60.0;
        spec.candidate_points = 600;
        spec.left_eye_on_axis = true;
        spec.sigma_rotation_rad = 1.0 / kDeg;
        spec.sigma_position_m = 0.0;
        spec.seed = seed;
        test::Network net = test::makeNetwork(spec);
        for (NetworkStation& s : net.approx) {
            s.prior_covariance = Mat6::Zero();
            s.prior_covariance.diagonal() << 1.0, 1.0, 1.0, 0.0, 0.0, 0.0;  // attitude free, position held
        }
        BundleConfig c;
        c.max_stations = 8;
        c.max_points = 1024;
        c.max_observations = 8192;
        std::vector<std::byte> pool(BundleAdjuster::workspaceBytes(c));
        Arena arena(pool.data(), pool.size());
        BundleAdjuster adj;
        ASSERT_TRUE(adj.init(c, arena).isOk());
        BundleResult r;
        const Status s = adj.adjust(Span<const NetworkStation>(net.approx.data(), net.approx.size()),
                                    Span<const TieObservation>(net.observations.data(), net.observations.size()),
                                    static_cast<std::uint32_t>(net.points_m.size()), r);
        ASSERT_TRUE(s.isOk()) << s.reason();
        std::vector<Mat3> truth;
        std::vector<Mat3> approx;
        std::vector<Mat3> mine;
        for (std::size_t i = 0; i < net.truth.size(); ++i) {
            truth.push_back(net.truth[i].site_from_a.R);
            approx.push_back(net.approx[i].site_from_a.R);
            mine.push_back(adj.stations()[i].site_from_a.R);
        }
        const std::vector<Mat3> cv = openCvRotations(net, spec);
        const double e0 = relativeRms(approx, truth);
        const double e1 = relativeRms(mine, truth);
        const double e2 = relativeRms(cv, truth);
        std::printf("[ MEASURED ] %d | %.4f | %.5f | %.5f   (%d points, %d observations)\n", static_cast<int>(seed), e0, e1,
                    e2, r.points_adjusted, r.observations);
        sumModule += e1;
        sumCv += e2;
        EXPECT_LT(e1, 0.1 * e0);
    }
    std::printf("[ MEASURED ] mean over 5 seeds: module %.5f deg, OpenCV BundleAdjusterRay %.5f deg\n", sumModule / 5.0, sumCv / 5.0);
}

}  // namespace
}  // namespace vtm::bundle
