// Host-only peer (docs/tiepoints.md "Peer"): OpenCV's SIFT and ORB with Lowe's ratio test on
// the same left/right images of the rendered panorama, scored against the same truth as the
// intra-stereo tie points (true ground point of the left pixel, projected through the TRUE
// right pose). Prints the table; asserts that the tie points are at least as accurate as
// SIFT (median error and fraction of wrong matches, > 2 px).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

#include "scene_fixture.hpp"

namespace vtm::tiepoints::test {
namespace {

struct Score {
    std::vector<double> errors;
    std::int32_t no_truth = 0;
    [[nodiscard]] double median() const {
        std::vector<double> v = errors;
        std::sort(v.begin(), v.end());
        return v.empty() ? 1e9 : v[v.size() / 2];
    }
    [[nodiscard]] double wrong() const {
        const auto n = std::count_if(errors.begin(), errors.end(), [](double e) { return e > 2.0; });
        return errors.empty() ? 1.0 : static_cast<double>(n) / static_cast<double>(errors.size());
    }
};

void scorePair(const Scene& s, std::int32_t station, const Vec2& left, const Vec2& right, Score& score) {
    Vec3 ground = Vec3::Zero();
    Vec2 projected = Vec2::Zero();
    const RigidPose& pose = s.right[station];
    if (!trueGround(s, station, left, ground) ||
        !projectPoint(s.model, pose.R.transpose() * (ground - pose.t_m), projected).isOk()) {
        ++score.no_truth;
        return;
    }
    score.errors.push_back((projected - right).norm());
}

Score opencvPeer(const Scene& s, const cv::Ptr<cv::Feature2D>& detector, cv::NormTypes norm) {
    Score score;
    for (std::int32_t k = 0; k < kStations; ++k) {
        const cv::Mat left(s.spec.height, s.spec.width, CV_8UC1, const_cast<std::uint8_t*>(s.pixels[2 * k].data()));
        const cv::Mat right(s.spec.height, s.spec.width, CV_8UC1,
                            const_cast<std::uint8_t*>(s.pixels[2 * k + 1].data()));
        std::vector<cv::KeyPoint> kl, kr;
        cv::Mat dl, dr;
        detector->detectAndCompute(left, cv::noArray(), kl, dl);
        detector->detectAndCompute(right, cv::noArray(), kr, dr);
        if (dl.empty() || dr.empty()) {
            continue;
        }
        cv::BFMatcher matcher(norm);
        std::vector<std::vector<cv::DMatch>> knn;
        matcher.knnMatch(dl, dr, knn, 2);
        for (const auto& m : knn) {
            if (m.size() == 2 && m[0].distance < 0.8F * m[1].distance) {
                const cv::Point2f a = kl[static_cast<std::size_t>(m[0].queryIdx)].pt;
                const cv::Point2f b = kr[static_cast<std::size_t>(m[0].trainIdx)].pt;
                scorePair(s, k, Vec2(a.x, a.y), Vec2(b.x, b.y), score);
            }
        }
    }
    return score;
}

Score ours(const Scene& s) {
    Score score;
    const Config config = sceneConfig();
    std::vector<std::byte> pool(TiePointExtractor::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    auto extractor = std::make_unique<TiePointExtractor>();
    if (!extractor->init(config, arena).isOk() ||
        !extractor->run(Span<const NetworkStation>(s.stations, kStations), Span<const StationImages>(s.images, kStations))
             .isOk()) {
        return score;
    }
    const Span<const TieObservation> obs = extractor->observations();
    for (std::size_t k = 0; k + 1 < obs.size(); ++k) {
        const TieObservation& a = obs[k];
        const TieObservation& b = obs[k + 1];
        if (a.point == b.point && a.image.station == b.image.station && a.image.eye == Eye::kLeft &&
            b.image.eye == Eye::kRight) {
            scorePair(s, a.image.station, a.pixel_px, b.pixel_px, score);
        }
    }
    return score;
}

TEST(TiePointsPeer, IntraStereoAgainstSiftAndOrb) {
    const Scene& s = scene();
    ASSERT_TRUE(s.ok);
    const Score mine = ours(s);
    const Score sift = opencvPeer(s, cv::SIFT::create(0, 3, 0.01), cv::NORM_L2);  // contrast 0.01: dim renders
    const Score orb = opencvPeer(s, cv::ORB::create(500, 1.2F, 8, 15, 0, 2, cv::ORB::HARRIS_SCORE, 15, 5), cv::NORM_HAMMING);
    std::printf("no truth (depth edge / sky): ours %d, SIFT %d, ORB %d\n", mine.no_truth, sift.no_truth, orb.no_truth);
    std::printf("left-right of %d stations  matches  median px  wrong (> 2 px)\n", kStations);
    std::printf("tie points (fsw)          %7zu  %9.3f  %6.2f %%\n", mine.errors.size(), mine.median(),
                100.0 * mine.wrong());
    std::printf("OpenCV SIFT c0.01 + 0.8  %7zu  %9.3f  %6.2f %%\n", sift.errors.size(), sift.median(),
                100.0 * sift.wrong());
    std::printf("OpenCV ORB 500 f5 + 0.8 %7zu  %9.3f  %6.2f %%\n", orb.errors.size(), orb.median(),
                100.0 * orb.wrong());
    ASSERT_GE(mine.errors.size(), 60U);
    ASSERT_GE(sift.errors.size(), 30U);
    EXPECT_LE(mine.median(), sift.median());
    EXPECT_LE(mine.wrong(), sift.wrong());
}

}  // namespace
}  // namespace vtm::tiepoints::test
