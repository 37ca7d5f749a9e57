// The sweep's row warp (fsw/descent/src/warp_row.hpp) against its plain form in the same
// run: every pixel tested and sampled as the sweep did before the row was split into
// columns certainly inside, certainly outside and tested. Both must give the same floats
// bit for bit, or the depths would change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "vtm/core/random.hpp"
#include "warp_row.hpp"

namespace {

using vtm::Random;
using vtm::descent::detail::kSubpixel;
using vtm::descent::detail::kSubpixelBits;

// The plain form: every pixel of [x0, x1) tested (W > 0, inside image 2) and sampled.
void plainRow(const double* h, std::int32_t y, std::int32_t x0, std::int32_t x1, const std::uint16_t* src,
              std::int32_t w, std::int32_t height, float* out) {
    const double s = static_cast<double>(kSubpixel);
    const double h0 = s * h[0], h3 = s * h[3];
    const double cu = 0.5 * s * static_cast<double>(w - 1);
    const double cv = 0.5 * s * static_cast<double>(height - 1);
    const double yd = static_cast<double>(y);
    const double bx = s * (h[1] * yd + h[2]);
    const double by = s * (h[4] * yd + h[5]);
    const double bw = h[7] * yd + h[8];
    for (std::int32_t x = x0; x < x1; ++x) {
        const auto xd = static_cast<double>(x);
        const double W = h[6] * xd + bw;
        out[x] = 0.0F;
        if (!(W > 0.0)) {
            continue;
        }
        const double inv = 1.0 / W;
        const double pu = (h0 * xd + bx) * inv;
        const double pv = (h3 * xd + by) * inv;
        if (!(std::fabs(pu - cu) <= cu && std::fabs(pv - cv) <= cv)) {
            continue;
        }
        const auto ui = static_cast<std::int32_t>(pu + 0.5);  // NOLINT(bugprone-incorrect-roundings)
        const auto vi = static_cast<std::int32_t>(pv + 0.5);  // NOLINT(bugprone-incorrect-roundings)
        const std::int32_t fx = ui & (kSubpixel - 1);
        const std::int32_t fy = vi & (kSubpixel - 1);
        const std::uint16_t* p = src + static_cast<std::ptrdiff_t>(vi >> kSubpixelBits) * w + (ui >> kSubpixelBits);
        const auto top = static_cast<std::uint32_t>(p[0] * (kSubpixel - fx) + p[1] * fx);
        const auto bottom = static_cast<std::uint32_t>(p[w] * (kSubpixel - fx) + p[w + 1] * fx);
        const std::uint32_t sum = top * static_cast<std::uint32_t>(kSubpixel - fy) + bottom * static_cast<std::uint32_t>(fy);
        out[x] = static_cast<float>(static_cast<std::int32_t>((sum + 512U) >> 10U));
    }
}

// A homography like a plane's between two descent frames: scale, rotation, shift and a
// perspective row; some with W crossing zero inside the image, some mapping it far away.
void randomHomography(Random& rng, std::int32_t w, std::int32_t height, double* h) {
    const double scale = 0.5 + 1.5 * rng.uniform01();
    const double angle = (rng.uniform01() - 0.5) * 0.6;
    const double c = scale * std::cos(angle), s = scale * std::sin(angle);
    const double shift = rng.uniform01() < 0.2 ? 3.0 : 0.5;  // sometimes far outside
    h[0] = c;
    h[1] = -s;
    h[2] = (rng.uniform01() - 0.5) * shift * w;
    h[3] = s;
    h[4] = c;
    h[5] = (rng.uniform01() - 0.5) * shift * height;
    const double persp = rng.uniform01() < 0.25 ? 4e-3 : 4e-4;  // W through 0 for some
    h[6] = (rng.uniform01() - 0.5) * persp;
    h[7] = (rng.uniform01() - 0.5) * persp;
    h[8] = 1.0;
}

TEST(WarpRow, EqualsThePlainPixelByPixelWarpBitForBit) {
    Random rng(20261207U);
    for (std::int32_t trial = 0; trial < 60; ++trial) {
        const std::int32_t w = 16 + static_cast<std::int32_t>(rng.uniform01() * 200.0);
        const std::int32_t height = 16 + static_cast<std::int32_t>(rng.uniform01() * 200.0);
        // Image 2 in levels x 16 with its padding row and pixel (the sweep's prefilter()).
        std::vector<std::uint16_t> image(static_cast<std::size_t>(w) * height + w + 1, 0U);
        for (std::size_t i = 0; i < static_cast<std::size_t>(w) * height; ++i) {
            image[i] = static_cast<std::uint16_t>(rng.uniform01() * 4095.0) * 16U;
        }
        double h[9];
        randomHomography(rng, w, height, h);
        if (trial == 0) {
            h[6] = std::numeric_limits<double>::quiet_NaN();  // a non-finite term: all tested, all 0
        }
        std::vector<float> fast(static_cast<std::size_t>(w), -1.0F), plain(static_cast<std::size_t>(w), -1.0F);
        std::int32_t inside = 0;
        for (std::int32_t y = -20; y < height + 20; y += 3) {
            const std::int32_t x0 = static_cast<std::int32_t>(rng.uniform01() * 0.3 * w);
            const std::int32_t x1 = w - static_cast<std::int32_t>(rng.uniform01() * 0.3 * w);
            vtm::descent::detail::warpRow(h, y, x0, x1, image.data(), w, height, fast.data());
            plainRow(h, y, x0, x1, image.data(), w, height, plain.data());
            ASSERT_EQ(0, std::memcmp(fast.data(), plain.data(), fast.size() * sizeof(float)))
                << "trial " << trial << " row " << y << " columns " << x0 << ".." << x1;
            for (std::int32_t x = x0; x < x1; ++x) {
                inside += plain[static_cast<std::size_t>(x)] != 0.0F ? 1 : 0;
            }
        }
        if (trial == 0) {
            EXPECT_EQ(inside, 0);
        }
    }
}

// spanMappedInside holds every column whose point maps inside image 2 (the sweep scores
// only those columns' windows; a column left out would lose its depth).
TEST(WarpRow, TheMappedInsideSpanHoldsEveryColumnThatMapsInside) {
    Random rng(7U);
    std::int32_t inside = 0, outside = 0;
    for (std::int32_t trial = 0; trial < 60; ++trial) {
        const std::int32_t w = 16 + static_cast<std::int32_t>(rng.uniform01() * 200.0);
        const std::int32_t height = 16 + static_cast<std::int32_t>(rng.uniform01() * 200.0);
        double h[9];
        randomHomography(rng, w, height, h);
        const double dx = (rng.uniform01() - 0.5) * 10.0;
        for (std::int32_t y = -20; y < height + 20; y += 3) {
            double lo = 0.0, hi = 0.0;
            vtm::descent::detail::spanMappedInside(h, dx, static_cast<double>(y), w, height, lo, hi);
            for (std::int32_t x = 0; x < w; ++x) {
                const double px = x + dx;
                const double W = h[6] * px + (h[7] * y + h[8]);
                const double u = (h[0] * px + (h[1] * y + h[2])) / W;
                const double v = (h[3] * px + (h[4] * y + h[5])) / W;
                const bool in = W > 0.0 && u >= 0.0 && u <= w - 1 && v >= 0.0 && v <= height - 1;
                inside += in ? 1 : 0;
                outside += (!in && (x < lo || x > hi)) ? 1 : 0;
                ASSERT_TRUE(!in || (x >= lo && x <= hi)) << "trial " << trial << " row " << y << " x " << x;
            }
        }
    }
    EXPECT_GT(inside, 10000);
    EXPECT_GT(outside, 10000);  // and it leaves out much of what maps outside
}

}  // namespace
