// Height maps at several resolutions from the octree, as one product set (paper §6:
// "height maps at any resolution by keeping the largest z per bin"; docs/octree.md).
//
// Product p is a terrain::HeightMap (its grid convention, docs/terrain.md) over the root
// cube's square: north-west corner (north_edge_m, west_edge_m), cell side_m / 2^level,
// 2^level x 2^level cells. Its bins are the octree's cells at that level seen from above:
// a sample lands in the bin HeightMap::add would put its point in.
//
// Extraction rule, per bin at level B: the samples at least as fine as the bin (nodes at
// levels >= B inside it) make the bin: highest (the paper's largest z), lowest, spread,
// count, and the mean with a kMean reducer. Where there are none, the finest coarser level
// l < B that has samples over the bin fills it: every level-l node above the bin (its
// whole column in z) contributes, so an orbital sample paints every bin of its cell where
// the rover saw nothing and never overrides what the rover saw. dataLevel() tells which:
// B for the bin's own resolution or finer, l < B for coarse fill, kNoLevel for no data.
//
// Bounded: extract() clears the maps (4^B bins each) and sweeps the node pool once for the
// fine data and once per coarser level that holds samples (<= B + 1 sweeps of nodeCount()
// nodes); a coarse node writes the 4^(B - l) bins it covers. No heap, no recursion.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/octree/octree.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::octree {

constexpr std::int32_t kMaxProducts = 6;
constexpr std::int32_t kMaxProductLevel = 12;  // 4096 cells a side: terrain::kMaxGridSide
constexpr std::uint8_t kNoLevel = 0xFFU;       // dataLevel() of a bin without data

struct ProductConfig {
    // Octree levels of the products, strictly increasing, each 0..min(max_depth,
    // kMaxProductLevel); the first `count` entries are used. Default: cells of side/16,
    // side/64, side/256 (8, 2 and 0.5 m in the default 128 m cube).
    std::array<std::int32_t, kMaxProducts> levels{{4, 6, 8, 0, 0, 0}};
    std::int32_t count = 3;  // 1..kMaxProducts
    // What HeightMap::elevation() gives: kHighest (the paper's largest z) or kMean (the
    // mean; the maps then also hold the sums). highest/lowest/spread/count on either.
    terrain::Reducer reducer = terrain::Reducer::kHighest;
    // kInvalidConfig naming the field ("products.levels: ...").
    [[nodiscard]] Status validate(const OctreeConfig& octree) const noexcept;
};

// Work of the last extract(), summed over the products.
struct ExtractStats {
    std::int64_t node_visits = 0;   // nodes looked at in the pool sweeps
    std::int64_t fine_writes = 0;   // node summaries merged into the bin they lie in
    std::int64_t coarse_writes = 0; // node summaries painted into bins finer than them
};

class HeightProducts {
public:
    // Per product: HeightMap::workspaceBytes of its grid and reducer, + 4^level bytes
    // (dataLevel) + 2 * 4^level bytes (sources), each block padded (Arena::arrayBytes).
    // 0 if either configuration is invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const ProductConfig& products, const OctreeConfig& octree) noexcept;
    // kInvalidConfig naming the field; kOutOfMemory.
    [[nodiscard]] Status init(const ProductConfig& products, const OctreeConfig& octree, Arena& arena) noexcept;

    // Rebuilds every product from the tree (rule above). kNotInitialized (either);
    // kSizeMismatch for a tree whose root cube or depth is not the init one's.
    [[nodiscard]] Status extract(const Octree& tree) noexcept;

    [[nodiscard]] std::int32_t count() const noexcept { return config_.count; }
    [[nodiscard]] std::int32_t level(std::int32_t product) const noexcept;
    // Product 0 <= product < count() (VTM_ASSERT).
    [[nodiscard]] const terrain::HeightMap& map(std::int32_t product) const noexcept;
    // The level whose samples made bin (col, row) (see above); kNoLevel without data.
    [[nodiscard]] std::uint8_t dataLevel(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept;
    // Bit s: a sample of source s contributed to bin (col, row).
    [[nodiscard]] std::uint16_t sources(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] const ExtractStats& stats() const noexcept { return stats_; }

private:
    struct Product {
        terrain::HeightMap map;
        Span<std::uint8_t> data_level;
        Span<std::uint16_t> sources;
        std::int32_t level = 0;
    };
    [[nodiscard]] std::size_t binIndex(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept;
    void clearProduct(Product& p) noexcept;
    void addFineNodes(Product& p, const Octree& tree) noexcept;
    void fillFromLevel(Product& p, const Octree& tree, std::int32_t coarse) noexcept;
    void write(Product& p, const OctreeNode& node, std::uint32_t col, std::uint32_t row_from_south,
               std::uint8_t data_level) noexcept;

    ProductConfig config_{};
    OctreeConfig octree_{};
    bool initialized_ = false;
    std::array<Product, kMaxProducts> products_{};
    ExtractStats stats_{};
};

}  // namespace vtm::octree
