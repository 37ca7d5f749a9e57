// The fast forms of fsw/features' samplers and of the detector's determinant against their
// plain forms in the same run (fsw/features/src/bilinear.hpp, tensor_det.hpp): the template
// grid inside the image, the five samples of the affine refinement's gradient, the
// determinant in doubles. They must be the same bits, or every match would change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "bilinear.hpp"
#include "tensor_det.hpp"
#include "test_images.hpp"
#include "vtm/core/random.hpp"

namespace {

using vtm::Random;
using vtm::features::test::Image;
using namespace vtm::features::detail;

Image noiseImage(Random& rng, std::int32_t w, std::int32_t h) {
    Image img(w, h);
    for (auto& p : img.pixels) {
        p = static_cast<std::uint8_t>(rng.uniformInt(0, 255));
    }
    return img;
}

// A coordinate in [lo, hi], often an integer or a half (ties of the floors and the roundings).
double coordinate(Random& rng, double lo, double hi) {
    const double u = rng.uniform01();
    const double v = lo + (hi - lo) * rng.uniform01();
    double c = v;
    if (u < 0.2) {
        c = std::floor(v);
    } else if (u < 0.35) {
        c = std::floor(v) + 0.5;
    }
    return c < lo ? lo : (c > hi ? hi : c);
}

double entry(Random& rng) {
    const double u = rng.uniform01();
    if (u < 0.2) {
        return static_cast<double>(rng.uniformInt(-2, 2)) * 0.5;  // exact halves, zero
    }
    return (rng.uniform01() * 2.0 - 1.0) * 2.5;
}

TEST(Bilinear, QuantisedGridGivesThePlainSamplesInsideAndAtTheBorders) {
    Random rng(20261207);
    std::int32_t inside = 0, outside = 0;
    for (std::int32_t trial = 0; trial < 1500; ++trial) {
        const auto w = static_cast<std::int32_t>(rng.uniformInt(2, 48));
        const auto h = static_cast<std::int32_t>(rng.uniformInt(2, 48));
        const Image img = noiseImage(rng, w, h);
        const auto half = static_cast<std::int32_t>(rng.uniformInt(1, 7));
        const Affine2 m = rng.uniform01() < 0.2 ? Affine2{} : Affine2{entry(rng), entry(rng), entry(rng), entry(rng)};
        const double cx = coordinate(rng, -4.0, static_cast<double>(w) + 4.0);
        const double cy = coordinate(rng, -4.0, static_cast<double>(h) + 4.0);
        std::vector<std::uint16_t> fast(static_cast<std::size_t>((2 * half + 1) * (2 * half + 1)));
        sampleQuantisedGrid(img.view(), cx, cy, m, half, fast.data());
        bool all_inside = true;
        std::size_t i = 0;
        for (std::int32_t dy = -half; dy <= half; ++dy) {
            for (std::int32_t dx = -half; dx <= half; ++dx) {
                const double x = cx + (m.a * dx + m.b * dy), y = cy + (m.c * dx + m.d * dy);
                all_inside = all_inside && x >= 0.0 && x < w - 1.0 && y >= 0.0 && y < h - 1.0;
                ASSERT_EQ(fast[i], sampleQuantised(img.view(), x, y)) << "trial " << trial << " (" << dx << ", " << dy << ")";
                ++i;
            }
        }
        (all_inside ? inside : outside) += 1;
    }
    // Both ways were taken often: the fast one and the clamped one.
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 100);
}

TEST(Bilinear, CrossSampleGivesTheFivePlainSamples) {
    Random rng(7);
    const double step = 0.5;
    for (std::int32_t trial = 0; trial < 20000; ++trial) {
        const auto w = static_cast<std::int32_t>(rng.uniformInt(3, 40));
        const auto h = static_cast<std::int32_t>(rng.uniformInt(3, 40));
        const Image img = noiseImage(rng, w, h);
        // Every one of the five points inside [0, w-1] x [0, h-1], the last column and row
        // reached (the corner clamped to w - 2 there).
        double x = coordinate(rng, step, w - 1.0 - step), y = coordinate(rng, step, h - 1.0 - step);
        if (rng.uniform01() < 0.1) {
            x = w - 1.0 - step;
        }
        if (rng.uniform01() < 0.1) {
            y = h - 1.0 - step;
        }
        const CrossSample s = sampleCross(img.view(), x, y, step);
        const auto v = img.view();
        ASSERT_EQ(s.value, sampleLinear(v, x, y)) << trial;
        ASSERT_EQ(s.gx, sampleLinear(v, x + step, y) - sampleLinear(v, x - step, y)) << trial;
        ASSERT_EQ(s.gy, sampleLinear(v, x, y + step) - sampleLinear(v, x, y - step)) << trial;
    }
}

TEST(TensorDeterminant, IsTheInt64ValueRoundedOnce) {
    Random rng(11);
    for (std::int32_t trial = 0; trial < 200000; ++trial) {
        // Sums of up to 31 x 31 gradient products (each below 1,040,401), around 2^26 often.
        const std::int64_t top = rng.uniform01() < 0.5 ? (std::int64_t{1} << 27) : 1000000000;
        const auto sxx = static_cast<std::int32_t>(rng.uniformInt(0, top));
        const auto syy = static_cast<std::int32_t>(rng.uniformInt(0, top));
        const auto bound = static_cast<std::int64_t>(std::sqrt(static_cast<double>(sxx) * static_cast<double>(syy)));
        auto sxy = static_cast<std::int32_t>(rng.uniformInt(-bound, bound));
        if (static_cast<std::int64_t>(sxy) * sxy > static_cast<std::int64_t>(sxx) * syy) {
            sxy = 0;  // the rounded square root overshot
        }
        const double expected =
            static_cast<double>(static_cast<std::int64_t>(sxx) * syy - static_cast<std::int64_t>(sxy) * sxy);
        ASSERT_EQ(tensorDeterminant(sxx, syy, sxy), expected) << sxx << " " << syy << " " << sxy;
    }
}

}  // namespace
