// fsw/stereo unit tests: synthetic pairs whose true disparity is known exactly, error
// paths, memory. Runs on the host and on every cross target (real-data accuracy against
// OpenCV peers is tests/peer, host only).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "no_heap_guard.hpp"
#include "smooth_texture.hpp"
#include "stereo_buffers.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {
namespace {

constexpr std::int32_t kW = 160;
constexpr std::int32_t kH = 96;

// A smooth random texture (box-blurred noise) sampled at real-valued x by linear
// interpolation, so that a right image shifted by a fractional disparity is exact.
class Texture {
public:
    explicit Texture(std::uint64_t seed) {
        Random rng(seed);
        values_ = smoothTexture(rng, kW + 80, kH, 40.0, 170.0);
    }
    // Intensity at texture coordinate (u, y), u in [0, kW + 79].
    double at(double u, std::int32_t y) const {
        const auto u0 = static_cast<std::int32_t>(std::floor(u));
        const double f = u - u0;
        const std::size_t i = static_cast<std::size_t>(y * (kW + 80) + u0);
        return values_[i] * (1.0 - f) + values_[i + 1] * f;
    }

private:
    std::vector<double> values_;
};

struct Pair {
    std::vector<std::uint8_t> left = std::vector<std::uint8_t>(kW * kH);
    std::vector<std::uint8_t> right = std::vector<std::uint8_t>(kW * kH);
};

// Left (x, y) sees texture u = x + 40; right (x, y) sees u = x + 40 + disparity(x, y),
// i.e. left x matches right x - d. disparity(x, y) from `trueD`.
template <typename F>
Pair makePair(const Texture& t, F trueD) {
    Pair p;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            p.left[static_cast<std::size_t>(y * kW + x)] = static_cast<std::uint8_t>(t.at(x + 40.0, y) + 0.5);
        }
    }
    // The right image: for each right pixel xr, find the left x with x - d(x) = xr by
    // sampling the texture at the matching u (surfaces here are fronto-parallel pieces).
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t xr = 0; xr < kW; ++xr) {
            const double d = trueD(xr, y);
            p.right[static_cast<std::size_t>(y * kW + xr)] = static_cast<std::uint8_t>(t.at(xr + 40.0 + d, y) + 0.5);
        }
    }
    return p;
}

using StereoRun = StereoBuffers<kW, kH>;

StereoRun runStereo(const Config& c, const Pair& p) {
    static std::byte pool[8U << 20U];
    Arena arena(pool, sizeof pool);
    static MlStereo stereo;
    StereoRun r;
    r.status = stereo.init(c, arena);
    if (!r.status.isOk()) {
        return r;
    }
    r.status = stereo.compute(ImageView<const std::uint8_t>(p.left.data(), kW, kH),
                              ImageView<const std::uint8_t>(p.right.data(), kW, kH), r.out(), &r.stats);
    return r;
}

Config smallConfig(std::int32_t dMin, std::int32_t dMax) {
    Config c;
    c.max_width = kW;
    c.max_height = kH;
    c.d_min = dMin;
    c.d_max = dMax;
    return c;
}

// Fraction of interior pixels (away from borders and from disparity edges) whose
// disparity is within tol px of the truth; and the mean absolute error there.
template <typename F>
void interiorError(const StereoRun& r, F trueD, double tol, double* within, double* mae, std::int32_t margin = 12) {
    std::int32_t n = 0;
    std::int32_t ok = 0;
    double sum = 0.0;
    for (std::int32_t y = margin; y < kH - margin; ++y) {
        for (std::int32_t x = margin + 24; x < kW - margin; ++x) {
            const std::int16_t d16 = r.disparity[static_cast<std::size_t>(y * kW + x)];
            ++n;
            if (d16 == kNoDisparity) {
                continue;
            }
            const double err = std::fabs(d16 / 16.0 - trueD(x - d16 / 16.0, y));
            ok += err <= tol ? 1 : 0;
            sum += err;
        }
    }
    *within = static_cast<double>(ok) / n;
    *mae = sum / (ok > 0 ? ok : 1);
}

