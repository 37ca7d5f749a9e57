// vtm_entropy_tests (local entropy): the fixed-point entropy image against a direct
// double-precision computation, the running histograms against brute force, flat images,
// 16-bit inputs, errors, every bad config field, no heap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "entropy_scene.hpp"
#include "no_heap_guard.hpp"
#include "vtm/entropy/local_entropy.hpp"

namespace vtm::entropy {
namespace {

struct Fixture {
    std::vector<std::byte> pool;
    Arena arena;
    LocalEntropy entropy;
    explicit Fixture(const EntropyConfig& c)
        : pool(LocalEntropy::workspaceBytes(c)), arena(pool.data(), pool.size()) {
        EXPECT_TRUE(entropy.init(c, arena).isOk());
    }
};

EntropyConfig smallConfig(std::int32_t window, std::int32_t bins) {
    EntropyConfig c;
    c.max_width = 80;
    c.max_height = 64;
    c.window = window;
    c.bins = bins;
    return c;
}

// Histogram of the window around (x, y), borders replicated, as the module defines it.
std::vector<std::int32_t> bruteHistogram(const std::vector<std::uint8_t>& img, std::int32_t w, std::int32_t h,
                                         std::int32_t x, std::int32_t y, std::int32_t window, std::int32_t bins) {
    std::vector<std::int32_t> counts(static_cast<std::size_t>(bins), 0);
    const std::int32_t r = window / 2;
    const std::int32_t shift = 8 - static_cast<std::int32_t>(std::lround(std::log2(bins)));
    for (std::int32_t dy = -r; dy <= r; ++dy) {
        for (std::int32_t dx = -r; dx <= r; ++dx) {
            const std::int32_t xx = std::clamp(x + dx, 0, w - 1);
            const std::int32_t yy = std::clamp(y + dy, 0, h - 1);
            ++counts[static_cast<std::size_t>(img[static_cast<std::size_t>(yy * w + xx)] >> shift)];
        }
    }
    return counts;
}

std::vector<std::uint8_t> textured(std::int32_t w, std::int32_t h) {
    const std::vector<std::uint8_t> world = test::makeWorld(3U);
    std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h);
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            img[static_cast<std::size_t>(y * w + x)] = world[static_cast<std::size_t>((y + 40) * test::kWorld + x + 40)];
        }
    }
    return img;
}

TEST(LocalEntropy, MatchesADirectDoublePrecisionComputation) {
    constexpr std::int32_t kW = 77;  // odd sizes: the borders and the last column are exercised
    constexpr std::int32_t kH = 53;
    for (const auto& [window, bins] : {std::pair{3, 8}, std::pair{9, 16}, std::pair{15, 64}}) {
        Fixture f(smallConfig(window, bins));
        const std::vector<std::uint8_t> img = textured(kW, kH);
        std::vector<std::uint8_t> out(img.size());
        ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint8_t>(img.data(), kW, kH),
                                      ImageView<std::uint8_t>(out.data(), kW, kH)).isOk());
        double worst = 0.0;
        std::int32_t spread = 0;
        for (std::int32_t y = 0; y < kH; ++y) {
            for (std::int32_t x = 0; x < kW; ++x) {
                const std::vector<std::int32_t> c = bruteHistogram(img, kW, kH, x, y, window, bins);
                double bits = 0.0;
                for (const std::int32_t n : c) {
                    if (n > 0) {
                        const double p = static_cast<double>(n) / (window * window);
                        bits -= p * std::log2(p);
                    }
                }
                const double expected = 255.0 * bits / std::log2(bins);
                const std::uint8_t got = out[static_cast<std::size_t>(y * kW + x)];
                worst = std::max(worst, std::fabs(got - expected));
                spread = std::max(spread, static_cast<std::int32_t>(got));
            }
        }
        // Rounding to the 8-bit output is 0.5; the 2^-16-bit table adds < 0.01 of a level.
        EXPECT_LE(worst, 0.51) << "window " << window << ", bins " << bins;
        EXPECT_GT(spread, 100) << "the scene has texture";
    }
}

