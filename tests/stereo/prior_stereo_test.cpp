// MlStereo's disparity prior (setDisparityPrior) and PyramidStereo (coarse to fine) on
// synthetic pairs whose true disparity is known exactly: a slanted surface whose
// disparity changes by tens of pixels over the image, as level ground does in a
// wide-baseline pair. Runs on the host and on every cross target.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "smooth_texture.hpp"
#include "stereo_buffers.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#include "vtm/stereo/pyramid_stereo.hpp"

namespace vtm::stereo {
namespace {

constexpr std::int32_t kW = 256;
constexpr std::int32_t kH = 128;
constexpr std::int32_t kTexturePad = 160;  // texture columns beyond the image (the largest disparity)

// The true disparity: a ramp down the image, 12 px at the top row to 12 + 0.75 (kH - 1)
// = 107.25 px at the bottom (ground seen from a mast: nearer, larger disparity below; level
// ground in a wide-baseline pair changes by baseline / camera height px per row, 3 px for a
// 5 m drive). gSlope: 0.75 px per row unless a test sets it.
double gSlope = 0.75;
double trueDisparity(std::int32_t y) { return 12.0 + gSlope * y; }

struct Pair {
    std::vector<std::uint8_t> left = std::vector<std::uint8_t>(kW * kH);
    std::vector<std::uint8_t> right = std::vector<std::uint8_t>(kW * kH);
};

// Left (x, y) sees texture column x + pad; right (x, y) sees column x + pad + d(y), so left x
// matches right x - d(y). The texture is linearly interpolated: fractional disparities are exact.
Pair makePair(std::uint64_t seed) {
    Random rng(seed);
    constexpr std::int32_t tw = kW + kTexturePad + 2;
    // Texture at two scales: pixel-scale noise and noise at 8 px (linearly interpolated),
    // which the coarse levels of PyramidStereo still see.
    std::vector<double> tex = smoothTexture(rng, tw, kH, 20.0, 110.0);
    const std::vector<double> coarse = smoothTexture(rng, tw / 8 + 2, kH / 8 + 2, 0.0, 110.0);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < tw; ++x) {
            const double fx = x / 8.0;
            const double fy = y / 8.0;
            const auto x0 = static_cast<std::int32_t>(fx);
            const auto y0 = static_cast<std::int32_t>(fy);
            const auto c = [&coarse, tw](std::int32_t cx, std::int32_t cy) {
                return coarse[static_cast<std::size_t>(cy * (tw / 8 + 2) + cx)];
            };
            const double ax = fx - x0;
            const double ay = fy - y0;
            tex[static_cast<std::size_t>(y * tw + x)] +=
                (1 - ay) * ((1 - ax) * c(x0, y0) + ax * c(x0 + 1, y0)) + ay * ((1 - ax) * c(x0, y0 + 1) + ax * c(x0 + 1, y0 + 1));
        }
    }
    const auto at = [&tex](double u, std::int32_t y) {
        const auto u0 = static_cast<std::int32_t>(std::floor(u));
        const double f = u - u0;
        const std::size_t i = static_cast<std::size_t>(y * tw + u0);
        return tex[i] * (1.0 - f) + tex[i + 1] * f;
    };
    Pair p;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            p.left[i] = static_cast<std::uint8_t>(at(x + kTexturePad, y) + 0.5);
        }
    }
    // The right image is the left one moved left by d(y): right(xr) = left(xr + d).
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t xr = 0; xr < kW; ++xr) {
            const double u = xr + kTexturePad + trueDisparity(y);
            p.right[static_cast<std::size_t>(y * kW + xr)] =
                static_cast<std::uint8_t>(u + 1.0 < tw ? at(u, y) + 0.5 : 0.0);
        }
    }
    return p;
}

using StereoRun = StereoBuffers<kW, kH>;

ImageView<const std::uint8_t> view(const std::vector<std::uint8_t>& v) {
    return ImageView<const std::uint8_t>(v.data(), kW, kH);
}