TEST(MlStereo, ConstantIntegerDisparityIsRecovered) {
    const Texture t(1);
    const auto d = [](double, std::int32_t) { return 9.0; };
    const StereoRun r = runStereo(smallConfig(0, 23), makePair(t, d));
    ASSERT_TRUE(r.status.isOk()) << r.status.reason();
    double within = 0.0;
    double mae = 0.0;
    interiorError(r, d, 0.5, &within, &mae);
    EXPECT_GT(within, 0.99);
    EXPECT_LT(mae, 0.1);
}

TEST(MlStereo, SubpixelDisparityIsRecoveredToAQuarterPixel) {
    const Texture t(2);
    for (const double trueD : {5.25, 5.5, 5.75}) {
        const auto d = [trueD](double, std::int32_t) { return trueD; };
        const StereoRun r = runStereo(smallConfig(0, 15), makePair(t, d));
        ASSERT_TRUE(r.status.isOk());
        double within = 0.0;
        double mae = 0.0;
        interiorError(r, d, 0.5, &within, &mae);
        EXPECT_GT(within, 0.97) << trueD;
        EXPECT_LT(mae, 0.25) << trueD;
    }
}

TEST(MlStereo, NegativeDisparitiesOfVergedPairs) {
    const Texture t(3);
    const auto d = [](double, std::int32_t) { return -6.0; };
    const StereoRun r = runStereo(smallConfig(-12, 4), makePair(t, d));
    ASSERT_TRUE(r.status.isOk());
    double within = 0.0;
    double mae = 0.0;
    interiorError(r, d, 0.5, &within, &mae);
    EXPECT_GT(within, 0.99);
}

TEST(MlStereo, TwoPlanesKeepTheirEdge) {
    // Foreground (d = 14) on the right half of the image over a background (d = 4).
    const Texture t(4);
    const auto d = [](double xLeft, std::int32_t) { return xLeft >= 90.0 ? 14.0 : 4.0; };
    const auto dRight = [](double xr, std::int32_t) { return xr >= 90.0 - 14.0 ? 14.0 : 4.0; };
    const StereoRun r = runStereo(smallConfig(0, 23), makePair(t, dRight));
    ASSERT_TRUE(r.status.isOk());
    std::int32_t good = 0;
    std::int32_t n = 0;
    for (std::int32_t y = 12; y < kH - 12; ++y) {
        for (std::int32_t x = 30; x < kW - 8; ++x) {
            if (x >= 76 && x < 90) {
                continue;  // background occluded in the right image (no true match)
            }
            const std::int16_t d16 = r.disparity[static_cast<std::size_t>(y * kW + x)];
            ++n;
            good += (d16 != kNoDisparity && std::fabs(d16 / 16.0 - d(x, y)) <= 1.0) ? 1 : 0;
        }
    }
    EXPECT_GT(static_cast<double>(good) / n, 0.95);
}

TEST(MlStereo, UncertaintyIsFiniteForValidAndInfiniteOtherwise) {
    const Texture t(5);
    const auto d = [](double, std::int32_t) { return 7.0; };
    const StereoRun r = runStereo(smallConfig(0, 15), makePair(t, d));
    ASSERT_TRUE(r.status.isOk());
    for (std::size_t i = 0; i < r.disparity.size(); ++i) {
        if (r.disparity[i] == kNoDisparity) {
            EXPECT_TRUE(std::isinf(r.sigma[i]));
            EXPECT_NE(r.reason[i], static_cast<std::uint8_t>(Reason::kValid));
        } else {
            EXPECT_GT(r.sigma[i], 0.0F);
            EXPECT_LT(r.sigma[i], 2.0F);
            EXPECT_EQ(r.reason[i], static_cast<std::uint8_t>(Reason::kValid));
        }
    }
    EXPECT_EQ(r.stats.valid_pixels, r.stats.reason_counts[0]);
}

