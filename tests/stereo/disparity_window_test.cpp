// fsw/stereo: the disparity window (MlStereo::setDisparityWindow) against the search it
// replaced in the wide-baseline mapper (the right image copied shifted by the window's
// start, 0 outside, searched over the Config's disparities, the start added back). Runs on
// every target.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "no_heap_guard.hpp"
#include "smooth_texture.hpp"
#include "stereo_buffers.hpp"
#include "vtm/core/assert.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {
namespace {

constexpr std::int32_t kW = 128;
constexpr std::int32_t kH = 48;

// A random pair: smooth random texture; the right image is the left one moved left by
// `disparity` columns (new texture where the move uncovers columns), plus noise.
struct Pair {
    std::vector<std::uint8_t> left = std::vector<std::uint8_t>(kW * kH);
    std::vector<std::uint8_t> right = std::vector<std::uint8_t>(kW * kH);
};

Pair randomPair(std::uint64_t seed, std::int32_t disparity) {
    Random rng(seed);
    // Texture columns u: left x sees u = x + kMargin, right x sees u = x + kMargin + disparity,
    // inside the texture for |disparity| <= kMargin.
    constexpr std::int32_t kMargin = 250;
    VTM_ASSERT(disparity >= -kMargin && disparity <= kMargin, disparity, kMargin);
    const std::int32_t tw = kW + 2 * kMargin;
    const std::vector<double> tex = smoothTexture(rng, tw, kH, 20.0, 215.0);
    Pair p;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double l = tex[static_cast<std::size_t>(y * tw + x + kMargin)];
            const double r = tex[static_cast<std::size_t>(y * tw + x + kMargin + disparity)] + 6.0 * (rng.uniform01() - 0.5);
            p.left[static_cast<std::size_t>(y * kW + x)] = static_cast<std::uint8_t>(l + 0.5);
            p.right[static_cast<std::size_t>(y * kW + x)] = static_cast<std::uint8_t>(r < 0.0 ? 0.0 : (r > 255.0 ? 255.0 : r + 0.5));
        }
    }
    return p;
}

using Result = StereoBuffers<kW, kH>;

// The mapper's former search: shifted(u) = right(u - s), 0 outside; the Config's window;
// s added to every disparity found.
Result shiftedCopySearch(MlStereo& stereo, const Pair& p, std::int32_t s) {
    std::vector<std::uint8_t> shifted(kW * kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t u = 0; u < kW; ++u) {
            const std::int32_t x = u - s;
            shifted[static_cast<std::size_t>(y * kW + u)] =
                (x >= 0 && x < kW) ? p.right[static_cast<std::size_t>(y * kW + x)] : std::uint8_t{0};
        }
    }
    Result r;
    EXPECT_TRUE(stereo.setDisparityWindow(stereo.config().d_min).isOk());
    EXPECT_TRUE(stereo
                    .compute(ImageView<const std::uint8_t>(p.left.data(), kW, kH),
                             ImageView<const std::uint8_t>(shifted.data(), kW, kH), r.out(), &r.stats)
                    .isOk());
    for (std::int16_t& d : r.disparity) {
        if (d != kNoDisparity) {
            d = static_cast<std::int16_t>(d + s * kDisparityScale);
        }
    }
    return r;
}

Result windowSearch(MlStereo& stereo, const Pair& p, std::int32_t window_min) {
    Result r;
    EXPECT_TRUE(stereo.setDisparityWindow(window_min).isOk());
    EXPECT_TRUE(stereo
                    .compute(ImageView<const std::uint8_t>(p.left.data(), kW, kH),
                             ImageView<const std::uint8_t>(p.right.data(), kW, kH), r.out(), &r.stats)
                    .isOk());
    return r;
}

std::int32_t countDifferent(const Result& a, const Result& b) {
    std::int32_t n = 0;
    for (std::size_t i = 0; i < a.disparity.size(); ++i) {
        n += (a.disparity[i] != b.disparity[i] || a.reason[i] != b.reason[i] ||
              std::memcmp(&a.sigma[i], &b.sigma[i], sizeof(float)) != 0)
                 ? 1
                 : 0;
    }
    return n;
}

