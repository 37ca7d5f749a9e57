// Equalisation before the entropy image (fsw/entropy/src/equalise.hpp): the local rank
// against its definition computed directly, and the properties registration relies on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "equalise.hpp"
#include "vtm/core/random.hpp"

namespace vtm::entropy::detail {
namespace {

struct Grey {
    std::int32_t w, h;
    std::vector<std::uint8_t> v;
    ImageView<const std::uint8_t> view() const { return ImageView<const std::uint8_t>(v.data(), w, h); }
};

Grey randomImage(std::int32_t w, std::int32_t h, std::uint64_t seed, std::int32_t levels) {
    Random rng(seed);
    Grey g{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h))};
    for (std::uint8_t& p : g.v) {
        p = static_cast<std::uint8_t>(rng.uniformInt(0, levels - 1));
    }
    return g;
}

// The definition, sample by sample: 256 (2 below + equal) / (2 n), at most 255, over the
// clipped square; fill (<= fillMax) neither counted nor ranked (0).
std::vector<std::uint8_t> rankDirectly(const Grey& g, std::int32_t r, std::int32_t fillMax) {
    std::vector<std::uint8_t> out(g.v.size());
    for (std::int32_t y = 0; y < g.h; ++y) {
        for (std::int32_t x = 0; x < g.w; ++x) {
            const std::int32_t v = g.v[static_cast<std::size_t>(y * g.w + x)];
            std::int64_t twice = 0;
            std::int64_t n = 0;
            for (std::int32_t yy = y - r; yy <= y + r; ++yy) {
                for (std::int32_t xx = x - r; xx <= x + r; ++xx) {
                    if (yy < 0 || xx < 0 || yy >= g.h || xx >= g.w) continue;
                    const std::int32_t u = g.v[static_cast<std::size_t>(yy * g.w + xx)];
                    if (u <= fillMax) continue;
                    twice += u < v ? 2 : (u == v ? 1 : 0);
                    ++n;
                }
            }
            const std::int64_t rank = v <= fillMax ? 0 : std::min<std::int64_t>(255, 256 * twice / (2 * n));
            out[static_cast<std::size_t>(y * g.w + x)] = static_cast<std::uint8_t>(rank);
        }
    }
    return out;
}

std::vector<std::uint8_t> localRankOf(const Grey& g, std::int32_t r, std::int32_t fillMax) {
    std::vector<std::uint8_t> out(g.v.size());
    std::vector<std::uint16_t> counts(kRankCounts);
    localRank(g.view(), ImageView<std::uint8_t>(out.data(), g.w, g.h), r, fillMax,
              Span<std::uint16_t>(counts.data(), counts.size()));
    return out;
}

TEST(LocalRank, EqualsTheDefinitionComputedDirectly) {
    struct Case {
        std::int32_t w, h, r, levels, fill;
    };
    // Odd sizes, windows wider than the image, few levels (many ties), fill.
    const Case cases[] = {{37, 23, 1, 256, -1}, {37, 23, 3, 256, -1}, {37, 23, 12, 256, -1},
                          {5, 64, 12, 256, -1}, {64, 3, 2, 4, -1},    {31, 29, 4, 256, 40},
                          {20, 20, 63, 16, -1}};
    std::uint64_t seed = 11U;
    for (const Case& k : cases) {
        const Grey g = randomImage(k.w, k.h, seed++, k.levels);
        EXPECT_EQ(localRankOf(g, k.r, k.fill), rankDirectly(g, k.r, k.fill))
            << k.w << "x" << k.h << " radius " << k.r << " fill " << k.fill;
    }
}

TEST(LocalRank, AFlatImageIsMidGreyAndAnOrderKeepingResponseDropsOut) {
    const Grey flat{16, 16, std::vector<std::uint8_t>(256, 77)};
    for (const std::uint8_t v : localRankOf(flat, 5, -1)) {
        ASSERT_EQ(v, 128);
    }
    // A second sensor with another, strictly increasing response: the same ranks.
    const Grey g = randomImage(40, 30, 5U, 128);
    // The response as a table: GCC 12.2 miscompiles the same map written as a loop of
    // (p * p) / 256 over bytes at -O3 on ppc750, leon3, riscv64 and armhf (docs/build.md).
    std::uint8_t response[128];
    for (std::int32_t v = 0; v < 128; ++v) {
        response[v] = static_cast<std::uint8_t>(20 + v + (v * v) / 256);  // 20..210, strictly increasing
    }
    Grey other = g;
    for (std::size_t i = 0; i < other.v.size(); ++i) {
        other.v[i] = response[g.v[i]];
    }
    EXPECT_NE(g.v, other.v);
    EXPECT_EQ(localRankOf(g, 6, -1), localRankOf(other, 6, -1));
}

TEST(Equalise, InPlaceEqualsOutOfPlaceAndSpreadsTheLevels) {
    const Grey g = randomImage(33, 17, 9U, 40);  // levels 0..39 only
    std::vector<std::uint8_t> out(g.v.size());
    equalise(g.view(), ImageView<std::uint8_t>(out.data(), g.w, g.h), -1);
    Grey same = g;
    equalise(same.view(), ImageView<std::uint8_t>(same.v.data(), g.w, g.h), -1);
    EXPECT_EQ(same.v, out);
    std::uint8_t lo = 255;
    std::uint8_t hi = 0;
    for (const std::uint8_t v : out) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    EXPECT_EQ(lo, 0);
    EXPECT_EQ(hi, 255);
}

}  // namespace
}  // namespace vtm::entropy::detail