TEST(LocalEntropy, RunningHistogramEqualsBruteForceExactly) {
    constexpr std::int32_t kW = 64;
    constexpr std::int32_t kH = 48;
    Fixture f(smallConfig(7, 32));
    const std::vector<std::uint8_t> img = textured(kW, kH);
    // A stride wider than the image: the module must honour it.
    std::vector<std::uint8_t> strided(static_cast<std::size_t>(kW + 5) * kH, 0xEE);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            strided[static_cast<std::size_t>(y * (kW + 5) + x)] = img[static_cast<std::size_t>(y * kW + x)];
        }
    }
    std::vector<std::uint8_t> out(img.size());
    ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint8_t>(strided.data(), kW, kH, kW + 5),
                                  ImageView<std::uint8_t>(out.data(), kW, kH)).isOk());
    std::int32_t mismatches = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::vector<std::int32_t> c = bruteHistogram(img, kW, kH, x, y, 7, 32);
            mismatches += out[static_cast<std::size_t>(y * kW + x)] != f.entropy.outputOf(c.data()) ? 1 : 0;
        }
    }
    EXPECT_EQ(mismatches, 0);
}

TEST(LocalEntropy, TableIsNLog2NInSixteenFractionBits) {
    Fixture f(smallConfig(31, 16));
    for (std::int32_t n = 0; n <= 31 * 31; ++n) {
        const double expected = n == 0 ? 0.0 : n * std::log2(static_cast<double>(n)) * 65536.0;
        EXPECT_LE(std::fabs(static_cast<double>(f.entropy.nLog2n(n)) - expected), 0.5 + 1e-6) << n;
    }
}

TEST(LocalEntropy, FlatImageHasZeroEntropyAndTwoEqualHalvesOneBit) {
    Fixture f(smallConfig(5, 16));
    std::vector<std::uint8_t> img(40 * 30, 137);
    std::vector<std::uint8_t> out(img.size(), 99);
    ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint8_t>(img.data(), 40, 30),
                                  ImageView<std::uint8_t>(out.data(), 40, 30)).isOk());
    for (const std::uint8_t v : out) {
        ASSERT_EQ(v, 0);
    }
    // Columns alternating between two bins: in the interior every window has 15 and 10
    // samples (or 10 and 15): H = 0.971 bit = 61.9 of 255 over log2(16) = 4 bits.
    for (std::int32_t y = 0; y < 30; ++y) {
        for (std::int32_t x = 0; x < 40; ++x) {
            img[static_cast<std::size_t>(y * 40 + x)] = (x % 2 == 0) ? 10 : 200;
        }
    }
    ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint8_t>(img.data(), 40, 30),
                                  ImageView<std::uint8_t>(out.data(), 40, 30)).isOk());
    const double bits = -(0.6 * std::log2(0.6) + 0.4 * std::log2(0.4));
    EXPECT_NEAR(out[10 * 40 + 10], 255.0 * bits / 4.0, 0.51);
}

TEST(LocalEntropy, SixteenBitInputWithItsSignificantBitsGivesTheEightBitResult) {
    EntropyConfig c = smallConfig(9, 16);
    c.input_bits = 12;
    Fixture f(c);
    const std::vector<std::uint8_t> img = textured(48, 40);
    std::vector<std::uint16_t> wide(img.size());
    for (std::size_t i = 0; i < img.size(); ++i) {
        wide[i] = static_cast<std::uint16_t>((img[i] << 4U) | (i % 16U));  // low bits do not change the bin
    }
    std::vector<std::uint8_t> a(img.size());
    std::vector<std::uint8_t> b(img.size());
    ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint8_t>(img.data(), 48, 40),
                                  ImageView<std::uint8_t>(a.data(), 48, 40)).isOk());
    ASSERT_TRUE(f.entropy.compute(ImageView<const std::uint16_t>(wide.data(), 48, 40),
                                  ImageView<std::uint8_t>(b.data(), 48, 40)).isOk());
    EXPECT_EQ(a, b);
    wide[100] = 4096;  // above 12 bits
    const Status s = f.entropy.compute(ImageView<const std::uint16_t>(wide.data(), 48, 40),
                                       ImageView<std::uint8_t>(b.data(), 48, 40));
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(s.detail(), 4096);
}

