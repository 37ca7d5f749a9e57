// The multi-resolution terrain octree (paper §6, SUMMITT; docs/octree.md).
//
// Terrain samples from sources of very different resolution (rover stereo, wide-baseline,
// descent, orbital maps) are kept in one octree over a cube of the site frame (x north,
// y east, z down, metres). Each sample carries a footprint (metres: its range times the
// pixel's angle, or its source grid's cell) and is inserted at the level whose cell
// matches it: the DEEPEST level whose cell side is still >= the footprint (level 0 = the
// root cube, side side_m; level l: side_m / 2^l). Coarse samples stay near the root, fine
// ones reach the leaves. Each node keeps the statistics of the samples inserted AT it
// (not of its subtree): count, highest and lowest elevation, the mean, and a bitmask of
// their sources.
//
// Cell keys are integers: a point's key at max_depth is floor((x - south_edge) / finest
// cell) per axis (double, + - / floor only), and the key at level l is that >> (max_depth
// - l). The same bits on every target.
//
// Bounded: an insertion walks at most max_depth levels and creates at most that many
// nodes from a pool sized at init (workspaceBytes); a full pool refuses the sample
// (kOutOfMemory) before anything changes. No recursion, no heap after init.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::octree {

constexpr std::int32_t kMaxDepth = 20;          // keys fit 20 bits per axis
constexpr std::int32_t kMaxNodes = 1 << 24;     // pool capacity limit
constexpr std::int32_t kMaxSources = 16;        // source ids 0..15 (a 16-bit mask per node)
constexpr std::uint32_t kNoNode = 0U;           // "no child": the root (index 0) is nobody's child
constexpr std::uint16_t kMaxNodeCount = 65535U; // a node's count saturates here

// The root cube in the site frame and the pool.
struct OctreeConfig {
    double north_edge_m = 64.0;   // site x of the north face (open: x < north_edge_m)
    double west_edge_m = -64.0;   // site y of the west face (closed)
    double top_z_m = -32.0;       // site z (down) of the top face (closed): z in [top, top + side)
    double side_m = 128.0;        // (0, 1e6]; the cube spans x in [north - side, north)
    std::int32_t max_depth = 10;  // 0..kMaxDepth; finest cell side_m / 2^max_depth
    std::int32_t max_nodes = 65536;  // 1..kMaxNodes, the root included
    // kInvalidConfig naming the field ("octree.side_m: ...", value in detail).
    [[nodiscard]] Status validate() const noexcept;
};

// One terrain sample.
struct Sample {
    Vec3 site_m{0.0, 0.0, 0.0};  // site frame (x north, y east, z down), metres
    double footprint_m = 0.0;    // metres, finite and > 0: the size of ground it stands for
    std::uint8_t source = 0U;    // 0..kMaxSources-1 (rover stereo, descent, orbital, ...)
};

// A node of the pool. Keys count cells of the node's level from the cube's south-west-top
// corner along x (north), y (east) and z (down). Elevations up (= -site z), metres.
struct OctreeNode {
    std::uint32_t child[8];   // pool indices, kNoNode = none; octant bit 0 x, bit 1 y, bit 2 z
    std::uint32_t key_x;
    std::uint32_t key_y;
    std::uint32_t key_z;
    float highest_m;          // of the samples inserted at this node (valid when count > 0)
    float lowest_m;
    double sum_m;             // sum of the float elevations, in insertion order, while count < 65535
    std::uint16_t count;      // samples inserted here, saturating at kMaxNodeCount
    std::uint16_t sources;    // bit s set: a sample of source s was inserted here
    std::uint8_t level;       // 0 = root
};

// What a node's samples say, read off an OctreeNode.
struct NodeStats {
    std::uint16_t count = 0U;
    float highest_m = 0.0F;  // NaN (terrain::kNoData) when count is 0, as all three below
    float lowest_m = 0.0F;
    float mean_m = 0.0F;     // sum_m / count (the first 65535 samples when saturated)
    float spread_m = 0.0F;   // highest - lowest
    std::uint16_t sources = 0U;
};
[[nodiscard]] NodeStats statsOf(const OctreeNode& node) noexcept;

// Counters of insert(): what went in, what was refused and why.
struct InsertStats {
    std::int64_t inserted = 0;
    std::int64_t inserted_at_level[kMaxDepth + 1] = {};
    std::int64_t refused_not_finite = 0;  // site_m not finite
    std::int64_t refused_outside = 0;     // outside the root cube
    std::int64_t refused_footprint = 0;   // footprint_m not finite or <= 0
    std::int64_t refused_source = 0;      // source >= kMaxSources
    std::int64_t refused_pool_full = 0;   // the nodes it needed were not left in the pool
};

class Octree {
public:
    // Bytes of arena for the node pool: Arena::arrayBytes<OctreeNode>(max_nodes); 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const OctreeConfig& config) noexcept;
    // kInvalidConfig naming the field, kOutOfMemory. The tree starts as the root alone.
    [[nodiscard]] Status init(const OctreeConfig& config, Arena& arena) noexcept;
    // Back to the root alone, counters zeroed.
    void clear() noexcept;

    // Inserts one sample at levelFor(footprint_m). kNotInitialized; kInvalidArgument naming
    // the input (site_m not finite, outside the root cube, footprint_m, source);
    // kOutOfMemory when the pool cannot hold the nodes down to its level. A refused sample
    // changes nothing but its counter.
    [[nodiscard]] Status insert(const Sample& sample) noexcept;
    // Inserts each in order; refused samples are counted and skipped. Returns the first
    // refusal's Status (kOk if none).
    [[nodiscard]] Status insert(Span<const Sample> samples) noexcept;

    // The level a footprint goes to: the deepest l <= max_depth with side_m / 2^l >=
    // footprint_m (0 for footprints at or above side_m). -1 for a footprint that is not
    // finite and > 0.
    [[nodiscard]] std::int32_t levelFor(double footprint_m) const noexcept;
    // side_m / 2^level, metres.
    [[nodiscard]] double cellSideM(std::int32_t level) const noexcept;
    // The node at `level` holding site point site_m, or nullptr (no such node, outside,
    // level out of 0..max_depth).
    [[nodiscard]] const OctreeNode* find(const Vec3& site_m, std::int32_t level) const noexcept;

    [[nodiscard]] std::uint32_t nodeCount() const noexcept { return used_; }
    // Pool entry 0 <= index < nodeCount() (VTM_ASSERT); index 0 is the root.
    [[nodiscard]] const OctreeNode& node(std::uint32_t index) const noexcept;
    [[nodiscard]] const InsertStats& stats() const noexcept { return stats_; }
    [[nodiscard]] const OctreeConfig& config() const noexcept { return config_; }
    [[nodiscard]] bool initialized() const noexcept { return initialized_; }

private:
    [[nodiscard]] Status checkSample(const Sample& sample) noexcept;
    [[nodiscard]] bool finestKey(const Vec3& site_m, std::uint32_t key[3]) const noexcept;
    [[nodiscard]] std::uint32_t newNode(std::uint32_t parent, std::uint32_t octant) noexcept;
    static void accumulate(OctreeNode& node, const Sample& sample) noexcept;

    OctreeConfig config_{};
    bool initialized_ = false;
    double south_edge_m_ = 0.0;  // north_edge_m - side_m
    double finest_m_ = 0.0;      // side_m / 2^max_depth
    Span<OctreeNode> nodes_{};
    std::uint32_t used_ = 0U;
    InsertStats stats_{};
};

}  // namespace vtm::octree
