// The verification steps (verify.hpp) on constructed matches: a smooth parallax field of a
// rover stereo pair (disparity growing towards the image bottom, a slight vertical term)
// with wrong matches injected; grid thinning against a count by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

#include "vtm/tiepoints/verify.hpp"

namespace vtm::tiepoints {
namespace {

using features::Match;

// Parallax of a tilted ground seen by a horizontal rig: d = -(10 + 0.12 y + 1e-4 x y), a
// small vertical component 0.002 x; NCC scores vary with position.
std::vector<Match> smoothField() {
    std::vector<Match> m;
    for (std::int32_t gy = 0; gy < 12; ++gy) {
        for (std::int32_t gx = 0; gx < 12; ++gx) {
            Match a;
            const double x = 10.0 + 20.0 * gx + 3.0 * ((gy * 7) % 5);
            const double y = 10.0 + 20.0 * gy + 2.0 * ((gx * 3) % 4);
            a.pixel_a = Vec2(x, y);
            a.pixel_b = a.pixel_a + Vec2(-(10.0 + 0.12 * y + 1e-4 * x * y), 0.002 * x);
            a.score = 0.8F + 0.01F * static_cast<float>((gx * 5 + gy * 3) % 17);
            a.feature_index = static_cast<std::int32_t>(m.size());
            m.push_back(a);
        }
    }
    return m;
}

TEST(Parallax, KeepsASmoothFieldAndRejectsInjectedWrongMatches) {
    std::vector<Match> m = smoothField();
    // Wrong matches: a 3 px slip along the epipolar line, a 1.6 px one, a 2 px vertical
    // one, and two adjacent wrong ones (each other's neighbours).
    const std::size_t wrong[] = {26U, 67U, 100U, 89U, 90U};
    m[26].pixel_b.x() += 3.0;
    m[67].pixel_b.x() -= 1.6;
    m[100].pixel_b.y() += 2.0;
    m[89].pixel_b.x() += 4.0;
    m[90].pixel_b.x() += 4.5;
    std::vector<std::uint8_t> keep(m.size(), 0U);
    ParallaxConfig config;  // 8 neighbours, tolerance 1 px
    ParallaxStats stats;
    ASSERT_TRUE(checkParallax(Span<const Match>(m.data(), m.size()), config,
                              Span<std::uint8_t>(keep.data(), keep.size()), &stats)
                    .isOk());
    for (std::size_t k = 0; k < m.size(); ++k) {
        const bool is_wrong = std::find(std::begin(wrong), std::end(wrong), k) != std::end(wrong);
        EXPECT_EQ(keep[k], is_wrong ? 0U : 1U) << "match " << k;
    }
    EXPECT_EQ(stats.inconsistent, 5);
    EXPECT_EQ(stats.consistent, static_cast<std::int32_t>(m.size()) - 5);
}

TEST(Parallax, IsolatedMatchesCannotBeChecked) {
    std::vector<Match> m = smoothField();
    m.resize(3);
    std::vector<std::uint8_t> keep(m.size(), 1U);
    ParallaxStats stats;
    ASSERT_TRUE(checkParallax(Span<const Match>(m.data(), m.size()), ParallaxConfig{},
                              Span<std::uint8_t>(keep.data(), keep.size()), &stats)
                    .isOk());
    EXPECT_EQ(stats.isolated, 3);
    EXPECT_EQ(keep[0] + keep[1] + keep[2], 0);
}

TEST(Parallax, Refusals) {
    std::vector<Match> m = smoothField();
    std::vector<std::uint8_t> keep(3U, 0U);
    const Status s = checkParallax(Span<const Match>(m.data(), m.size()), ParallaxConfig{},
                                   Span<std::uint8_t>(keep.data(), keep.size()));
    EXPECT_EQ(s.code(), StatusCode::kSizeMismatch);
    ParallaxConfig bad;
    bad.tolerance_px = 0.0;
    EXPECT_NE(std::string(bad.validate().reason()).find("tolerance_px"), std::string::npos);
}

// 4 x 4 cells over 240 x 240: each non-empty cell keeps exactly its highest score.
TEST(Thinning, OnePerCellTheBestScore) {
    const std::vector<Match> m = smoothField();
    std::vector<std::uint8_t> keep(m.size(), 1U);
    keep[5] = 0U;  // a match already rejected stays rejected
    ThinningConfig grid;
    grid.cols = 4;
    grid.rows = 4;
    std::int32_t kept = 0;
    ASSERT_TRUE(thinByGrid(Span<const Match>(m.data(), m.size()), grid, 240, 240,
                           Span<std::uint8_t>(keep.data(), keep.size()), kept)
                    .isOk());
    EXPECT_EQ(kept, 16);
    std::vector<float> best(16U, -2.0F);
    std::vector<std::int32_t> count(16U, 0);
    for (std::size_t k = 0; k < m.size(); ++k) {
        const auto cell = static_cast<std::size_t>(static_cast<std::int32_t>((m[k].pixel_a.y() + 0.5) / 60.0) * 4 +
                                                   static_cast<std::int32_t>((m[k].pixel_a.x() + 0.5) / 60.0));
        if (k != 5U) {
            best[cell] = std::max(best[cell], m[k].score);
        }
        if (keep[k] != 0U) {
            ++count[cell];
            EXPECT_EQ(m[k].score, best[cell] > m[k].score ? best[cell] : m[k].score);
        }
    }
    for (std::size_t c = 0; c < 16U; ++c) {
        EXPECT_EQ(count[c], 1) << "cell " << c;
    }
    for (std::size_t k = 0; k < m.size(); ++k) {
        if (keep[k] != 0U) {
            const auto cell = static_cast<std::size_t>(static_cast<std::int32_t>((m[k].pixel_a.y() + 0.5) / 60.0) * 4 +
                                                       static_cast<std::int32_t>((m[k].pixel_a.x() + 0.5) / 60.0));
            EXPECT_EQ(m[k].score, best[cell]);
        }
    }
    EXPECT_EQ(keep[5], 0U);
}

}  // namespace
}  // namespace vtm::tiepoints
