// stereo::SpeckleFilter against OpenCV's cv::filterSpeckles (calib3d) on the same 16-bit
// disparity images: both remove 4-connected regions of at most maxSpeckleSize pixels whose
// neighbours differ by at most maxDiff, and treat the new value as "no disparity"; the
// results must be the same bits. Host only (OpenCV is a test-time peer).
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "vtm/core/random.hpp"
#include "vtm/stereo/speckle_filter.hpp"

namespace vtm::stereo {
namespace {

// Disparity planes with noise, steps and holes: every kind of region (large, small,
// split by a step above maxDiff, touching the border).
std::vector<std::int16_t> noisyDisparity(std::int32_t w, std::int32_t h, std::uint64_t seed) {
    Random rng(seed);
    std::vector<std::int16_t> d(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            const double u = rng.uniform01();
            std::int32_t v = 16 * ((x / 11 + y / 7) % 9) + static_cast<std::int32_t>(24.0 * rng.uniform01());
            if (u < 0.12) {
                v = kNoDisparity;
            } else if (u < 0.2) {
                v += 400;  // a wrong match: an island of its own or part of a few neighbours
            }
            d[static_cast<std::size_t>(y * w + x)] = static_cast<std::int16_t>(v);
        }
    }
    return d;
}

TEST(SpecklePeer, SameBitsAsOpenCvFilterSpeckles) {
    constexpr std::int32_t kW = 317, kH = 203;
    int compared = 0;
    for (const std::uint64_t seed : {1U, 2U, 3U}) {
        for (const std::int32_t max_region : {0, 1, 10, 50, 200}) {
            for (const std::int32_t max_diff : {0, 8, 16, 32}) {
                std::vector<std::int16_t> ours = noisyDisparity(kW, kH, seed);
                cv::Mat peer(kH, kW, CV_16SC1);
                std::copy(ours.begin(), ours.end(), peer.ptr<std::int16_t>(0));
                cv::filterSpeckles(peer, kNoDisparity, max_region, max_diff);

                SpeckleConfig c;
                c.max_width = kW;
                c.max_height = kH;
                c.max_region_px = max_region;
                c.max_diff_px16 = max_diff;
                std::vector<std::byte> pool(SpeckleFilter::workspaceBytes(c));
                Arena arena(pool.data(), pool.size());
                auto filter = std::make_unique<SpeckleFilter>();
                ASSERT_TRUE(filter->init(c, arena).isOk());
                std::int32_t removed = 0;
                ASSERT_TRUE(filter->apply(DisparityOutput{ImageView<std::int16_t>(ours.data(), kW, kH), {}, {}},
                                          nullptr, &removed)
                                .isOk());
                std::int32_t differ = 0;
                for (std::int32_t i = 0; i < kW * kH; ++i) {
                    differ += ours[static_cast<std::size_t>(i)] != peer.ptr<std::int16_t>(0)[i] ? 1 : 0;
                }
                EXPECT_EQ(differ, 0) << "seed " << seed << " max_region " << max_region << " max_diff " << max_diff
                                     << " (removed " << removed << ")";
                if (max_region >= 10 && max_diff == 16) {
                    EXPECT_GT(removed, 0);  // the case exercises the filter
                }
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 60);
}

}  // namespace
}  // namespace vtm::stereo