Config config(std::int32_t d_min, std::int32_t d_max) {
    Config c;
    c.max_width = kW;
    c.max_height = kH;
    c.d_min = d_min;
    c.d_max = d_max;
    return c;
}

// Share of the pixels at least `margin` from the image edges (and right of the largest
// disparity, which the right image sees) whose disparity is within tol px of the truth.
double shareWithin(const StereoRun& r, double tol, std::int32_t margin = 8) {
    std::int32_t n = 0;
    std::int32_t ok = 0;
    for (std::int32_t y = margin; y < kH - margin; ++y) {
        for (std::int32_t x = 128 + margin; x < kW - margin; ++x) {
            ++n;
            const std::int16_t d16 = r.disparity[static_cast<std::size_t>(y * kW + x)];
            ok += (d16 != kNoDisparity && std::fabs(d16 / 16.0 - trueDisparity(y)) <= tol) ? 1 : 0;
        }
    }
    return static_cast<double>(ok) / n;
}

// One MlStereo, re-initialised per test (static: its state is large).
MlStereo& stereo() {
    static MlStereo s;
    return s;
}
std::byte* pool() {
    static std::byte p[6U << 20U];
    return p;
}
constexpr std::size_t kPoolBytes = 6U << 20U;

TEST(MlStereoPrior, AZeroPriorSearchesExactlyWhatThePlainSearchDoes) {
    const Pair pair = makePair(3);
    // A constant disparity of the same pair (row 0 of the ramp) is not needed: compare the
    // two modes on the ramp pair over a window around 0 in both (most pixels fail alike).
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(stereo().init(config(-20, 20), arena).isOk());
    StereoRun plain;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), plain.out(), &plain.stats).isOk());
    const std::vector<std::int16_t> zero(kW * kH, 0);
    ASSERT_TRUE(stereo().setDisparityPrior(ImageView<const std::int16_t>(zero.data(), kW, kH)).isOk());
    ASSERT_TRUE(stereo().hasDisparityPrior());
    StereoRun prior;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), prior.out(), &prior.stats).isOk());
    EXPECT_EQ(plain.disparity, prior.disparity);
    EXPECT_EQ(plain.reason, prior.reason);
    EXPECT_EQ(plain.stats.valid_pixels, prior.stats.valid_pixels);
    EXPECT_GT(plain.stats.valid_pixels, 1000);  // the top rows (d = 12..20) are found
}

TEST(MlStereoPrior, ARoughPriorGuidesANarrowSearchOverTheWholeRamp) {
    const Pair pair = makePair(5);
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(stereo().init(config(-6, 6), arena).isOk());
    // The prior: the truth off by a smooth error of up to +-3 px, rounded (as an
    // interpolated coarse disparity is).
    std::vector<std::int16_t> prior(kW * kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double err = 3.0 * std::sin(6.2831853 * x / 128.0) * std::cos(6.2831853 * y / 96.0);
            prior[static_cast<std::size_t>(y * kW + x)] = static_cast<std::int16_t>(std::lround(trueDisparity(y) + err));
        }
    }
    ASSERT_TRUE(stereo().setDisparityPrior(ImageView<const std::int16_t>(prior.data(), kW, kH)).isOk());
    StereoRun r;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), r.out(), &r.stats).isOk());
    // 13 disparities per pixel cover a ramp of 96 px. Without the prior the same 13
    // find only the top rows.
    stereo().clearDisparityPrior();
    StereoRun narrow;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), narrow.out(), &narrow.stats).isOk());
    EXPECT_LT(shareWithin(narrow, 0.5), 0.05);
    // The peer: the plain search over all 128 disparities the ramp needs, in this run. The
    // prior's window follows the slant, the plain one is fronto-parallel.
    Arena arena2(pool(), kPoolBytes);
    ASSERT_TRUE(stereo().init(config(0, 127), arena2).isOk());
    StereoRun full;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), full.out(), &full.stats).isOk());
    std::printf("within 0.5 / 0.25 px: prior +-6 px %.3f / %.3f, plain 0..127 %.3f / %.3f\n", shareWithin(r, 0.5),
                shareWithin(r, 0.25), shareWithin(full, 0.5), shareWithin(full, 0.25));
    EXPECT_GT(shareWithin(r, 0.5), 0.85);
    EXPECT_GE(shareWithin(r, 0.5), shareWithin(full, 0.5) - 0.02);
    EXPECT_GE(shareWithin(r, 0.25), shareWithin(full, 0.25) - 0.02);
}