Config windowConfig(std::int32_t d_min, std::int32_t d_max, bool conservative, Prefilter prefilter) {
    Config c = conservative ? Config::conservative() : Config{};
    c.max_width = kW;
    c.max_height = kH;
    c.d_min = d_min;
    c.d_max = d_max;
    c.window = 7;
    c.prefilter = prefilter;
    return c;
}

TEST(MlStereoWindow, WindowSearchEqualsTheShiftedCopySearchBitForBit) {
    static std::byte pool[1U << 20U];
    static MlStereo stereo;
    struct Case {
        std::int32_t config_min, config_max;  // the Config's window (count fixed at init)
        bool conservative;
        Prefilter prefilter;
        std::int32_t true_disparity;
        std::int32_t window_min;  // where the window is moved
    };
    const Case cases[] = {
        {0, 31, true, Prefilter::kLocalMeanRemoved, 40, 25},    // the mapper's case: d_min 0, moved up
        {0, 31, true, Prefilter::kLocalMeanRemoved, -60, -75},  // moved to negative disparities
        {0, 31, false, Prefilter::kNone, 70, 60},               // dense, no prefilter
        {-5, 20, true, Prefilter::kNone, -30, -40},             // a Config window not starting at 0
        {-5, 20, false, Prefilter::kLocalMeanRemoved, 12, 3},
        {0, 15, true, Prefilter::kLocalMeanRemoved, 6, 0},       // not moved at all
        {0, 15, true, Prefilter::kLocalMeanRemoved, 200, 180},  // beyond the image: all black
    };
    std::uint64_t seed = 100;
    for (const Case& k : cases) {
        const Config c = windowConfig(k.config_min, k.config_max, k.conservative, k.prefilter);
        Arena arena(pool, sizeof pool);
        ASSERT_TRUE(stereo.init(c, arena).isOk());
        EXPECT_EQ(stereo.windowMin(), k.config_min);
        const Pair p = randomPair(++seed, k.true_disparity);
        const Result want = shiftedCopySearch(stereo, p, k.window_min - k.config_min);
        const Result got = windowSearch(stereo, p, k.window_min);
        EXPECT_EQ(stereo.windowMin(), k.window_min);
        EXPECT_EQ(stereo.windowMax(), k.window_min + k.config_max - k.config_min);
        EXPECT_EQ(countDifferent(want, got), 0) << "window " << k.window_min;
        EXPECT_EQ(std::memcmp(&want.stats, &got.stats, sizeof(StereoStats)), 0);
        if (k.window_min < 150) {
            // The window holds the true disparity: the search found it somewhere.
            EXPECT_GT(got.stats.valid_pixels, kW * kH / 4) << "window " << k.window_min;
        }
        // The window stays where it was put: a second request gives the same bits.
        const Result again = windowSearch(stereo, p, k.window_min);
        EXPECT_EQ(countDifferent(got, again), 0);
    }
}

