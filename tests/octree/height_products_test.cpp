// vtm_octree_tests (height products): the multi-resolution height maps of the analytic
// scene against its truth per bin (largest z, mean, count, sources, which level filled
// the bin), the fine bins against a HeightMap of the same points, no heap, the same bits
// twice, the work bound, configuration and workspace.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "octree_scene.hpp"
#include "vtm/octree/height_products.hpp"

namespace vtm::octree {
namespace {

using terrain::Reducer;

struct Scene {
    std::vector<std::byte> tree_pool;
    Arena tree_arena;
    Octree tree;
    std::vector<std::byte> product_pool;
    Arena product_arena;
    HeightProducts products;
    Scene(const ProductConfig& pc, bool insert)
        : tree_pool(Octree::workspaceBytes(test::sceneConfig())),
          tree_arena(tree_pool.data(), tree_pool.size()),
          product_pool(HeightProducts::workspaceBytes(pc, test::sceneConfig())),
          product_arena(product_pool.data(), product_pool.size()) {
        EXPECT_TRUE(tree.init(test::sceneConfig(), tree_arena).isOk());
        EXPECT_TRUE(products.init(pc, test::sceneConfig(), product_arena).isOk());
        if (insert) {
            const std::vector<Sample> s = test::sceneSamples();
            EXPECT_TRUE(tree.insert(Span<const Sample>(s.data(), s.size())).isOk());
        }
    }
};

ProductConfig threeLevels(Reducer reducer) {
    ProductConfig c;
    c.levels = {{3, 6, 8, 0, 0, 0}};  // 8 m, 1 m and 0.25 m bins
    c.count = 3;
    c.reducer = reducer;
    return c;
}

// What a bin must hold, worked out from the scene's definition (octree_scene.hpp), not
// from the module: the samples at least as fine as the bin, or else the finest coarser
// source above it.
struct Expected {
    std::int32_t count = 0;
    double highest = -1e30;
    double sum = 0.0;
    unsigned sources = 0U;
    std::int32_t level = kNoLevel;
    bool rover = false;  // the rover's part is the surface sampled densely (tolerance below)
};

void addValue(Expected& e, double v, unsigned source) {
    ++e.count;
    e.highest = std::max(e.highest, v);
    e.sum += v;
    e.sources |= 1U << source;
}

Expected expectedBin(std::int32_t level, std::int32_t col, std::int32_t row) {
    const double c = test::kSide / (1 << level);
    const double n0 = test::kNorth - (row + 1) * c, n1 = n0 + c;
    const double e0 = test::kWest + col * c, e1 = e0 + c;
    Expected e;
    // Rover: its part of the bin, every 1/32 m (4 points per rover sample spacing a side).
    const double rn0 = std::max(n0, -test::kRoverHalf), rn1 = std::min(n1, test::kRoverHalf);
    const double re0 = std::max(e0, -test::kRoverHalf), re1 = std::min(e1, test::kRoverHalf);
    if (rn0 < rn1 && re0 < re1) {
        const double step = 1.0 / 32.0;
        double top = -1e30, sum = 0.0;
        std::int64_t n = 0;
        for (double north = rn0 + step / 2; north < rn1; north += step) {
            for (double east = re0 + step / 2; east < re1; east += step) {
                const double h = test::surface(north, east);
                top = std::max(top, h);
                sum += h;
                ++n;
            }
        }
        const auto samples = static_cast<std::int32_t>(std::lround((rn1 - rn0) * (re1 - re0) / 0.015625));
        e.count += samples;
        e.highest = top;
        e.sum += sum / static_cast<double>(n) * samples;
        e.sources |= 1U;
        e.rover = true;
    }
    if (level <= 6) {  // orbital 1 m cells (level 6) inside the bin
        for (double north = n0 + 0.5; north < n1; north += 1.0) {
            for (double east = e0 + 0.5; east < std::min(e1, test::kOrbitalEastEnd); east += 1.0) {
                addValue(e, test::surface(north, east), 1U);
            }
        }
    }
    if (level <= 4) {  // descent 4 m cells (level 4) inside the bin
        for (double north = n0 + 2.0; north < n1; north += 4.0) {
            for (double east = e0 + 2.0; east < e1; east += 4.0) {
                addValue(e, test::surface(north, east), 2U);
            }
        }
    }
    if (e.count > 0) {
        e.level = level;
        return e;
    }
    const double south = test::kNorth - test::kSide;
    if (level > 6 && e0 < test::kOrbitalEastEnd) {  // the orbital 1 m cell above the bin
        addValue(e, test::surface(std::floor(n0) + 0.5, std::floor(e0) + 0.5), 1U);
        e.level = 6;
    } else if (level > 4) {  // the descent 4 m cell above it
        addValue(e, test::surface(south + 4.0 * std::floor((n0 - south) / 4.0) + 2.0,
                                  test::kWest + 4.0 * std::floor((e0 - test::kWest) / 4.0) + 2.0),
                 2U);
        e.level = 4;
    }
    return e;
}

TEST(HeightProducts, EachResolutionEqualsTheSceneTruthInEveryBin) {
    Scene mean(threeLevels(Reducer::kMean), true);
    Scene high(threeLevels(Reducer::kHighest), true);
    ASSERT_TRUE(mean.products.extract(mean.tree).isOk());
    ASSERT_TRUE(high.products.extract(high.tree).isOk());
    std::int32_t by_level[3][11] = {};
    for (std::int32_t p = 0; p < 3; ++p) {
        const std::int32_t level = mean.products.level(p);
        const terrain::HeightMap& m = mean.products.map(p);
        ASSERT_EQ(m.grid().cols, 1 << level);
        ASSERT_EQ(m.grid().cell_m, test::kSide / (1 << level));
        std::int32_t bad = 0;
        for (std::int32_t row = 0; row < m.grid().rows && bad < 10; ++row) {
            for (std::int32_t col = 0; col < m.grid().cols && bad < 10; ++col) {
                const Expected e = expectedBin(level, col, row);
                // Largest z: the rover's samples lie 0.125 m apart on slopes below 0.45,
                // so their top is within 0.05 m of the surface's; other sources' exactly.
                const double max_tol = e.rover ? 0.05 : 1e-5;
                const double mean_tol = e.rover ? 0.005 : 2e-5;
                const bool ok = m.count(col, row) == std::min(e.count, 65535) &&
                                std::fabs(m.highest(col, row) - e.highest) <= max_tol &&
                                std::fabs(m.elevation(col, row) - e.sum / e.count) <= mean_tol &&
                                mean.products.dataLevel(p, col, row) == e.level &&
                                mean.products.sources(p, col, row) == e.sources;
                if (!ok) {
                    ++bad;
                    ADD_FAILURE() << "level " << level << " bin (" << col << ", " << row << "): count "
                                  << m.count(col, row) << " vs " << e.count << ", highest " << m.highest(col, row)
                                  << " vs " << e.highest << ", mean " << m.elevation(col, row) << " vs "
                                  << e.sum / e.count << ", data level " << int(mean.products.dataLevel(p, col, row))
                                  << " vs " << e.level << ", sources " << mean.products.sources(p, col, row)
                                  << " vs " << e.sources;
                }
                ++by_level[p][std::min(e.level, 10)];
                // The kHighest set: its elevation is the largest z, the same bits.
                const float a = high.products.map(p).elevation(col, row), b = m.highest(col, row);
                EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
                EXPECT_EQ(high.products.map(p).spread(col, row), m.spread(col, row));
            }
        }
        EXPECT_EQ(bad, 0) << "level " << level;
    }
    // Every branch of the rule is exercised: own data at each level, the orbital filling
    // 0.25 m bins, the descent filling 1 m and 0.25 m bins beyond the orbital data.
    EXPECT_EQ(by_level[0][3], 64);
    EXPECT_EQ(by_level[1][6], 48 * 64);
    EXPECT_EQ(by_level[1][4], 16 * 64);
    EXPECT_EQ(by_level[2][8], 64 * 64);
    EXPECT_EQ(by_level[2][6], 192 * 256 - 64 * 64);
    EXPECT_EQ(by_level[2][4], 64 * 256);
    // The rock: its 0.25 m bins stand 0.6 m above the bins beside them.
    const terrain::HeightMap& fine = mean.products.map(2);
    const std::int32_t rock_col = static_cast<std::int32_t>((-3.5 - test::kWest) / 0.25);
    const std::int32_t rock_row = static_cast<std::int32_t>((test::kNorth - 2.5) / 0.25);
    EXPECT_GT(fine.highest(rock_col, rock_row) - fine.highest(rock_col - 4, rock_row), 0.5F);
}

TEST(HeightProducts, FineBinsEqualAHeightMapOfTheSamePointsBitForBit) {
    // Rover samples only: at 0.25 m every bin is made of its own points, so the product must
    // equal HeightMap::add of the same site points (highest, lowest, count) bit for bit.
    ProductConfig pc = threeLevels(Reducer::kHighest);
    Scene s(pc, false);
    const std::vector<Sample> all = test::sceneSamples();
    std::vector<Sample> rover;
    for (const Sample& x : all) {
        if (x.source == 0U) {
            rover.push_back(x);
        }
    }
    ASSERT_TRUE(s.tree.insert(Span<const Sample>(rover.data(), rover.size())).isOk());
    ASSERT_TRUE(s.products.extract(s.tree).isOk());
    const terrain::HeightMap& product = s.products.map(2);
    terrain::HeightMapConfig mc{product.grid(), Reducer::kHighest};
    std::vector<std::byte> pool(terrain::HeightMap::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    terrain::HeightMap direct;
    ASSERT_TRUE(direct.init(mc, arena).isOk());
    for (const Sample& x : rover) {
        ASSERT_TRUE(direct.add(x.site_m).isOk());
    }
    std::int32_t filled = 0, mismatches = 0;
    for (std::int32_t row = 0; row < mc.grid.rows; ++row) {
        for (std::int32_t col = 0; col < mc.grid.cols; ++col) {
            const float a = product.highest(col, row), b = direct.highest(col, row);
            const float c = product.lowest(col, row), d = direct.lowest(col, row);
            mismatches += (std::memcmp(&a, &b, sizeof a) != 0 || std::memcmp(&c, &d, sizeof c) != 0 ||
                           product.count(col, row) != direct.count(col, row))
                              ? 1
                              : 0;
            filled += direct.count(col, row) > 0 ? 1 : 0;
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(filled, 64 * 64);
}

TEST(HeightProducts, ExtractionTouchesNoHeapRepeatsBitForBitAndStaysWithinItsBound) {
    Scene s(threeLevels(Reducer::kMean), false);
    const std::vector<Sample> samples = test::sceneSamples();
    std::vector<float> first;
    for (int run = 0; run < 2; ++run) {
        s.tree.clear();
        vtm::test::NoHeapScope guard;
        ASSERT_TRUE(s.tree.insert(Span<const Sample>(samples.data(), samples.size())).isOk());
        ASSERT_TRUE(s.products.extract(s.tree).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
        std::vector<float> bits;
        for (std::int32_t p = 0; p < s.products.count(); ++p) {
            const terrain::HeightMap& m = s.products.map(p);
            for (std::int32_t row = 0; row < m.grid().rows; ++row) {
                for (std::int32_t col = 0; col < m.grid().cols; ++col) {
                    bits.push_back(m.highest(col, row));
                    bits.push_back(m.elevation(col, row));
                    bits.push_back(static_cast<float>(m.count(col, row)));
                }
            }
        }
        if (run == 0) {
            first = bits;
        } else {
            ASSERT_EQ(bits.size(), first.size());
            EXPECT_EQ(std::memcmp(bits.data(), first.data(), bits.size() * sizeof(float)), 0);
        }
    }
    // The documented bound: per product of level B, at most B + 1 sweeps of the pool and
    // 4^(B - l) bin writes per coarse node of level l.
    std::int64_t visits = 0, coarse = 0;
    for (std::int32_t p = 0; p < s.products.count(); ++p) {
        const std::int32_t b = s.products.level(p);
        visits += static_cast<std::int64_t>(b + 1) * s.tree.nodeCount();
        for (std::uint32_t i = 0; i < s.tree.nodeCount(); ++i) {
            const OctreeNode& n = s.tree.node(i);
            if (n.count > 0U && n.level < b) {
                coarse += std::int64_t{1} << (2 * (b - n.level));
            }
        }
    }
    EXPECT_LE(s.products.stats().node_visits, visits);
    EXPECT_LE(s.products.stats().coarse_writes, coarse);
    EXPECT_GT(s.products.stats().coarse_writes, 0);
    EXPECT_GT(s.products.stats().fine_writes, 0);
}

TEST(HeightProducts, BadConfigsNameTheFieldAndTheWorkspaceFormulaFitsExactly) {
    const OctreeConfig oc = test::sceneConfig();
    struct Bad {
        ProductConfig config;
        const char* field;
    };
    std::vector<Bad> bad;
    ProductConfig c = threeLevels(Reducer::kHighest);
    c.count = 0;
    bad.push_back({c, "products.count"});
    c.count = 7;
    bad.push_back({c, "products.count"});
    c = threeLevels(Reducer::kHighest);
    c.levels = {{3, 3, 8, 0, 0, 0}};
    bad.push_back({c, "products.levels"});
    c.levels = {{3, 6, 11, 0, 0, 0}};  // deeper than max_depth 10
    bad.push_back({c, "products.levels"});
    c.levels = {{-1, 6, 8, 0, 0, 0}};
    bad.push_back({c, "products.levels"});
    c = threeLevels(static_cast<Reducer>(7));
    bad.push_back({c, "products.reducer"});
    for (const Bad& b : bad) {
        const Status s = b.config.validate(oc);
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << b.field;
        EXPECT_NE(std::string(s.reason()).find(b.field), std::string::npos) << s.reason();
        EXPECT_EQ(HeightProducts::workspaceBytes(b.config, oc), 0U);
    }
    OctreeConfig deep = oc;
    deep.max_depth = 16;
    c = threeLevels(Reducer::kHighest);
    c.levels = {{3, 6, 13, 0, 0, 0}};  // 8192 cells a side: beyond the height map's 4096
    EXPECT_EQ(c.validate(deep).code(), StatusCode::kInvalidConfig);
    OctreeConfig broken = oc;
    broken.side_m = -1.0;
    EXPECT_NE(std::string(threeLevels(Reducer::kHighest).validate(broken).reason()).find("octree.side_m"),
              std::string::npos);
    // The formula holds wherever the pool starts; a pool short by a byte (aligned) fails.
    c = threeLevels(Reducer::kMean);
    c.levels = {{0, 2, 5, 0, 0, 0}};
    const std::size_t bytes = HeightProducts::workspaceBytes(c, oc);
    std::size_t unpadded = 0;
    for (const std::int32_t l : {0, 2, 5}) {
        const std::size_t n = std::size_t{1} << (2 * l);
        unpadded += n * (3 * sizeof(float) + sizeof(std::uint16_t)) + n + 2 * n;
    }
    EXPECT_EQ(bytes, unpadded + 3U * 6U * (Arena::kDefaultAlignment - 1U));  // 6 blocks per product
    std::vector<std::byte> pool(bytes + 64U);
    for (std::size_t offset = 0; offset < Arena::kDefaultAlignment; ++offset) {
        Arena arena(pool.data() + offset, bytes);
        HeightProducts hp;
        EXPECT_TRUE(hp.init(c, oc, arena).isOk()) << offset;
    }
    // Arena blocks need padding between them unless sizes are multiples of 16: give the
    // aligned pool exactly the unpadded sum rounded per block, less one byte.
    std::size_t tight = 0;
    for (const std::int32_t l : {0, 2, 5}) {
        const std::size_t n = std::size_t{1} << (2 * l);
        for (const std::size_t b : {4 * n, 4 * n, 4 * n, 2 * n, n, 2 * n}) {
            tight += (b + 15U) / 16U * 16U;
        }
    }
    HeightProducts hp;
    Arena small(reinterpret_cast<std::byte*>((reinterpret_cast<std::uintptr_t>(pool.data()) + 15U) & ~std::uintptr_t{15U}),
                tight - 1U);
    EXPECT_EQ(hp.init(c, oc, small).code(), StatusCode::kOutOfMemory);
    // Extraction before init, and from a tree of another cube.
    Scene s(threeLevels(Reducer::kHighest), false);
    HeightProducts never;
    EXPECT_EQ(never.extract(s.tree).code(), StatusCode::kNotInitialized);
    Octree uninitialised;
    EXPECT_EQ(s.products.extract(uninitialised).code(), StatusCode::kNotInitialized);
    OctreeConfig other = test::sceneConfig();
    other.max_nodes = 100;
    other.top_z_m += 1.0;
    std::vector<std::byte> other_pool(Octree::workspaceBytes(other));
    Arena other_arena(other_pool.data(), other_pool.size());
    Octree moved;
    ASSERT_TRUE(moved.init(other, other_arena).isOk());
    EXPECT_EQ(s.products.extract(moved).code(), StatusCode::kSizeMismatch);
}

}  // namespace
}  // namespace vtm::octree