TEST(MlStereoPrior, PixelsWithoutPriorOrWhoseSearchLeavesTheImageAreMarked) {
    const Pair pair = makePair(7);
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(stereo().init(config(-4, 4), arena).isOk());
    std::vector<std::int16_t> prior(kW * kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            std::int16_t v = static_cast<std::int16_t>(std::lround(trueDisparity(y)));
            if (x < 40 && y > 60) v = kNoDisparity;  // a hole in the prior
            if (x >= 200 && y < 20) v = -300;        // searches right of the right image
            prior[static_cast<std::size_t>(y * kW + x)] = v;
        }
    }
    ASSERT_TRUE(stereo().setDisparityPrior(ImageView<const std::int16_t>(prior.data(), kW, kH)).isOk());
    StereoRun r;
    ASSERT_TRUE(stereo().compute(view(pair.left), view(pair.right), r.out(), &r.stats).isOk());
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            if (x < 40 && y > 60) {
                ASSERT_EQ(r.reason[i], static_cast<std::uint8_t>(Reason::kNoPrior)) << x << "," << y;
                ASSERT_EQ(r.disparity[i], kNoDisparity);
            }
            if (x >= 200 && y < 20) {
                ASSERT_EQ(r.reason[i], static_cast<std::uint8_t>(Reason::kBorder)) << x << "," << y;
            }
        }
    }
    EXPECT_GT(shareWithin(r, 0.5), 0.9);  // the rest is found
}

TEST(MlStereoPrior, ErrorsNameTheInput) {
    static MlStereo fresh;
    const std::vector<std::int16_t> prior(kW * kH, 0);
    EXPECT_EQ(fresh.setDisparityPrior(ImageView<const std::int16_t>(prior.data(), kW, kH)).code(),
              StatusCode::kNotInitialized);
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(stereo().init(config(-4, 4), arena).isOk());
    EXPECT_EQ(stereo().setDisparityPrior(ImageView<const std::int16_t>()).code(), StatusCode::kInvalidArgument);
    ASSERT_TRUE(stereo().setDisparityPrior(ImageView<const std::int16_t>(prior.data(), kW - 1, kH)).isOk());
    const Pair pair = makePair(1);
    StereoRun r;
    const Status s = stereo().compute(view(pair.left), view(pair.right), r.out());
    EXPECT_EQ(s.code(), StatusCode::kSizeMismatch);
    EXPECT_NE(std::string(s.reason()).find("prior"), std::string::npos) << s.reason();
    // setDisparityWindow returns to the plain search.
    ASSERT_TRUE(stereo().setDisparityWindow(-4).isOk());
    EXPECT_FALSE(stereo().hasDisparityPrior());
    EXPECT_TRUE(stereo().compute(view(pair.left), view(pair.right), r.out()).isOk());
}

PyramidConfig pyramidConfig() {
    PyramidConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.levels = 1;               // a 128 x 64 coarse level
    c.coarse_disparities = 96;  // covers about 2 x 94 = 188 full-resolution px
    c.coarse_window = 7;
    c.fine_radius_px = 6;
    return c;
}

PyramidStereo& pyramid() {
    static PyramidStereo p;
    return p;
}