// Away from the image's left and right edges, the moved window gives what a matcher
// whose Config holds that window gives: the black columns and the columns pushed off the
// moved image are only seen near the edges (the matching window, the distance
// transform's radius and the prefilter's window wide; docs/stereo.md).
TEST(MlStereoWindow, AwayFromTheEdgesTheWindowEqualsAConfigOfThatWindow) {
    static std::byte pool_a[1U << 20U];
    static std::byte pool_b[1U << 20U];
    static MlStereo moved;
    static MlStereo direct;
    for (const std::int32_t window_min : {20, -40}) {
        const std::int32_t count = 24;
        const Config c = windowConfig(0, count - 1, true, Prefilter::kLocalMeanRemoved);
        const Config d = windowConfig(window_min, window_min + count - 1, true, Prefilter::kLocalMeanRemoved);
        Arena arena_a(pool_a, sizeof pool_a);
        Arena arena_b(pool_b, sizeof pool_b);
        ASSERT_TRUE(moved.init(c, arena_a).isOk());
        ASSERT_TRUE(direct.init(d, arena_b).isOk());
        const Pair p = randomPair(7, window_min + 10);
        const Result a = windowSearch(moved, p, window_min);
        const Result b = windowSearch(direct, p, window_min);
        // A left column x sees right columns x - d for d in the window, each widened by
        // the matching half-window, the DT radius and the prefilter's half-window. The
        // moved image holds right columns -s..w-1-s (s = the shift, here window_min):
        // black ones where the image has none, its own replicated border where it cuts
        // the image; the direct search sees columns 0..w-1 and nothing outside.
        const std::int32_t radius = (c.truncation_sigmas * c.inlier_sigma_px16 + 15) / 16;
        const std::int32_t reach = c.window / 2 + radius + c.prefilter_window / 2;
        const std::int32_t s = window_min;
        const std::int32_t x_lo = (s > 0 ? s : 0) + count - 1 + reach;
        const std::int32_t x_hi = kW + (s < 0 ? s : 0) - reach;
        ASSERT_LT(x_lo + 10, x_hi);
        std::int32_t compared = 0;
        std::int32_t different = 0;
        for (std::int32_t y = 0; y < kH; ++y) {
            for (std::int32_t x = x_lo; x < x_hi; ++x) {
                const std::size_t i = static_cast<std::size_t>(y * kW + x);
                different += (a.disparity[i] != b.disparity[i] || a.reason[i] != b.reason[i]) ? 1 : 0;
                ++compared;
            }
        }
        EXPECT_EQ(different, 0) << "window " << window_min << ", columns " << x_lo << ".." << x_hi - 1;
        EXPECT_GT(compared, 0);
    }
}

TEST(MlStereoWindow, WindowLimitsAndStateAreChecked) {
    MlStereo fresh;
    EXPECT_EQ(fresh.setDisparityWindow(0).code(), StatusCode::kNotInitialized);
    static std::byte pool[1U << 20U];
    static MlStereo stereo;
    Arena arena(pool, sizeof pool);
    ASSERT_TRUE(stereo.init(windowConfig(0, 63, true, Prefilter::kLocalMeanRemoved), arena).isOk());
    EXPECT_TRUE(stereo.setDisparityWindow(-2047).isOk());
    EXPECT_TRUE(stereo.setDisparityWindow(2047 - 63).isOk());
    EXPECT_EQ(stereo.windowMax(), 2047);
    const Status low = stereo.setDisparityWindow(-2048);
    EXPECT_EQ(low.code(), StatusCode::kInvalidArgument);
    EXPECT_STREQ(low.reason(), "MlStereo::setDisparityWindow: d_min: the window must lie in -2047..2047 px");
    EXPECT_EQ(low.detail(), -2048);
    EXPECT_EQ(stereo.setDisparityWindow(2047 - 62).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(stereo.setDisparityWindow(INT32_MAX).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(stereo.setDisparityWindow(INT32_MIN).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(stereo.windowMin(), 2047 - 63);  // a refused window leaves the last one
    // init() puts the Config's own window back.
    Arena again(pool, sizeof pool);
    ASSERT_TRUE(stereo.init(windowConfig(-3, 60, true, Prefilter::kLocalMeanRemoved), again).isOk());
    EXPECT_EQ(stereo.windowMin(), -3);
    EXPECT_EQ(stereo.windowMax(), 60);
}

TEST(MlStereoWindow, AMovedWindowTouchesNoHeap) {
    static std::byte pool[1U << 20U];
    static MlStereo stereo;
    Arena arena(pool, sizeof pool);
    ASSERT_TRUE(stereo.init(windowConfig(0, 15, true, Prefilter::kLocalMeanRemoved), arena).isOk());
    arena.freeze();
    const Pair p = randomPair(3, 30);
    static std::int16_t disparity[kW * kH];
    const DisparityOutput out{ImageView<std::int16_t>(disparity, kW, kH), {}, {}};
    test::NoHeapScope guard;
    for (const std::int32_t w : {25, -10}) {
        ASSERT_TRUE(stereo.setDisparityWindow(w).isOk());
        ASSERT_TRUE(stereo
                        .compute(ImageView<const std::uint8_t>(p.left.data(), kW, kH),
                                 ImageView<const std::uint8_t>(p.right.data(), kW, kH), out)
                        .isOk());
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm::stereo