TEST(MlStereo, TexturelessPairGivesNoTextureNotNonsense) {
    Pair p;
    std::fill(p.left.begin(), p.left.end(), std::uint8_t{90});
    std::fill(p.right.begin(), p.right.end(), std::uint8_t{90});
    const StereoRun r = runStereo(smallConfig(0, 15), p);
    ASSERT_TRUE(r.status.isOk());
    EXPECT_EQ(r.stats.valid_pixels, 0);
    EXPECT_GT(r.stats.reason_counts[static_cast<std::int32_t>(Reason::kNoTexture)], kW * kH / 2);
}

TEST(MlStereo, PixelsWithoutAnySearchPositionAreBorder) {
    const Texture t(6);
    const auto d = [](double, std::int32_t) { return 20.0; };
    const StereoRun r = runStereo(smallConfig(20, 35), makePair(t, d));
    ASSERT_TRUE(r.status.isOk());
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < 20; ++x) {
            EXPECT_EQ(r.reason[static_cast<std::size_t>(y * kW + x)], static_cast<std::uint8_t>(Reason::kBorder));
        }
    }
}

TEST(MlStereo, ConservativePresetReturnsFewerButMoreOftenCorrectDisparities) {
    const Texture t(7);
    const auto dRight = [](double xr, std::int32_t) { return xr >= 76.0 ? 14.0 : 4.0; };
    const auto d = [](double xLeft, std::int32_t) { return xLeft >= 90.0 ? 14.0 : 4.0; };
    const Pair pair = makePair(t, dRight);
    Config dense = smallConfig(0, 23);
    Config conservative = Config::conservative();
    conservative.max_width = kW;
    conservative.max_height = kH;
    conservative.d_min = 0;
    conservative.d_max = 23;
    const StereoRun a = runStereo(dense, pair);
    const StereoRun b = runStereo(conservative, pair);
    ASSERT_TRUE(a.status.isOk());
    ASSERT_TRUE(b.status.isOk());
    const auto wrongAmongValid = [&d](const StereoRun& r) {
        std::int32_t valid = 0;
        std::int32_t wrong = 0;
        for (std::int32_t y = 6; y < kH - 6; ++y) {
            for (std::int32_t x = 30; x < kW; ++x) {
                const std::int16_t d16 = r.disparity[static_cast<std::size_t>(y * kW + x)];
                if (d16 == kNoDisparity) {
                    continue;
                }
                ++valid;
                wrong += std::fabs(d16 / 16.0 - d(x, y)) > 1.0 ? 1 : 0;
            }
        }
        return static_cast<double>(wrong) / (valid > 0 ? valid : 1);
    };
    EXPECT_LT(b.stats.valid_pixels, a.stats.valid_pixels);
    EXPECT_LT(wrongAmongValid(b), wrongAmongValid(a));
    EXPECT_GT(b.stats.reason_counts[static_cast<std::int32_t>(Reason::kLeftRightMismatch)], 0);
}