// Share of the pixels with a prior (away from the edges) whose prior is within tol px of the
// truth, and how many have one.
double priorWithin(const ImageView<const std::int16_t>& prior, double tol, std::int32_t* withPrior) {
    std::int32_t inside = 0;
    *withPrior = 0;
    for (std::int32_t y = 8; y < kH - 8; ++y) {
        for (std::int32_t x = 136; x < kW - 8; ++x) {
            const std::int16_t p = prior.row(y)[x];
            if (p == kNoDisparity) continue;
            ++*withPrior;
            inside += std::fabs(p - trueDisparity(y)) <= tol ? 1 : 0;
        }
    }
    return *withPrior > 0 ? static_cast<double>(inside) / *withPrior : 0.0;
}
constexpr std::int32_t kInterior = (kH - 16) * (kW - 144);

TEST(PyramidStereo, FindsAGentleRampFromTheRangeAlone) {
    gSlope = 0.1;
    const Pair pair = makePair(11);
    gSlope = 0.75;
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(pyramid().init(pyramidConfig(), arena).isOk());
    StereoRun r;
    PyramidStats st;
    const Status s = pyramid().compute(view(pair.left), view(pair.right), {}, 0, 150, r.out(), &st);
    ASSERT_TRUE(s.isOk()) << s.reason();
    EXPECT_LE(st.coarse_d_min * 2, 0);  // the coarse window holds the range asked for
    EXPECT_GE(st.coarse_d_max * 2, 150);
    gSlope = 0.1;
    std::int32_t withPrior = 0;
    const double inside = priorWithin(pyramid().prior(), 5.0, &withPrior);
    std::printf("range alone: prior within 5 px %.3f of %d (interior %d), disparity within 0.5 px %.3f\n", inside,
                withPrior, kInterior, shareWithin(r, 0.5));
    // Measured 0.89 of 59 % and 0.35 (this small pair's coarse level, 128 x 64, is weak;
    // docs/stereo.md). A scale or offset error in the prior gives ~0.
    EXPECT_GT(inside, 0.8);
    EXPECT_GT(withPrior, kInterior / 2);
    EXPECT_GT(shareWithin(r, 0.5), 0.3);
    gSlope = 0.75;
}

TEST(PyramidStereo, FollowsASurfaceToASteepRampItOnlyRoughlyKnows) {
    const Pair pair = makePair(11);
    // The surface: the ramp with a smooth error of up to +-10 px (a hill it does not know).
    std::vector<std::int16_t> surface(kW * kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double err = 10.0 * std::sin(6.2831853 * x / 200.0) * std::sin(3.14159265 * y / kH);
            surface[static_cast<std::size_t>(y * kW + x)] = static_cast<std::int16_t>(std::lround(trueDisparity(y) + err));
        }
    }
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(pyramid().init(pyramidConfig(), arena).isOk());
    StereoRun r;
    PyramidStats st;
    const Status s = pyramid().compute(view(pair.left), view(pair.right),
                                       ImageView<const std::int16_t>(surface.data(), kW, kH), 0, 150, r.out(), &st);
    ASSERT_TRUE(s.isOk()) << s.reason();
    std::int32_t withPrior = 0;
    const double inside = priorWithin(pyramid().prior(), 5.0, &withPrior);
    std::printf("surface-guided: coarse valid %d filled %d, prior within 5 px %.3f of %d, within 0.5 px %.3f\n",
                st.coarse.valid_pixels, st.coarse_filled, inside, withPrior, shareWithin(r, 0.5));
    // Without the surface the fronto-parallel coarse window finds less of the steep ramp.
    StereoRun plain;
    ASSERT_TRUE(pyramid().compute(view(pair.left), view(pair.right), {}, 0, 150, plain.out()).isOk());
    std::int32_t withPlain = 0;
    const double insidePlain = priorWithin(pyramid().prior(), 5.0, &withPlain);
    std::printf("range alone: prior within 5 px %.3f of %d, within 0.5 px %.3f\n", insidePlain, withPlain,
                shareWithin(plain, 0.5));
    EXPECT_GT(inside * withPrior, 1.5 * insidePlain * withPlain);
    EXPECT_GT(shareWithin(r, 0.5), 1.5 * shareWithin(plain, 0.5));
    EXPECT_GT(shareWithin(r, 0.5), 0.1);
}

