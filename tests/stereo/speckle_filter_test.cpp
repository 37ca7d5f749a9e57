// stereo::SpeckleFilter: islands of known size on a smooth disparity surface (removed up to
// max_region_px, kept above), reasons, sigma and stats, no heap, errors. Runs on the host
// and every cross target; tests/peer/speckle_peer_test.cpp compares it with OpenCV's
// filterSpeckles bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "no_heap_guard.hpp"
#include "vtm/stereo/speckle_filter.hpp"

namespace vtm::stereo {
namespace {

constexpr std::int32_t kW = 96;
constexpr std::int32_t kH = 64;

struct Filter {
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    SpeckleFilter filter;
    explicit Filter(const SpeckleConfig& c) : pool(SpeckleFilter::workspaceBytes(c)) {
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        const Status s = filter.init(c, *arena);
        EXPECT_TRUE(s.isOk()) << s.reason();
    }
};

SpeckleConfig smallConfig() {
    SpeckleConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.max_region_px = 20;
    c.max_diff_px16 = 16;
    return c;
}

// A slanted surface (d rises 1/16 px per column: one region) with square islands of side
// 1, 2, 4 and 5 (1, 4, 16, 25 px) whose disparity is 40 px above it, each fenced by a ring
// of pixels without a disparity so that it is a region of its own.
struct Scene {
    std::vector<std::int16_t> d = std::vector<std::int16_t>(static_cast<std::size_t>(kW * kH));
    std::vector<float> sigma = std::vector<float>(static_cast<std::size_t>(kW * kH), 0.25f);
    std::vector<std::uint8_t> reason = std::vector<std::uint8_t>(static_cast<std::size_t>(kW * kH), 0U);
    std::int16_t& at(std::int32_t x, std::int32_t y) { return d[static_cast<std::size_t>(y * kW + x)]; }
    Scene() {
        for (std::int32_t y = 0; y < kH; ++y) {
            for (std::int32_t x = 0; x < kW; ++x) {
                at(x, y) = static_cast<std::int16_t>(160 + x);
            }
        }
        const std::int32_t sides[4] = {1, 2, 4, 5};
        for (std::int32_t k = 0; k < 4; ++k) {
            const std::int32_t x0 = 8 + 20 * k, y0 = 20, s = sides[k];
            for (std::int32_t y = y0 - 1; y <= y0 + s; ++y) {
                for (std::int32_t x = x0 - 1; x <= x0 + s; ++x) {
                    const bool inside = x >= x0 && x < x0 + s && y >= y0 && y < y0 + s;
                    at(x, y) = inside ? static_cast<std::int16_t>(160 + x + 640) : kNoDisparity;
                    if (!inside) {
                        reason[static_cast<std::size_t>(y * kW + x)] = static_cast<std::uint8_t>(Reason::kNoTexture);
                        sigma[static_cast<std::size_t>(y * kW + x)] = std::numeric_limits<float>::infinity();
                    }
                }
            }
        }
    }
    DisparityOutput out() {
        return DisparityOutput{ImageView<std::int16_t>(d.data(), kW, kH), ImageView<float>(sigma.data(), kW, kH),
                               ImageView<std::uint8_t>(reason.data(), kW, kH)};
    }
};

TEST(SpeckleFilter, RemovesIslandsUpToMaxRegionAndKeepsTheRest) {
    Scene scene;
    const Scene before = scene;
    Filter f(smallConfig());  // islands of 1, 4 and 16 px go; 25 px stays
    StereoStats stats;
    std::int32_t valid = 0;
    for (const std::int16_t v : scene.d) {
        valid += v != kNoDisparity ? 1 : 0;
    }
    stats.valid_pixels = valid;
    stats.reason_counts[0] = valid;
    std::int32_t removed = -1;
    {
        test::NoHeapScope scope;
        ASSERT_TRUE(f.filter.apply(scene.out(), &stats, &removed).isOk());
        EXPECT_EQ(scope.heapCalls(), 0U);
    }
    EXPECT_EQ(removed, 1 + 4 + 16);
    EXPECT_EQ(stats.valid_pixels, valid - removed);
    EXPECT_EQ(stats.reason_counts[0], valid - removed);
    EXPECT_EQ(stats.reason_counts[static_cast<std::size_t>(Reason::kSpeckle)], removed);
    const std::int32_t sides[4] = {1, 2, 4, 5};
    std::int32_t speckle_pixels = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const auto i = static_cast<std::size_t>(y * kW + x);
            bool in_small_island = false;
            for (std::int32_t k = 0; k < 3; ++k) {
                const std::int32_t x0 = 8 + 20 * k, s = sides[k];
                in_small_island = in_small_island || (x >= x0 && x < x0 + s && y >= 20 && y < 20 + s);
            }
            if (in_small_island) {
                ++speckle_pixels;
                EXPECT_EQ(scene.d[i], kNoDisparity);
                EXPECT_EQ(scene.reason[i], static_cast<std::uint8_t>(Reason::kSpeckle));
                EXPECT_TRUE(std::isinf(scene.sigma[i]));
            } else {  // the surface, the 25-px island and the fences are untouched
                EXPECT_EQ(scene.d[i], before.d[i]) << x << ", " << y;
                EXPECT_EQ(scene.reason[i], before.reason[i]);
                EXPECT_EQ(scene.sigma[i], before.sigma[i]);
            }
        }
    }
    EXPECT_EQ(speckle_pixels, removed);
}

