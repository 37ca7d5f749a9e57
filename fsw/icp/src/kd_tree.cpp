// The k-d tree of the ICP model: build by selection level by level, bounded queries.
#include "vtm/icp/kd_tree.hpp"

#include <algorithm>

namespace vtm::icp {
namespace {

float coordinate(const TreePoint& p, std::int32_t axis) noexcept {
    return axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
}

double coordinate(double x, double y, double z, std::int32_t axis) noexcept {
    return axis == 0 ? x : (axis == 1 ? y : z);
}

// Range [lo, hi) of node `position` (0-based within its level) at depth `depth`: follow the
// path bits from the root, taking the upper half for a 1.
void rangeOf(std::int32_t depth, std::int32_t position, std::int32_t n, std::int32_t& lo, std::int32_t& hi) noexcept {
    lo = 0;
    hi = n;
    for (std::int32_t b = depth - 1; b >= 0; --b) {
        const std::int32_t mid = lo + (hi - lo) / 2;
        if (((position >> b) & 1) != 0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

struct StackEntry {
    std::int32_t node;
    std::int32_t depth;
    std::int32_t lo;
    std::int32_t hi;
    double plane2;  // squared distance from the query to the node's side of its parent's plane
};

}  // namespace

std::int32_t KdTree::depthFor(std::size_t n, std::int32_t leafSize) noexcept {
    std::int32_t d = 0;
    const auto leaf = static_cast<std::size_t>(leafSize < 1 ? 1 : leafSize);
    while (d < kMaxTreeDepth && ((n + (std::size_t{1} << d) - 1U) >> d) > leaf) {  // bound: kMaxTreeDepth
        ++d;
    }
    return d;
}

std::size_t KdTree::workspaceBytes(std::size_t maxPoints, std::int32_t leafSize) noexcept {
    const std::size_t internal = (std::size_t{1} << depthFor(maxPoints, leafSize)) - 1U;
    return Arena::arrayBytes<std::int32_t>(maxPoints)  // permutation of the points
           + Arena::arrayBytes<TreeNode>(internal);    // splitting planes of the internal nodes
}

bool KdTree::init(std::size_t maxPoints, std::int32_t leafSize, std::int32_t maxLeaves, Arena& arena) noexcept {
    maxPoints_ = maxPoints;
    leafSize_ = leafSize < 1 ? 1 : leafSize;
    maxLeaves_ = maxLeaves < 1 ? 1 : maxLeaves;
    const std::size_t internal = (std::size_t{1} << depthFor(maxPoints, leafSize_)) - 1U;
    order_ = arena.allocateArray<std::int32_t>(maxPoints);
    nodes_ = internal > 0U ? arena.allocateArray<TreeNode>(internal) : Span<TreeNode>();
    points_ = Span<const TreePoint>();
    return order_.size() == maxPoints && nodes_.size() == internal;
}

void KdTree::build(Span<const TreePoint> points) noexcept {
    VTM_ASSERT(points.size() <= maxPoints_, static_cast<std::int64_t>(points.size()),
               static_cast<std::int64_t>(maxPoints_));
    points_ = points.size() <= maxPoints_ ? points : Span<const TreePoint>();
    const auto n = static_cast<std::int32_t>(points_.size());
    for (std::int32_t i = 0; i < n; ++i) {
        order_[static_cast<std::size_t>(i)] = i;
    }
    depth_ = depthFor(points_.size(), leafSize_);
    // Level by level: every node of a level is split before the next level starts.
    for (std::int32_t d = 0; d < depth_; ++d) {
        const std::int32_t first = (1 << d) - 1;
        for (std::int32_t position = 0; position < (1 << d); ++position) {
            std::int32_t lo = 0;
            std::int32_t hi = 0;
            rangeOf(d, position, n, lo, hi);
            splitNode(first + position, lo, hi);
        }
    }
}

void KdTree::splitNode(std::int32_t node, std::int32_t lo, std::int32_t hi) noexcept {
    TreeNode& t = nodes_[static_cast<std::size_t>(node)];
    if (hi - lo < 2) {
        t.axis = 0;
        t.split = hi > lo ? points_[static_cast<std::size_t>(order_[static_cast<std::size_t>(lo)])].x : 0.0F;
        return;
    }
    float mn[3] = {0.0F, 0.0F, 0.0F};
    float mx[3] = {0.0F, 0.0F, 0.0F};
    for (std::int32_t i = lo; i < hi; ++i) {
        const TreePoint& p = points_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
        for (std::int32_t a = 0; a < 3; ++a) {
            const float c = coordinate(p, a);
            mn[a] = (i == lo || c < mn[a]) ? c : mn[a];
            mx[a] = (i == lo || c > mx[a]) ? c : mx[a];
        }
    }
    std::int32_t axis = 0;
    for (std::int32_t a = 1; a < 3; ++a) {
        if (mx[a] - mn[a] > mx[axis] - mn[axis]) {
            axis = a;
        }
    }
    const TreePoint* pts = points_.data();
    const auto less = [pts, axis](std::int32_t a, std::int32_t b) noexcept {
        const float ca = coordinate(pts[a], axis);
        const float cb = coordinate(pts[b], axis);
        return ca < cb || (ca == cb && a < b);
    };
    const std::int32_t mid = lo + (hi - lo) / 2;
    std::int32_t* o = order_.data();
    std::nth_element(o + lo, o + mid, o + hi, less);
    t.axis = axis;
    t.split = coordinate(pts[o[mid]], axis);
}

void KdTree::scanLeaf(std::int32_t lo, std::int32_t hi, double qx, double qy, double qz, std::int32_t k,
                      double radius2, Neighbours& out) const noexcept {
    for (std::int32_t i = lo; i < hi; ++i) {
        const std::int32_t idx = order_[static_cast<std::size_t>(i)];
        const TreePoint& p = points_[static_cast<std::size_t>(idx)];
        const double dx = static_cast<double>(p.x) - qx;
        const double dy = static_cast<double>(p.y) - qy;
        const double dz = static_cast<double>(p.z) - qz;
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 > radius2) {
            continue;
        }
        // Insertion into the sorted list (distance, then index); the last one drops out when full.
        std::int32_t pos = out.count;
        // bound: out.count <= kMaxNeighbours steps
        while (pos > 0 && (out.distance2[pos - 1] > d2 || (out.distance2[pos - 1] == d2 && out.index[pos - 1] > idx))) {
            --pos;
        }
        if (pos >= k) {
            continue;
        }
        const std::int32_t last = out.count < k ? out.count : k - 1;
        for (std::int32_t j = last; j > pos; --j) {
            out.distance2[j] = out.distance2[j - 1];
            out.index[j] = out.index[j - 1];
        }
        out.distance2[pos] = d2;
        out.index[pos] = idx;
        out.count = out.count < k ? out.count + 1 : k;
    }
}

void KdTree::nearest(double qx, double qy, double qz, std::int32_t k, double radius2, Neighbours& out) const noexcept {
    out.count = 0;
    out.truncated = false;
    k = std::clamp(k, 1, kMaxNeighbours);
    if (points_.empty()) {
        return;
    }
    StackEntry stack[kMaxTreeDepth + 2];
    std::int32_t top = 0;
    stack[top++] = StackEntry{0, 0, 0, static_cast<std::int32_t>(points_.size()), 0.0};
    std::int32_t leaves = 0;
    // Every node is pushed at most once, and at most max_leaves leaves are scanned.
    while (top > 0) {  // bound: 2^(depth+1) - 1 pops
        const StackEntry e = stack[--top];
        const double worst = out.count == k ? out.distance2[k - 1] : radius2;
        if (e.plane2 > worst) {
            continue;
        }
        if (e.depth == depth_) {
            if (leaves == maxLeaves_) {
                out.truncated = true;
                return;
            }
            scanLeaf(e.lo, e.hi, qx, qy, qz, k, radius2, out);
            ++leaves;
            continue;
        }
        const TreeNode& t = nodes_[static_cast<std::size_t>(e.node)];
        const double diff = coordinate(qx, qy, qz, t.axis) - static_cast<double>(t.split);
        const std::int32_t mid = e.lo + (e.hi - e.lo) / 2;
        const StackEntry left{2 * e.node + 1, e.depth + 1, e.lo, mid, diff < 0.0 ? e.plane2 : std::max(e.plane2, diff * diff)};
        const StackEntry right{2 * e.node + 2, e.depth + 1, mid, e.hi, diff < 0.0 ? std::max(e.plane2, diff * diff) : e.plane2};
        // Far side first, so the near side is searched next.
        stack[top++] = diff < 0.0 ? right : left;
        stack[top++] = diff < 0.0 ? left : right;
    }
}

}  // namespace vtm::icp
