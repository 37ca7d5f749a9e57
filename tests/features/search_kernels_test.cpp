// The template matcher's fast search kernels against their plain forms in the same run:
// PolylineScan against nearestVertex / withinPolyline (and its span against every position
// within), the slid column sums and the products-only pass against the one-pass window
// sums, and the NCC pruning (nccIfAbove) against the score it skips. Both must give the same answers bit for bit, or the matches
// (and every product downstream) would change.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "polyline.hpp"
#include "template_ncc.hpp"
#include "vtm/core/random.hpp"

namespace {

using vtm::Random;
using vtm::Vec2;
using namespace vtm::features::detail;

// A polyline like a ray's image: samples along a line through the region, slightly bent,
// some vertices repeated (a ray sample can project twice to the same pixel).
std::vector<Vec2> rayLike(Random& rng, std::int32_t n) {
    const Vec2 start(rng.uniform01() * 200.0, rng.uniform01() * 200.0);
    Vec2 dir(rng.uniform01() * 2.0 - 1.0, rng.uniform01() * 2.0 - 1.0);
    // Axis-parallel lines and a single repeated point too: ties in x, in y, in distance.
    const double shape = rng.uniform01();
    if (shape < 0.15) {
        dir = Vec2(1.0, 0.0);
    } else if (shape < 0.3) {
        dir = Vec2(0.0, 1.0);
    } else if (shape < 0.35) {
        dir = Vec2(0.0, 0.0);
    }
    std::vector<Vec2> poly;
    for (std::int32_t i = 0; i < n; ++i) {
        const double t = 6.0 * i;
        const double bend = shape < 0.35 ? 0.0 : 0.002 * t * t;
        poly.push_back(start + t * dir + Vec2(-dir.y(), dir.x()) * bend);
        if (rng.uniform01() < 0.1 && i + 1 < n) {
            poly.push_back(poly.back());
            ++i;
        }
    }
    return poly;
}

TEST(PolylineScan, GivesTheSameVertexAndMembershipAsThePlainFunctions) {
    Random rng(2026);
    std::int64_t within = 0, tested = 0, rows = 0;
    double spans = 0.0;
    for (std::int32_t trial = 0; trial < 80; ++trial) {
        const std::int32_t n = 1 + static_cast<std::int32_t>(rng.uniformInt(0, kMaxPolylineVertices - 1));
        const std::vector<Vec2> poly = rayLike(rng, n);
        const double margin = 2.0 + rng.uniform01() * 40.0;
        PolylineScan scan;
        scan.set(poly.data(), static_cast<std::int32_t>(poly.size()), margin * margin);
        for (std::int32_t y = -20; y < 240; y += 3) {
            scan.row(static_cast<double>(y));
            for (std::int32_t x = -20; x < 240; x += 2) {
                const Vec2 p(x, y);
                const auto m = static_cast<std::int32_t>(poly.size());
                const bool w = withinPolyline(p, poly.data(), m, margin * margin);
                ASSERT_EQ(scan.within(p.x()), w) << "trial " << trial << " at " << x << ", " << y;
                ASSERT_EQ(scan.nearest(p.x()), nearestVertex(p, poly.data(), m))
                    << "trial " << trial << " at " << x << ", " << y;
                within += w ? 1 : 0;
                ++tested;
            }
            // span(): every position within lies inside it (it is what the search visits).
            double lo = 0.0, hi = 0.0;
            scan.span(lo, hi);
            for (std::int32_t x = -60; x < 280; ++x) {
                if (withinPolyline(Vec2(x, y), poly.data(), static_cast<std::int32_t>(poly.size()), margin * margin)) {
                    ASSERT_TRUE(x >= lo && x <= hi) << "trial " << trial << " at " << x << ", " << y;
                }
            }
            spans += (hi >= lo) ? hi - lo : 0.0;
            ++rows;
        }
    }
    // span() is narrower than the scanned rows on average: it skips positions.
    EXPECT_LT(spans / static_cast<double>(rows), 200.0);
    // Both answers were exercised.
    EXPECT_GT(within, tested / 20);
    EXPECT_LT(within, tested - tested / 20);
}

// The rover's rays: long, nearly horizontal polylines (vertices a few pixels apart in x),
// asked at every position of a row and at the points where two vertices are equally far
// (and a rounding step either side), where the row's envelope hands over to the walk.
TEST(PolylineScan, TheEnvelopeGivesTheSameVertexAsThePlainFunctionEverywhereAlongARow) {
    Random rng(7);
    std::int64_t asked = 0;
    for (std::int32_t trial = 0; trial < 40; ++trial) {
        const auto n = static_cast<std::int32_t>(rng.uniformInt(2, kMaxPolylineVertices));
        const Vec2 start(rng.uniform01() * 300.0, rng.uniform01() * 300.0);
        const double dx = 0.5 + rng.uniform01() * 8.0;
        const double slope = (rng.uniform01() * 2.0 - 1.0) * (trial % 3 == 0 ? 3.0 : 0.3);
        std::vector<Vec2> poly;
        for (std::int32_t i = 0; i < n; ++i) {
            poly.emplace_back(start.x() + dx * i + 0.1 * rng.uniform01(), start.y() + slope * dx * i + 0.5 * rng.uniform01());
        }
        const double margin = 3.0 + rng.uniform01() * 30.0;
        PolylineScan scan;
        scan.set(poly.data(), n, margin * margin);
        for (std::int32_t y = static_cast<std::int32_t>(start.y()) - 40; y < static_cast<std::int32_t>(start.y()) + 40; ++y) {
            scan.row(static_cast<double>(y));
            std::vector<double> xs;
            for (std::int32_t x = static_cast<std::int32_t>(start.x()) - 40; x < static_cast<std::int32_t>(start.x() + dx * n) + 40; ++x) {
                xs.push_back(x);
            }
            // The envelope's ends lie between samples near each other in x (the samples are
            // in increasing x): each sample with its next three.
            for (std::int32_t i = 0; i < n; ++i) {
                for (std::int32_t j = i + 1; j < std::min(n, i + 4); ++j) {
                    const double dyi = y - poly[static_cast<std::size_t>(i)].y(), dyj = y - poly[static_cast<std::size_t>(j)].y();
                    const double xi = poly[static_cast<std::size_t>(i)].x(), xj = poly[static_cast<std::size_t>(j)].x();
                    const double meet = 0.5 * (xi + xj) + (dyj * dyj - dyi * dyi) / (2.0 * (xj - xi));
                    for (const double d : {0.0, 1e-12, -1e-12, 1e-6, -1e-6, 1e-3, -1e-3}) {
                        xs.push_back(meet + d * (1.0 + std::fabs(meet)));
                    }
                }
            }
            std::sort(xs.begin(), xs.end());  // in increasing x, as the search asks
            for (const double x : xs) {
                ASSERT_EQ(scan.nearest(x), nearestVertex(Vec2(x, y), poly.data(), n))
                    << "trial " << trial << " at " << x << ", " << y;
                ++asked;
            }
        }
    }
    EXPECT_GT(asked, 50000);
}

TEST(TemplateNcc, PruningNeverSkipsAScoreAboveTheBestAndTheKernelsAgree) {
    Random rng(7);
    constexpr std::int32_t kSize = 64;
    std::vector<std::uint8_t> img(kSize * kSize);
    for (auto& v : img) {
        v = static_cast<std::uint8_t>(rng.uniformInt(0, 255));
    }
    const vtm::ImageView<const std::uint8_t> to(img.data(), kSize, kSize, kSize);
    std::int64_t pruned = 0, missed = 0;
    for (const std::int32_t half : {1, 5, 7, 8, 15}) {
        const std::int32_t side = 2 * half + 1;
        std::vector<std::uint16_t> values(static_cast<std::size_t>(side * side));
        std::vector<std::uint16_t> values2(values.size());
        const Pos at{kSize / 2, kSize / 2};
        for (std::int32_t i = 0; i < side * side; ++i) {
            // A template like a shifted copy of the window plus noise, in 1/256 levels.
            const std::int32_t dy = i / side - half, dx = i % side - half;
            const std::int32_t v = to.row(at.y + dy)[at.x + dx] + static_cast<std::int32_t>(rng.uniformInt(-40, 40));
            values[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>((v < 0 ? 0 : (v > 255 ? 255 : v)) * 256);
            values2[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(rng.uniformInt(0, 255 * 256));
        }
        Template t{values.data()}, u{values2.data()};
        setTemplateSums(t, half);
        setTemplateSums(u, half);
        const Template* both[2] = {&t, &u};
        // Column sums over the whole width, set on the first row and slid down after.
        std::vector<std::uint32_t> col(kSize), col_sq(kSize);
        ColumnSums columns{col.data(), col_sq.data(), 0, kSize - 1, 0};
        for (std::int32_t y = half; y < kSize - half; ++y) {
            if (y == half) {
                setColumnSums(columns, to, y, half);
            } else {
                slideColumnSums(columns, to, half);
            }
            // Mostly consecutive positions (the window slid along the row), some skipped
            // (summed anew).
            for (std::int32_t x = half; x < kSize - half; x += (rng.uniform01() < 0.8 ? 1 : 2)) {
                double cross[2] = {};
                const WindowStats w = windowAndCrossSums(both, 2, to, Pos{x, y}, half, cross);
                // The window's sums from the slid columns and the products alone: the same bits.
                const WindowStats wc = windowFromColumns(columns, x, half);
                ASSERT_EQ(wc.sum, w.sum);
                ASSERT_EQ(wc.var, w.var);
                double cross_only[2] = {};
                crossSums(both, 2, to, Pos{x, y}, half, cross_only);
                ASSERT_EQ(cross_only[0], cross[0]);
                ASSERT_EQ(cross_only[1], cross[1]);
                const double s = nccFromSums(t, w, cross[0], half);
                ASSERT_EQ(s, ncc(t, to, Pos{x, y}, half));  // the one- and two-template passes
                ASSERT_EQ(nccFromSums(u, w, cross[1], half), ncc(u, to, Pos{x, y}, half));
                for (const double best : {-0.5, 0.0, 0.1, 0.5, s, s * (1.0 - 1e-15), 0.99}) {
                    const double got = nccIfAbove(t, w, cross[0], half, best);
                    const bool may = got != kNotAbove;
                    if (s > best) {
                        ASSERT_TRUE(may) << "half " << half << " score " << s << " best " << best;
                    }
                    if (may) {
                        ASSERT_EQ(got, s);  // the score itself, bit for bit
                    }
                    pruned += may ? 0 : 1;
                    // Clearly below a best >= 0: the square root is not needed.
                    missed += (may && best >= 0.0 && s < best - 1e-6) ? 1 : 0;
                }
            }
        }
    }
    EXPECT_GT(pruned, 0);
    EXPECT_EQ(missed, 0);  // every score clearly below a best >= 0 is pruned
}


// The coarse search's float products (crossSumsFloatRun: fused multiply-adds on ppc750,
// aarch64 and riscv64, a product and a sum elsewhere) against the integer pass at every
// position of each run: equal as doubles, for windows 3..31, one and two templates, runs
// of 1..4, on random content and on the largest values (every pixel 255, every template
// value 255 * 256: the sums' largest magnitudes, 1.6e10 at 31 x 31).
TEST(TemplateNcc, FloatRunsGiveTheIntegerProductsBitForBit) {
    Random rng(11);
    constexpr std::int32_t kSize = 48;
    std::vector<std::uint8_t> img(kSize * kSize);
    std::vector<float> img_f(img.size());
    std::int64_t compared = 0;
    for (const bool extreme : {false, true}) {
        for (auto& v : img) {
            v = extreme ? std::uint8_t{255} : static_cast<std::uint8_t>(rng.uniformInt(0, 255));
        }
        const vtm::ImageView<const std::uint8_t> to(img.data(), kSize, kSize, kSize);
        toFloats(to, img_f.data());
        const vtm::ImageView<const float> to_f(img_f.data(), kSize, kSize, kSize);
        for (std::int32_t y = 0; y < kSize; ++y) {
            for (std::int32_t x = 0; x < kSize; ++x) {
                ASSERT_EQ(to_f.row(y)[x], static_cast<float>(to.row(y)[x]));
            }
        }
        for (const std::int32_t half : {1, 5, 7, 8, 15}) {
            const std::int32_t side = 2 * half + 1;
            const auto n = static_cast<std::size_t>(side * side);
            std::vector<std::uint16_t> v0(n), v1(n);
            std::vector<float> f0(n), f1(n);
            for (std::size_t i = 0; i < n; ++i) {
                v0[i] = extreme ? std::uint16_t{255 * 256} : static_cast<std::uint16_t>(rng.uniformInt(0, 255 * 256));
                v1[i] = extreme ? std::uint16_t{255 * 256} : static_cast<std::uint16_t>(rng.uniformInt(0, 255 * 256));
            }
            toFloats(v0.data(), static_cast<std::int32_t>(n), f0.data());
            toFloats(v1.data(), static_cast<std::int32_t>(n), f1.data());
            Template t{v0.data()}, u{v1.data()};
            const Template* both[2] = {&t, &u};
            const float* both_f[2] = {f0.data(), f1.data()};
            for (std::int32_t trial = 0; trial < 40; ++trial) {
                const std::int32_t run = static_cast<std::int32_t>(rng.uniformInt(1, kMaxRun));
                const std::int32_t count = static_cast<std::int32_t>(rng.uniformInt(1, 2));
                const Pos b{static_cast<std::int32_t>(rng.uniformInt(half, kSize - half - run)),
                            static_cast<std::int32_t>(rng.uniformInt(half, kSize - half - 1))};
                double runs[kMaxRun * 2] = {};
                crossSumsFloatRun(both_f, count, to_f, b, run, half, runs);
                for (std::int32_t k = 0; k < run; ++k) {
                    double cross[2] = {};
                    crossSums(both, count, to, Pos{b.x + k, b.y}, half, cross);
                    for (std::int32_t i = 0; i < count; ++i) {
                        ASSERT_EQ(runs[k * count + i], cross[i]) << "half " << half << " run " << run << " position " << k;
                        ++compared;
                    }
                }
            }
        }
    }
    EXPECT_GT(compared, 400);
}

}  // namespace
