// vtm_octree_tests (the tree): the level rule and the integer keys against hand-computed
// cells, the scene's samples at the levels their footprints ask for, node statistics
// against a brute-force grouping of the samples, a full pool, bad samples, saturation,
// configuration and workspace, no heap.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "no_heap_guard.hpp"
#include "octree_scene.hpp"
#include "vtm/core/random.hpp"
#include "vtm/octree/octree.hpp"

namespace vtm::octree {
namespace {

struct Tree {
    std::vector<std::byte> pool;
    Arena arena;
    Octree tree;
    explicit Tree(const OctreeConfig& c) : pool(Octree::workspaceBytes(c)), arena(pool.data(), pool.size()) {
        EXPECT_TRUE(tree.init(c, arena).isOk());
    }
};

// An 8 m cube, 1 m finest cells: x (north) in [-4, 4), y (east) in [-4, 4), z in [-4, 4).
OctreeConfig smallCube(std::int32_t max_nodes = 1000) {
    OctreeConfig c;
    c.north_edge_m = 4.0;
    c.west_edge_m = -4.0;
    c.top_z_m = -4.0;
    c.side_m = 8.0;
    c.max_depth = 3;
    c.max_nodes = max_nodes;
    return c;
}

Sample at(double x, double y, double z, double footprint, std::uint8_t source = 0U) {
    Sample s;
    s.site_m = Vec3(x, y, z);
    s.footprint_m = footprint;
    s.source = source;
    return s;
}

// Walks the tree from the root with an explicit stack: every node reached exactly once,
// children one level down with the parent's keys doubled plus their octant bits.
// Returns the number of nodes reached (-1 on any inconsistency).
std::int64_t checkTree(const Octree& t) {
    std::vector<bool> seen(t.nodeCount(), false);
    std::vector<std::uint32_t> stack{0U};
    std::int64_t reached = 0;
    while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        if (i >= t.nodeCount() || seen[i]) {
            return -1;
        }
        seen[i] = true;
        ++reached;
        const OctreeNode& n = t.node(i);
        for (std::uint32_t o = 0; o < 8U; ++o) {
            const std::uint32_t c = n.child[o];
            if (c == kNoNode) {
                continue;
            }
            if (c >= t.nodeCount()) {
                return -1;
            }
            const OctreeNode& k = t.node(c);
            if (k.level != n.level + 1 || k.key_x != 2U * n.key_x + (o & 1U) ||
                k.key_y != 2U * n.key_y + ((o >> 1U) & 1U) || k.key_z != 2U * n.key_z + ((o >> 2U) & 1U)) {
                return -1;
            }
            stack.push_back(c);
        }
    }
    return reached;
}

TEST(Octree, KeysAndLevelsFollowTheDocumentedRule) {
    Tree f(smallCube());
    Octree& t = f.tree;
    // Deepest level whose cell (8, 4, 2, 1 m) is >= the footprint; 0 above the cube.
    EXPECT_EQ(t.levelFor(100.0), 0);
    EXPECT_EQ(t.levelFor(8.0), 0);
    EXPECT_EQ(t.levelFor(4.0001), 0);
    EXPECT_EQ(t.levelFor(4.0), 1);
    EXPECT_EQ(t.levelFor(1.5), 2);
    EXPECT_EQ(t.levelFor(1.0), 3);
    EXPECT_EQ(t.levelFor(0.01), 3);  // finer than the finest cell: the leaves
    EXPECT_EQ(t.levelFor(0.0), -1);
    EXPECT_EQ(t.cellSideM(2), 2.0);
    // North-east-top corner cell: x in [3, 4) -> key_x 7, y in [-4, -3) -> 0, z in [-4, -3) -> 0.
    ASSERT_TRUE(t.insert(at(3.5, -3.5, -3.9, 1.0, 3U)).isOk());
    EXPECT_EQ(t.nodeCount(), 4U);  // root and one node per level down to 3
    const OctreeNode* n = t.find(Vec3(3.01, -3.99, -3.5), 3);
    ASSERT_NE(n, nullptr);
    EXPECT_EQ(n->level, 3U);
    EXPECT_EQ(n->key_x, 7U);
    EXPECT_EQ(n->key_y, 0U);
    EXPECT_EQ(n->key_z, 0U);
    EXPECT_EQ(n->count, 1U);
    EXPECT_EQ(n->highest_m, 3.9F);  // elevation up = -z
    EXPECT_EQ(n->sources, 1U << 3U);
    // The closed faces (south, west, top) are inside, keys 0; the open ones are outside.
    ASSERT_TRUE(t.insert(at(-4.0, 3.999, 3.999, 1.0)).isOk());
    n = t.find(Vec3(-4.0, 3.5, 3.5), 3);
    ASSERT_NE(n, nullptr);
    EXPECT_EQ(n->key_x, 0U);
    EXPECT_EQ(n->key_y, 7U);
    EXPECT_EQ(n->key_z, 7U);
    EXPECT_EQ(t.nodeCount(), 7U);
    for (const Sample& s : {at(4.0, 0.0, 0.0, 1.0), at(0.0, 4.0, 0.0, 1.0), at(0.0, 0.0, 4.0, 1.0),
                            at(-4.0001, 0.0, 0.0, 1.0), at(0.0, -4.0001, 0.0, 1.0), at(0.0, 0.0, -4.0001, 1.0)}) {
        EXPECT_EQ(t.insert(s).code(), StatusCode::kInvalidArgument);
    }
    EXPECT_EQ(t.stats().refused_outside, 6);
    // A 2 m footprint stops at level 2: the existing ancestor takes it, nothing is created.
    ASSERT_TRUE(t.insert(at(3.5, -3.5, -3.0, 2.0)).isOk());
    EXPECT_EQ(t.nodeCount(), 7U);
    EXPECT_EQ(t.find(Vec3(3.5, -3.5, -3.9), 2)->count, 1U);
    EXPECT_EQ(t.find(Vec3(3.5, -3.5, -3.9), 3)->count, 1U);
    // A coarse sample (footprint above the cube) goes to the root.
    ASSERT_TRUE(t.insert(at(0.0, 0.0, 0.0, 50.0)).isOk());
    EXPECT_EQ(t.node(0).count, 1U);
    EXPECT_EQ(t.stats().inserted, 4);
    EXPECT_EQ(t.stats().inserted_at_level[0], 1);
    EXPECT_EQ(t.stats().inserted_at_level[2], 1);
    EXPECT_EQ(t.stats().inserted_at_level[3], 2);
    EXPECT_EQ(checkTree(t), 7);
}

TEST(Octree, SceneSamplesLandAtTheLevelTheirFootprintAsksForAndNoDeeper) {
    const std::vector<Sample> samples = test::sceneSamples();
    Tree f(test::sceneConfig());
    ASSERT_TRUE(f.tree.insert(Span<const Sample>(samples.data(), samples.size())).isOk());
    std::int64_t expected[kMaxDepth + 1] = {};
    for (const Sample& s : samples) {
        // The rule in logarithms: deepest l with 64 / 2^l >= footprint, within 0..10.
        const double l = std::floor(std::log2(test::kSide / s.footprint_m));
        const int level = static_cast<int>(std::max(0.0, std::min(10.0, l)));
        ++expected[level];
        const OctreeNode* n = f.tree.find(s.site_m, level);
        ASSERT_NE(n, nullptr);
        EXPECT_NE(n->count, 0U);
        EXPECT_NE(n->sources & (1U << s.source), 0U);
        // Orbital samples off the rover square and descent samples east of the orbital
        // data have nothing finer around them: no node may exist below their level.
        const bool alone = !test::inRover(s.site_m.x(), s.site_m.y()) &&
                           (s.source == 1U || s.site_m.y() >= test::kOrbitalEastEnd);
        if (alone && level < 10) {
            EXPECT_EQ(f.tree.find(s.site_m, level + 1), nullptr) << "a coarse sample stays near the root";
        }
    }
    EXPECT_GT(expected[9], 1000);   // both rover levels are exercised
    EXPECT_GT(expected[10], 1000);
    std::int64_t total = 0;
    for (int l = 0; l <= kMaxDepth; ++l) {
        EXPECT_EQ(f.tree.stats().inserted_at_level[l], expected[l]) << "level " << l;
    }
    for (std::uint32_t i = 0; i < f.tree.nodeCount(); ++i) {
        total += f.tree.node(i).count;
    }
    EXPECT_EQ(total, static_cast<std::int64_t>(samples.size()));
    EXPECT_EQ(checkTree(f.tree), static_cast<std::int64_t>(f.tree.nodeCount()));
}

TEST(Octree, NodeStatisticsEqualABruteForceGroupingOfTheSamples) {
    Random rng(25U);
    std::vector<Sample> samples(3000);
    for (Sample& s : samples) {
        const double x = -4.0 + 8.0 * rng.uniform01();
        const double y = -4.0 + 8.0 * rng.uniform01();
        const double z = -0.5 + 0.3 * rng.uniform01();  // a thin layer: several samples per node
        const double fp = 0.3 + 9.0 * rng.uniform01();
        const auto src = static_cast<std::uint8_t>(rng.uniform01() * 15.99);
        s = at(x, y, z, fp, src);
    }
    Tree f(smallCube());
    ASSERT_TRUE(f.tree.insert(Span<const Sample>(samples.data(), samples.size())).isOk());
    struct Truth {
        int count = 0;
        float hi = -1e30F, lo = 1e30F;
        double sum = 0.0;
        unsigned sources = 0U;
    };
    std::map<std::tuple<int, long, long, long>, Truth> truth;
    for (const Sample& s : samples) {
        const int level = s.footprint_m > 8.0 ? 0 : std::min(3, static_cast<int>(std::floor(std::log2(8.0 / s.footprint_m))));
        const double cell = 8.0 / std::pow(2.0, level);
        const auto key = std::make_tuple(level, std::lround(std::floor((s.site_m.x() + 4.0) / cell)),
                                         std::lround(std::floor((s.site_m.y() + 4.0) / cell)),
                                         std::lround(std::floor((s.site_m.z() + 4.0) / cell)));
        Truth& t = truth[key];
        const auto up = static_cast<float>(-s.site_m.z());
        ++t.count;
        t.hi = std::max(t.hi, up);
        t.lo = std::min(t.lo, up);
        t.sum += up;
        t.sources |= 1U << s.source;
    }
    std::size_t occupied = 0;
    for (std::uint32_t i = 0; i < f.tree.nodeCount(); ++i) {
        const OctreeNode& n = f.tree.node(i);
        if (n.count == 0U) {
            continue;
        }
        ++occupied;
        const auto it = truth.find(std::make_tuple(static_cast<int>(n.level), static_cast<long>(n.key_x),
                                                   static_cast<long>(n.key_y), static_cast<long>(n.key_z)));
        ASSERT_NE(it, truth.end());
        const NodeStats s = statsOf(n);
        EXPECT_EQ(s.count, it->second.count);
        EXPECT_EQ(s.highest_m, it->second.hi);
        EXPECT_EQ(s.lowest_m, it->second.lo);
        EXPECT_EQ(s.spread_m, it->second.hi - it->second.lo);
        EXPECT_NEAR(s.mean_m, it->second.sum / it->second.count, 1e-6);
        EXPECT_EQ(s.sources, it->second.sources);
    }
    EXPECT_EQ(occupied, truth.size());
    EXPECT_GT(truth.size(), 50U);
    const NodeStats empty = statsOf(OctreeNode{});
    EXPECT_TRUE(std::isnan(empty.highest_m) && std::isnan(empty.mean_m) && std::isnan(empty.spread_m));
}

TEST(Octree, AFullPoolRefusesCleanlyAndTheTreeStaysConsistentAndQueryable) {
    Tree f(smallCube(12));
    Octree& t = f.tree;
    ASSERT_TRUE(t.insert(at(-3.5, -3.5, -3.5, 1.0)).isOk());  // nodes 1..3
    ASSERT_TRUE(t.insert(at(3.5, 3.5, 3.5, 1.0)).isOk());     // 4..6
    ASSERT_TRUE(t.insert(at(3.5, -3.5, 3.5, 1.0)).isOk());    // 7..9
    ASSERT_TRUE(t.insert(at(3.5, -3.5, 2.5, 1.0)).isOk());    // 10 (shares levels 1-2): 11 nodes
    ASSERT_EQ(t.nodeCount(), 11U);
    const std::vector<OctreeNode> before(&t.node(0), &t.node(0) + t.nodeCount());
    // Needs three new nodes, one is left: refused, nothing created.
    vtm::test::NoHeapScope guard;
    const Status s = t.insert(at(-3.5, 3.5, -3.5, 1.0));
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_NE(std::strstr(s.reason(), "max_nodes"), nullptr) << s.reason();  // no std::string: the guard is on
    EXPECT_EQ(t.nodeCount(), 11U);
    EXPECT_EQ(std::memcmp(before.data(), &t.node(0), before.size() * sizeof(OctreeNode)), 0);
    EXPECT_EQ(t.stats().refused_pool_full, 1);
    // Samples into existing nodes, or needing exactly the one node left, still go in.
    EXPECT_TRUE(t.insert(at(-3.2, -3.2, -3.2, 1.0)).isOk());
    EXPECT_TRUE(t.insert(at(2.5, -3.5, 3.5, 1.0)).isOk());  // level-3 sibling under an existing level-2 node
    EXPECT_EQ(t.nodeCount(), 12U);
    EXPECT_EQ(t.insert(at(3.5, -2.5, 2.5, 1.0)).code(), StatusCode::kOutOfMemory);
    EXPECT_TRUE(t.insert(at(0.0, 0.0, 0.0, 5.0)).isOk());  // level 0: the root
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_EQ(checkTree(t), 12);
    EXPECT_EQ(t.find(Vec3(-3.5, -3.5, -3.5), 3)->count, 2U);
    EXPECT_EQ(t.find(Vec3(-3.5, 3.5, -3.5), 1), nullptr);
    EXPECT_EQ(t.stats().refused_pool_full, 2);
    EXPECT_EQ(t.stats().inserted, 7);
    t.clear();
    EXPECT_EQ(t.nodeCount(), 1U);
    EXPECT_TRUE(t.insert(at(-3.5, 3.5, -3.5, 1.0)).isOk());
}

TEST(Octree, BadSamplesAreRefusedNamingTheInputAndChangeNothing) {
    Octree never;
    EXPECT_EQ(never.insert(at(0.0, 0.0, 0.0, 1.0)).code(), StatusCode::kNotInitialized);
    Tree f(smallCube());
    Octree& t = f.tree;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    struct Case {
        Sample sample;
        const char* names;
    };
    const Case cases[] = {
        {at(nan, 0.0, 0.0, 1.0), "site_m"},       {at(0.0, inf, 0.0, 1.0), "site_m"},
        {at(0.0, 0.0, -inf, 1.0), "site_m"},      {at(0.0, 0.0, 0.0, 0.0), "footprint_m"},
        {at(0.0, 0.0, 0.0, -1.0), "footprint_m"}, {at(0.0, 0.0, 0.0, nan), "footprint_m"},
        {at(0.0, 0.0, 0.0, inf), "footprint_m"},  {at(0.0, 0.0, 0.0, 1.0, 16U), "source"},
        {at(9.0, 0.0, 0.0, 1.0), "outside"},
    };
    for (const Case& c : cases) {
        const Status s = t.insert(c.sample);
        EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << c.names;
        EXPECT_NE(std::string(s.reason()).find(c.names), std::string::npos) << s.reason();
    }
    EXPECT_EQ(t.nodeCount(), 1U);
    EXPECT_EQ(t.node(0).count, 0U);
    EXPECT_EQ(t.stats().refused_not_finite, 3);
    EXPECT_EQ(t.stats().refused_footprint, 4);
    EXPECT_EQ(t.stats().refused_source, 1);
    EXPECT_EQ(t.stats().refused_outside, 1);
    EXPECT_EQ(t.stats().inserted, 0);
    // A batch inserts the good samples and returns the first refusal.
    const Sample batch[] = {at(1.0, 1.0, 1.0, 1.0), at(0.0, 0.0, 0.0, -2.0), at(1.2, 1.2, 1.2, 1.0, 15U),
                            at(nan, 0.0, 0.0, 1.0)};
    const Status s = t.insert(Span<const Sample>(batch, 4U));
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::string(s.reason()).find("footprint_m"), std::string::npos) << s.reason();
    EXPECT_EQ(t.stats().inserted, 2);
    EXPECT_EQ(t.find(Vec3(1.0, 1.0, 1.0), 3)->sources, (1U << 0U) | (1U << 15U));
    EXPECT_EQ(t.find(Vec3(nan, 1.0, 1.0), 3), nullptr);
    EXPECT_EQ(t.find(Vec3(1.0, 1.0, 1.0), 4), nullptr);
}