TEST(LocalEntropy, ErrorsNameTheInput) {
    LocalEntropy fresh;
    std::vector<std::uint8_t> img(32 * 32, 1);
    std::vector<std::uint8_t> out(img.size());
    const ImageView<const std::uint8_t> in(img.data(), 32, 32);
    EXPECT_EQ(fresh.compute(in, ImageView<std::uint8_t>(out.data(), 32, 32)).code(), StatusCode::kNotInitialized);
    Fixture f(smallConfig(5, 16));
    EXPECT_EQ(f.entropy.compute(ImageView<const std::uint8_t>(), ImageView<std::uint8_t>(out.data(), 32, 32)).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(f.entropy.compute(in, ImageView<std::uint8_t>(out.data(), 31, 32)).code(), StatusCode::kSizeMismatch);
    std::vector<std::uint8_t> big(100 * 10, 1);
    std::vector<std::uint8_t> bigOut(big.size());
    EXPECT_EQ(f.entropy.compute(ImageView<const std::uint8_t>(big.data(), 100, 10),
                                ImageView<std::uint8_t>(bigOut.data(), 100, 10)).code(),
              StatusCode::kSizeMismatch);
}

TEST(LocalEntropyConfig, EveryBadFieldIsNamedAndTheWorkspaceFits) {
    auto reason = [](const EntropyConfig& c) { return std::string(c.validate().reason()); };
    EntropyConfig c;
    EXPECT_TRUE(c.validate().isOk());
    c.max_width = 7;
    EXPECT_NE(reason(c).find("entropy.max_width"), std::string::npos);
    EXPECT_EQ(LocalEntropy::workspaceBytes(c), 0U);
    c = EntropyConfig{};
    c.max_height = 9000;
    EXPECT_NE(reason(c).find("entropy.max_height"), std::string::npos);
    for (const std::int32_t w : {1, 4, 33}) {
        c = EntropyConfig{};
        c.window = w;
        EXPECT_NE(reason(c).find("entropy.window"), std::string::npos) << w;
    }
    for (const std::int32_t b : {1, 12, 128}) {
        c = EntropyConfig{};
        c.bins = b;
        EXPECT_NE(reason(c).find("entropy.bins"), std::string::npos) << b;
    }
    c = EntropyConfig{};
    c.input_bits = 17;
    EXPECT_NE(reason(c).find("entropy.input_bits"), std::string::npos);
    c = EntropyConfig{};
    EXPECT_EQ(c.validate().code(), StatusCode::kOk);
    std::vector<std::byte> pool(LocalEntropy::workspaceBytes(c));
    Arena exact(pool.data(), pool.size());
    LocalEntropy e;
    EXPECT_TRUE(e.init(c, exact).isOk());
    Arena small(pool.data(), pool.size() / 2U);
    EXPECT_EQ(e.init(c, small).code(), StatusCode::kOutOfMemory);
}

TEST(LocalEntropy, ComputeTouchesNoHeap) {
    Fixture f(smallConfig(9, 16));
    const std::vector<std::uint8_t> img = textured(64, 64);
    std::vector<std::uint8_t> out(img.size());
    vtm::test::NoHeapScope guard;
    const Status s = f.entropy.compute(ImageView<const std::uint8_t>(img.data(), 64, 64),
                                       ImageView<std::uint8_t>(out.data(), 64, 64));
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_TRUE(s.isOk());
}

}  // namespace
}  // namespace vtm::entropy
