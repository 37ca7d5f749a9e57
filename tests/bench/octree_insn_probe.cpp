// Instruction-count probe of the terrain octree (vtm::octree), built for every target.
// Counted under qemu-user with the plugin of tools/qemu (docs/octree.md "Cost"):
//
//   vtm_octree_insn_probe SAMPLES INSERT_REPEAT EXTRACT_REPEAT
//
// A 64 m cube, max_depth 10, 65,536 nodes. SAMPLES points spread uniformly over the cube's
// square on a gentle surface, each with a 5 cm footprint: every insertion walks to level
// 10, the deepest (the worst case of the walk). The tree is cleared and refilled
// INSERT_REPEAT times, then products at levels 4, 6 and 8 (kHighest) are extracted
// EXTRACT_REPEAT times. Differences of counts isolate one pass:
//   per insertion = (count(S, 2, 0) - count(S, 1, 0)) / S
//   per extraction = count(S, 1, 2) - count(S, 1, 1)
// Prints the node count and a hash of the 0.25 m product (the same on every target).
// Test code: the heap holds the samples and pools.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/core/random.hpp"
#include "vtm/octree/height_products.hpp"
#include "vtm/octree/octree.hpp"

namespace {

int parseArg(const char* s, int lo, int hi, const char* what) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) {
        std::fprintf(stderr, "octree_insn_probe: %s must be %d..%d\n", what, lo, hi);
        std::exit(2);
    }
    return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: vtm_octree_insn_probe SAMPLES INSERT_REPEAT EXTRACT_REPEAT\n");
        return 2;
    }
    const int n = parseArg(argv[1], 1, 200000, "SAMPLES");
    const int insert_repeat = parseArg(argv[2], 0, 100, "INSERT_REPEAT");
    const int extract_repeat = parseArg(argv[3], 0, 100, "EXTRACT_REPEAT");
    vtm::octree::OctreeConfig c;
    c.north_edge_m = 32.0;
    c.west_edge_m = -32.0;
    c.top_z_m = -16.0;
    c.side_m = 64.0;
    c.max_depth = 10;
    c.max_nodes = 65536;
    std::vector<vtm::octree::Sample> samples(static_cast<std::size_t>(n));
    vtm::Random rng(0x0C7EEu);
    for (vtm::octree::Sample& s : samples) {
        const double x = -32.0 + 64.0 * rng.uniform01();
        const double y = -32.0 + 64.0 * rng.uniform01();
        s.site_m = vtm::Vec3(x, y, -(0.02 * x - 0.01 * y + 0.001 * x * y / 8.0));
        s.footprint_m = 0.05;
        s.source = 0U;
    }
    std::vector<std::byte> tree_pool(vtm::octree::Octree::workspaceBytes(c));
    vtm::Arena tree_arena(tree_pool.data(), tree_pool.size());
    static vtm::octree::Octree tree;
    vtm::octree::ProductConfig pc;  // levels 4, 6, 8, kHighest
    std::vector<std::byte> product_pool(vtm::octree::HeightProducts::workspaceBytes(pc, c));
    vtm::Arena product_arena(product_pool.data(), product_pool.size());
    static vtm::octree::HeightProducts products;
    if (!tree.init(c, tree_arena).isOk() || !products.init(pc, c, product_arena).isOk()) {
        std::fprintf(stderr, "octree_insn_probe: init failed\n");
        return 1;
    }
    const vtm::Span<const vtm::octree::Sample> all(samples.data(), samples.size());
    for (int r = 0; r < insert_repeat; ++r) {
        tree.clear();
        if (!tree.insert(all).isOk()) {
            std::fprintf(stderr, "octree_insn_probe: insert refused (pool too small?)\n");
            return 1;
        }
    }
    for (int r = 0; r < extract_repeat; ++r) {
        if (!products.extract(tree).isOk()) {
            std::fprintf(stderr, "octree_insn_probe: extract failed\n");
            return 1;
        }
    }
    std::uint64_t hash = 0xCBF29CE484222325ULL;
    const vtm::terrain::HeightMap& m = products.map(2);
    for (std::int32_t row = 0; row < m.grid().rows; ++row) {
        for (std::int32_t col = 0; col < m.grid().cols; ++col) {
            const float v = m.count(col, row) > 0U ? m.highest(col, row) : 0.0F;
            std::uint32_t bits = 0U;
            std::memcpy(&bits, &v, sizeof bits);
            hash = (hash ^ bits) * 0x100000001B3ULL;
        }
    }
    std::printf("samples %d nodes %u hash %016llx\n", n, tree.nodeCount(), static_cast<unsigned long long>(hash));
    return 0;
}
