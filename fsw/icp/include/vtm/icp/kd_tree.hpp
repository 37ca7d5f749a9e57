// A k-d tree over a fixed array of points, built without recursion into storage carved
// from an Arena, for nearest-neighbour queries with bounded work (docs/icp.md "Neighbours").
//
// Shape: an implicit balanced tree. The root covers all n points; a node covering
// [lo, hi) of the permutation `order` splits at mid = (lo + hi) / 2 along the axis of its
// points' largest extent, by selection (std::nth_element under a strict total order:
// coordinate, then point index), so each child holds a uniquely defined set of points.
// Nodes are stored breadth first (children of i at 2i + 1, 2i + 2); a node is a leaf when
// it covers at most leaf_size points. Build: O(n log n), no recursion.
//
// Query: the k nearest points within a radius, depth first with an explicit stack, far
// children pruned by their splitting plane; at most `max_leaves` leaves are opened
// (the bound on the work of one query: max_leaves * leaf_size distances). A query that
// hits the bound returns the best found so far and says so (approximate). Equal distances
// are ordered by point index, so the answer does not depend on the order inside a leaf.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/span.hpp"

namespace vtm::icp {

constexpr std::int32_t kMaxNeighbours = 32;  // k of one query, at most
constexpr std::int32_t kMaxTreeDepth = 30;   // depth of any tree this module builds

struct TreePoint {
    float x, y, z;  // metres, relative to the owner's origin
};

struct TreeNode {
    float split;         // coordinate of the plane
    std::int32_t axis;   // 0, 1, 2
};

struct Neighbours {
    std::int32_t count = 0;
    std::int32_t index[kMaxNeighbours]{};  // ascending distance, then index
    double distance2[kMaxNeighbours]{};    // squared, m^2
    bool truncated = false;                // max_leaves reached before the search was exact
};

class KdTree {
public:
    // Tree depth for n points and the leaf size: the least d with ceil(n / 2^d) <= leaf_size.
    [[nodiscard]] static std::int32_t depthFor(std::size_t n, std::int32_t leafSize) noexcept;
    // Bytes of arena for a tree over up to maxPoints points (node array and permutation).
    [[nodiscard]] static std::size_t workspaceBytes(std::size_t maxPoints, std::int32_t leafSize) noexcept;

    // Carves the storage; false when the arena is too small. leafSize >= 1.
    [[nodiscard]] bool init(std::size_t maxPoints, std::int32_t leafSize, std::int32_t maxLeaves,
                            Arena& arena) noexcept;

    // Builds over points (not copied: they must outlive the queries). points.size() <= maxPoints.
    void build(Span<const TreePoint> points) noexcept;

    // The k (1..kMaxNeighbours) nearest points to q whose squared distance is <= radius2.
    void nearest(double qx, double qy, double qz, std::int32_t k, double radius2, Neighbours& out) const noexcept;

    [[nodiscard]] std::size_t size() const noexcept { return points_.size(); }

private:
    void splitNode(std::int32_t node, std::int32_t lo, std::int32_t hi) noexcept;
    void scanLeaf(std::int32_t lo, std::int32_t hi, double qx, double qy, double qz, std::int32_t k, double radius2,
                  Neighbours& out) const noexcept;

    Span<const TreePoint> points_{};
    Span<std::int32_t> order_{};
    Span<TreeNode> nodes_{};
    std::size_t maxPoints_ = 0U;
    std::int32_t leafSize_ = 8;
    std::int32_t maxLeaves_ = 64;
    std::int32_t depth_ = 0;
};

}  // namespace vtm::icp