TEST(PyramidStereo, ComputeTouchesNoHeapAndIsRepeatable) {
    const Pair pair = makePair(13);
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(pyramid().init(pyramidConfig(), arena).isOk());
    arena.freeze();
    StereoRun a;
    StereoRun b;
    {
        test::NoHeapScope guard;
        ASSERT_TRUE(pyramid().compute(view(pair.left), view(pair.right), {}, 0, 150, a.out()).isOk());
        ASSERT_TRUE(pyramid().compute(view(pair.left), view(pair.right), {}, 0, 150, b.out()).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(a.disparity, b.disparity);
}

TEST(PyramidStereo, WorkspaceFormulaIsExactlyEnough) {
    const PyramidConfig c = pyramidConfig();
    const std::size_t need = PyramidStereo::workspaceBytes(c);
    ASSERT_GT(need, 0U);
    ASSERT_LE(need, kPoolBytes);
    Arena exact(pool(), need);
    EXPECT_TRUE(pyramid().init(c, exact).isOk());
    Arena tooSmall(pool(), need / 2U);
    const Status s = pyramid().init(c, tooSmall);
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(s.detail(), static_cast<std::int64_t>(need));
}

TEST(PyramidStereo, ErrorsNameTheInput) {
    static PyramidStereo fresh;
    const Pair pair = makePair(1);
    StereoRun r;
    EXPECT_EQ(fresh.compute(view(pair.left), view(pair.right), {}, 0, 100, r.out()).code(), StatusCode::kNotInitialized);
    Arena arena(pool(), kPoolBytes);
    ASSERT_TRUE(pyramid().init(pyramidConfig(), arena).isOk());
    // Wider than 96 coarse disparities cover.
    const Status wide = pyramid().compute(view(pair.left), view(pair.right), {}, 0, 400, r.out());
    EXPECT_EQ(wide.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(pyramid().compute(view(pair.left), view(pair.right), {}, 10, 5, r.out()).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(pyramid()
                  .compute(ImageView<const std::uint8_t>(pair.left.data(), kW - 2, kH), view(pair.right), {}, 0, 100,
                           r.out())
                  .code(),
              StatusCode::kSizeMismatch);
}

TEST(PyramidConfig, EveryBadFieldIsNamed) {
    struct Case {
        const char* field;
        void (*mutate)(PyramidConfig&);
    };
    const Case cases[] = {
        {"levels", [](PyramidConfig& c) { c.levels = 0; }},
        {"levels", [](PyramidConfig& c) { c.levels = 4; }},
        {"coarse_disparities", [](PyramidConfig& c) { c.coarse_disparities = 2; }},
        {"coarse_window", [](PyramidConfig& c) { c.coarse_window = 8; }},
        {"fine_radius_px", [](PyramidConfig& c) { c.fine_radius_px = 0; }},
        {"fill_reach_px", [](PyramidConfig& c) { c.fill_reach_px = -1; }},
        {"levels", [](PyramidConfig& c) { c.max_width = 12; }},  // coarse level under 8 px
    };
    for (const Case& k : cases) {
        PyramidConfig c = pyramidConfig();
        k.mutate(c);
        const Status s = c.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << k.field;
        EXPECT_NE(std::string(s.reason()).find(k.field), std::string::npos) << s.reason();
        EXPECT_EQ(PyramidStereo::workspaceBytes(c), 0U);
    }
    EXPECT_TRUE(pyramidConfig().validate().isOk());
}

}  // namespace
}  // namespace vtm::stereo