TEST(MlStereo, ComputeTouchesNoHeap) {
    const Texture t(8);
    const Pair pair = makePair(t, [](double, std::int32_t) { return 3.0; });
    static std::byte pool[4U << 20U];
    Arena arena(pool, sizeof pool);
    static MlStereo stereo;
    ASSERT_TRUE(stereo.init(smallConfig(0, 15), arena).isOk());
    arena.freeze();
    static std::int16_t disparity[kW * kH];
    static float sigma[kW * kH];
    static std::uint8_t reason[kW * kH];
    const DisparityOutput out{ImageView<std::int16_t>(disparity, kW, kH), ImageView<float>(sigma, kW, kH),
                              ImageView<std::uint8_t>(reason, kW, kH)};
    test::NoHeapScope guard;
    for (int i = 0; i < 2; ++i) {
        ASSERT_TRUE(stereo.compute(ImageView<const std::uint8_t>(pair.left.data(), kW, kH),
                                   ImageView<const std::uint8_t>(pair.right.data(), kW, kH), out)
                        .isOk());
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
}

TEST(MlStereo, WorkspaceFormulaIsExactlyEnoughAndFits8MiBForTheFlightCase) {
    Config big;
    big.max_width = 1024;
    big.max_height = 1024;
    big.d_min = 0;
    big.d_max = 255;
    EXPECT_LE(MlStereo::workspaceBytes(big), std::size_t{8} << 20U);
    const Config c = smallConfig(0, 31);
    const std::size_t need = MlStereo::workspaceBytes(c);
    ASSERT_GT(need, 0U);
    static std::byte pool[2U << 20U];
    ASSERT_LE(need, sizeof pool);
    static MlStereo stereo;
    Arena exact(pool, need);
    EXPECT_TRUE(stereo.init(c, exact).isOk());
    Arena tooSmall(pool, need / 2U);
    const Status s = stereo.init(c, tooSmall);
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(s.detail(), static_cast<std::int64_t>(need));
}

TEST(MlStereo, ErrorsNameTheInput) {
    static MlStereo stereo;
    static std::uint8_t img[kW * kH];
    static std::int16_t disp[kW * kH];
    const ImageView<const std::uint8_t> view(img, kW, kH);
    const DisparityOutput out{ImageView<std::int16_t>(disp, kW, kH), {}, {}};
    MlStereo fresh;
    EXPECT_EQ(fresh.compute(view, view, out).code(), StatusCode::kNotInitialized);
    static std::byte pool[2U << 20U];
    Arena arena(pool, sizeof pool);
    ASSERT_TRUE(stereo.init(smallConfig(0, 15), arena).isOk());
    const ImageView<const std::uint8_t> smaller(img, kW - 2, kH);
    EXPECT_EQ(stereo.compute(view, smaller, out).code(), StatusCode::kSizeMismatch);
    EXPECT_STREQ(stereo.compute(view, smaller, out).reason(), "MlStereo::compute: left and right sizes differ");
    const DisparityOutput wrongOut{ImageView<std::int16_t>(disp, kW - 1, kH), {}, {}};
    EXPECT_EQ(stereo.compute(view, view, wrongOut).code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(stereo.compute(ImageView<const std::uint8_t>(), view, out).code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(stereo.compute(view, view, out).isOk());  // reason and sigma are optional
}

TEST(MlStereoConfig, EveryBadFieldIsNamed) {
    struct Case {
        void (*mutate)(Config&);
        const char* field;
    };
    const Case cases[] = {
        {[](Config& c) { c.max_width = 4; }, "max_width"},
        {[](Config& c) { c.max_height = 9000; }, "max_height"},
        {[](Config& c) { c.d_max = c.d_min - 1; }, "d_max"},
        {[](Config& c) { c.d_min = -10; c.d_max = 1020; }, "d_max"},
        {[](Config& c) { c.window = 8; }, "window"},
        {[](Config& c) { c.window = 33; }, "window"},
        {[](Config& c) { c.beta_q10 = 0; }, "beta_q10"},
        {[](Config& c) { c.intensity_bins = 48; }, "intensity_bins"},
        {[](Config& c) { c.inlier_sigma_px16 = 2; }, "inlier_sigma_px16"},
        {[](Config& c) { c.inlier_percent = 100; }, "inlier_percent"},
        {[](Config& c) { c.outlier_level_percent = 0; }, "outlier_level_percent"},
        {[](Config& c) { c.truncation_sigmas = 7; }, "truncation_sigmas"},
        {[](Config& c) { c.prefilter_window = 4; }, "prefilter_window"},
        {[](Config& c) { c.uniqueness_percent = -1; }, "uniqueness_percent"},
        {[](Config& c) { c.lr_max_diff_px = -2; }, "lr_max_diff_px"},
        {[](Config& c) { c.max_outlier_percent = 0; }, "max_outlier_percent"},
    };
    EXPECT_TRUE(Config{}.validate().isOk());
    EXPECT_TRUE(Config::conservative().validate().isOk());
    for (const Case& k : cases) {
        Config c;
        k.mutate(c);
        const Status s = c.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << k.field;
        EXPECT_EQ(std::strncmp(s.reason(), k.field, std::strlen(k.field)), 0) << s.reason();
        EXPECT_EQ(MlStereo::workspaceBytes(c), 0U);
    }
}

}  // namespace
}  // namespace vtm::stereo