TEST(Octree, ACountSaturatesAndKeepsTheMeanOfItsFirst65535Samples) {
    Tree f(smallCube());
    const int n = 65535 + 100;
    for (int i = 0; i < n; ++i) {
        // Elevations 1.0 (first 65535) then 3.0; one deeper and one higher at the end.
        const double up = (i < 65535) ? 1.0 : 3.0;
        ASSERT_TRUE(f.tree.insert(at(0.5, 0.5, -up, 10.0)).isOk());  // the root
    }
    ASSERT_TRUE(f.tree.insert(at(0.5, 0.5, -3.5, 10.0)).isOk());
    ASSERT_TRUE(f.tree.insert(at(-2.5, 3.5, 0.25, 10.0)).isOk());
    const NodeStats s = statsOf(*f.tree.find(Vec3(0.5, 0.5, -1.0), 0));
    EXPECT_EQ(s.count, 65535U);
    EXPECT_EQ(s.mean_m, 1.0F);
    EXPECT_EQ(s.highest_m, 3.5F);
    EXPECT_EQ(s.lowest_m, -0.25F);
    EXPECT_EQ(f.tree.stats().inserted, n + 2);
}

TEST(Octree, BadConfigsNameTheFieldAndTheWorkspaceFormulaFitsExactly) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    struct Bad {
        OctreeConfig config;
        const char* field;
    };
    std::vector<Bad> bad;
    OctreeConfig c = smallCube();
    c.north_edge_m = nan;
    bad.push_back({c, "octree.north_edge_m"});
    c = smallCube();
    c.west_edge_m = std::numeric_limits<double>::infinity();
    bad.push_back({c, "octree.west_edge_m"});
    c = smallCube();
    c.top_z_m = nan;
    bad.push_back({c, "octree.top_z_m"});
    for (const double side : {0.0, -1.0, 1.0e-4, 2.0e6, nan}) {
        c = smallCube();
        c.side_m = side;
        bad.push_back({c, "octree.side_m"});
    }
    for (const std::int32_t depth : {-1, 21}) {
        c = smallCube();
        c.max_depth = depth;
        bad.push_back({c, "octree.max_depth"});
    }
    for (const std::int32_t nodes : {0, kMaxNodes + 1}) {
        c = smallCube();
        c.max_nodes = nodes;
        bad.push_back({c, "octree.max_nodes"});
    }
    for (const Bad& b : bad) {
        const Status s = b.config.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << b.field;
        EXPECT_NE(std::string(s.reason()).find(b.field), std::string::npos) << s.reason();
        EXPECT_EQ(Octree::workspaceBytes(b.config), 0U);
        Octree t;
        std::byte pool[64];
        Arena arena(pool, sizeof pool);
        EXPECT_EQ(t.init(b.config, arena).code(), StatusCode::kInvalidConfig) << b.field;
    }
    // The formula holds wherever the pool starts; one node less does not.
    c = smallCube(100);
    const std::size_t bytes = Octree::workspaceBytes(c);
    EXPECT_EQ(bytes, 100U * sizeof(OctreeNode) + Arena::kDefaultAlignment - 1U);
    alignas(16) static std::byte pool[100U * sizeof(OctreeNode) + 64U];
    for (std::size_t offset = 0; offset < Arena::kDefaultAlignment; ++offset) {
        Arena arena(pool + offset, bytes);
        Octree t;
        EXPECT_TRUE(t.init(c, arena).isOk()) << offset;
    }
    Arena small(pool, 100U * sizeof(OctreeNode) - 1U);
    Octree t;
    EXPECT_EQ(t.init(c, small).code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(t.insert(at(0.0, 0.0, 0.0, 1.0)).code(), StatusCode::kNotInitialized);
}

}  // namespace
}  // namespace vtm::octree