TEST(SpeckleFilter, NeighboursBeyondMaxDiffSplitARegion) {
    // Two 8 x 8 halves of one 16 x 8 block, 2 px apart in disparity, on an empty image: with
    // max_diff 1 px each half is a 64-px region (removed with max_region 64); with max_diff
    // 2 px they are one 128-px region (kept).
    for (const std::int32_t diff : {16, 32}) {
        std::vector<std::int16_t> d(static_cast<std::size_t>(kW * kH), kNoDisparity);
        for (std::int32_t y = 10; y < 18; ++y) {
            for (std::int32_t x = 10; x < 26; ++x) {
                d[static_cast<std::size_t>(y * kW + x)] = static_cast<std::int16_t>(x < 18 ? 320 : 352);
            }
        }
        SpeckleConfig c = smallConfig();
        c.max_region_px = 64;
        c.max_diff_px16 = diff;
        Filter f(c);
        std::int32_t removed = -1;
        ASSERT_TRUE(f.filter.apply(DisparityOutput{ImageView<std::int16_t>(d.data(), kW, kH), {}, {}}, nullptr,
                                   &removed)
                        .isOk());
        EXPECT_EQ(removed, diff == 16 ? 128 : 0) << "max_diff_px16 " << diff;
    }
}

TEST(SpeckleFilter, ZeroMaxRegionChangesNothing) {
    Scene scene;
    const Scene before = scene;
    SpeckleConfig c = smallConfig();
    c.max_region_px = 0;
    Filter f(c);
    std::int32_t removed = -1;
    ASSERT_TRUE(f.filter.apply(scene.out(), nullptr, &removed).isOk());
    EXPECT_EQ(removed, 0);
    EXPECT_EQ(scene.d, before.d);
}

TEST(SpeckleFilter, BadConfigAndInputAreNamed) {
    SpeckleConfig c = smallConfig();
    c.max_region_px = -1;
    Status s = c.validate();
    EXPECT_EQ(s.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::string(s.reason()).find("max_region_px"), std::string::npos) << s.reason();
    EXPECT_EQ(SpeckleFilter::workspaceBytes(c), 0U);
    c = smallConfig();
    c.max_diff_px16 = 40000;
    EXPECT_NE(std::string(c.validate().reason()).find("max_diff_px16"), std::string::npos);
    c = smallConfig();
    c.max_width = 0;
    EXPECT_NE(std::string(c.validate().reason()).find("max_width"), std::string::npos);

    SpeckleFilter idle;
    std::vector<std::int16_t> d(static_cast<std::size_t>(kW * kH), 0);
    const DisparityOutput out{ImageView<std::int16_t>(d.data(), kW, kH), {}, {}};
    EXPECT_EQ(idle.apply(out).code(), StatusCode::kNotInitialized);

    // Too small an arena: kOutOfMemory.
    std::vector<std::byte> little(SpeckleFilter::workspaceBytes(smallConfig()) / 2U);
    Arena arena(little.data(), little.size());
    EXPECT_EQ(idle.init(smallConfig(), arena).code(), StatusCode::kOutOfMemory);

    Filter f(smallConfig());
    EXPECT_EQ(f.filter.apply(DisparityOutput{}).code(), StatusCode::kInvalidArgument);
    std::vector<std::int16_t> big(static_cast<std::size_t>((kW + 1) * kH), 0);
    EXPECT_EQ(f.filter.apply(DisparityOutput{ImageView<std::int16_t>(big.data(), kW + 1, kH), {}, {}}).code(),
              StatusCode::kSizeMismatch);
    std::vector<float> sigma(static_cast<std::size_t>(kW * (kH - 1)), 0.f);
    EXPECT_EQ(f.filter.apply(DisparityOutput{ImageView<std::int16_t>(d.data(), kW, kH),
                                             ImageView<float>(sigma.data(), kW, kH - 1), {}})
                  .code(),
              StatusCode::kSizeMismatch);
}

}  // namespace
}  // namespace vtm::stereo
