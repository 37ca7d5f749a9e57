// fsw/stereo: the disparity window (MlStereo::setDisparityWindow) against the search it
// replaces in the wide-baseline mapper (the right image copied shifted by the window's
// start, 0 outside, searched over the Config's disparities, the start added back), and
// placeDisparityWindow on hand-made disparities. Runs on every target.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "no_heap_guard.hpp"
#include "smooth_texture.hpp"
#include "vtm/core/assert.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/disparity_window.hpp"
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

struct Result {
    std::vector<std::int16_t> disparity = std::vector<std::int16_t>(kW * kH);
    std::vector<float> sigma = std::vector<float>(kW * kH);
    std::vector<std::uint8_t> reason = std::vector<std::uint8_t>(kW * kH);
    StereoStats stats{};
};

DisparityOutput outputOf(Result& r) {
    return DisparityOutput{ImageView<std::int16_t>(r.disparity.data(), kW, kH),
                           ImageView<float>(r.sigma.data(), kW, kH), ImageView<std::uint8_t>(r.reason.data(), kW, kH)};
}

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
                             ImageView<const std::uint8_t>(shifted.data(), kW, kH), outputOf(r), &r.stats)
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
                             ImageView<const std::uint8_t>(p.right.data(), kW, kH), outputOf(r), &r.stats)
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

// ---- placeDisparityWindow ------------------------------------------------------------

DisparityWindow place(std::vector<double> samples, std::int32_t count, std::int32_t lo = -1000,
                      std::int32_t hi = 1000) {
    DisparityWindow w;
    w.d_min = w.d_max = w.samples_inside = -99999;
    const Status s = placeDisparityWindow(Span<double>(samples.data(), samples.size()), count, lo, hi, w);
    EXPECT_TRUE(s.isOk()) << s.reason();
    return w;
}

TEST(PlaceDisparityWindow, CentresOnTheLargestGroupWithTwoPixelsOfMargin) {
    // count 16: a group spans at most 11 px. {10, 11, 12} beats {50}; centre 11:
    // d_min = floor(11 - 7.5 + 0.5) = 4.
    DisparityWindow w = place({50.0, 12.0, 10.0, 11.0}, 16);
    EXPECT_EQ(w.d_min, 4);
    EXPECT_EQ(w.d_max, 19);
    EXPECT_EQ(w.samples_inside, 3);
    // Two samples exactly 11 px apart are one group, with 2 px to each window edge.
    w = place({0.0, 11.0}, 16);
    EXPECT_EQ(w.d_min, -2);
    EXPECT_EQ(w.d_max, 13);
    EXPECT_EQ(w.samples_inside, 2);
    // 12 px apart they are not: two groups of one, the lower one wins: centre 0.
    w = place({12.0, 0.0}, 16);
    EXPECT_EQ(w.d_min, -7);
    EXPECT_EQ(w.samples_inside, 1);
    // Equal groups: the lowest disparities. {0, 1} and {100, 101}: centre 0.5,
    // floor(0.5 - 7.5 + 0.5) = -7.
    w = place({100.0, 1.0, 101.0, 0.0}, 16);
    EXPECT_EQ(w.d_min, -7);
    EXPECT_EQ(w.samples_inside, 2);
    // Halves round up: centre -3 with count 4: floor(-3 - 1.5 + 0.5) = -4.
    w = place({-3.0}, 4);
    EXPECT_EQ(w.d_min, -4);
    EXPECT_EQ(w.d_max, -1);
    // count < 5: no group spans anything; the lowest sample alone is the group.
    w = place({5.5, 5.0}, 3);
    EXPECT_EQ(w.d_min, 4);
    EXPECT_EQ(w.d_max, 6);
    EXPECT_EQ(w.samples_inside, 2);
    // A wide spread: the densest 124 px of a 128 window (the mapper's count).
    std::vector<double> many;
    for (int i = 0; i < 30; ++i) many.push_back(-150.0 + 4.0 * i);  // -150 .. -34
    many.push_back(40.0);
    many.push_back(-400.0);
    w = place(many, 128);
    EXPECT_EQ(w.d_min, static_cast<std::int32_t>(std::floor(0.5 * (-150.0 - 34.0) - 63.5 + 0.5)));
    EXPECT_EQ(w.samples_inside, 30);
}

TEST(PlaceDisparityWindow, StaysInsideBoundsThatHoldItAndSortsTheSamples) {
    std::vector<double> samples = {2.0, 1.0};
    DisparityWindow w;
    ASSERT_TRUE(placeDisparityWindow(Span<double>(samples.data(), samples.size()), 16, 0, 40, w).isOk());
    EXPECT_EQ(w.d_min, 0);  // floor(1.5 - 7) = -6, moved up to the bound
    EXPECT_EQ(w.d_max, 15);
    EXPECT_EQ(samples[0], 1.0);  // sorted in place
    EXPECT_EQ(samples[1], 2.0);
    w = place({39.0}, 16, 0, 40);  // start 32 would end at 47: moved down to end at 40
    EXPECT_EQ(w.d_min, 25);
    EXPECT_EQ(w.d_max, 40);
    w = place({39.0}, 16, 25, 40);  // exactly as wide as the window
    EXPECT_EQ(w.d_min, 25);
    w = place({39.0}, 16, 26, 40);  // narrower bounds: not applied
    EXPECT_EQ(w.d_min, 32);
    // The order of the samples does not matter.
    Random rng(5);
    std::vector<double> a;
    for (int i = 0; i < 40; ++i) a.push_back(-60.0 + 90.0 * rng.uniform01());
    std::vector<double> b(a.rbegin(), a.rend());
    const DisparityWindow wa = place(a, 32);
    const DisparityWindow wb = place(b, 32);
    EXPECT_EQ(wa.d_min, wb.d_min);
    EXPECT_EQ(wa.samples_inside, wb.samples_inside);
    // samples_inside counts the samples in the window against the sorted list.
    std::int32_t inside = 0;
    for (const double d : a) inside += (d >= wa.d_min && d <= wa.d_max) ? 1 : 0;
    EXPECT_EQ(wa.samples_inside, inside);
}

TEST(PlaceDisparityWindow, BadInputsAreNamed) {
    DisparityWindow w;
    double one[1] = {1.0};
    EXPECT_STREQ(placeDisparityWindow(Span<double>(), 16, 0, 10, w).reason(),
                 "placeDisparityWindow: samples: no disparity to place the window on");
    EXPECT_EQ(placeDisparityWindow(Span<double>(one, 1), 0, 0, 10, w).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(placeDisparityWindow(Span<double>(one, 1), 1025, 0, 10, w).detail(), 1025);
    EXPECT_STREQ(placeDisparityWindow(Span<double>(one, 1), 16, 10, 0, w).reason(),
                 "placeDisparityWindow: bound_min is above bound_max");
    double bad[3] = {1.0, std::nan(""), 2.0};
    const Status s = placeDisparityWindow(Span<double>(bad, 3), 16, 0, 10, w);
    EXPECT_STREQ(s.reason(), "placeDisparityWindow: samples: not finite or beyond 1e6 px");
    EXPECT_EQ(s.detail(), 1);
    double far[1] = {2.0e6};
    EXPECT_EQ(placeDisparityWindow(Span<double>(far, 1), 16, 0, 10, w).code(), StatusCode::kInvalidArgument);
    test::NoHeapScope guard;
    double few[4] = {3.0, 1.0, 2.0, 9.0};
    EXPECT_TRUE(placeDisparityWindow(Span<double>(few, 4), 16, -100, 100, w).isOk());
    EXPECT_EQ(guard.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm::stereo
