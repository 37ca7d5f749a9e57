#include "vtm/octree/octree.hpp"
#include "vtm/core/config_check.hpp"

#include <cmath>
#include <limits>

#include "vtm/core/assert.hpp"
#include "vtm/core/math.hpp"

namespace vtm::octree {
namespace {

// Octant of the child at `level` on the way to finest keys `key`: bit 0 x, bit 1 y, bit 2 z.
std::uint32_t octantAt(const std::uint32_t key[3], std::int32_t max_depth, std::int32_t level) noexcept {
    const auto shift = static_cast<std::uint32_t>(max_depth - level);
    return ((key[0] >> shift) & 1U) | (((key[1] >> shift) & 1U) << 1U) | (((key[2] >> shift) & 1U) << 2U);
}

}  // namespace

Status OctreeConfig::validate() const noexcept {
    if (!math::isFinite(north_edge_m)) {
        return invalidConfig("octree.north_edge_m: must be finite", 0);
    }
    if (!math::isFinite(west_edge_m)) {
        return invalidConfig("octree.west_edge_m: must be finite", 0);
    }
    if (!math::isFinite(top_z_m)) {
        return invalidConfig("octree.top_z_m: must be finite", 0);
    }
    // From 1 mm: the finest cell, side / 2^20, stays a normal double (exact halving).
    if (!(side_m >= 1.0e-3) || !(side_m <= 1.0e6)) {
        return invalidConfig("octree.side_m: must be in [0.001, 1e6] m", 0);  // no detail: a double may not fit
    }
    if (max_depth < 0 || max_depth > kMaxDepth) {
        return invalidConfig("octree.max_depth: must be 0..20", max_depth);
    }
    if (max_nodes < 1 || max_nodes > kMaxNodes) {
        return invalidConfig("octree.max_nodes: must be 1..16777216", max_nodes);
    }
    return Status::ok();
}

NodeStats statsOf(const OctreeNode& node) noexcept {
    NodeStats s;
    s.count = node.count;
    s.sources = node.sources;
    if (node.count == 0U) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        s.highest_m = nan;
        s.lowest_m = nan;
        s.mean_m = nan;
        s.spread_m = nan;
        return s;
    }
    s.highest_m = node.highest_m;
    s.lowest_m = node.lowest_m;
    s.mean_m = static_cast<float>(node.sum_m / static_cast<double>(node.count));
    s.spread_m = node.highest_m - node.lowest_m;
    return s;
}

std::size_t Octree::workspaceBytes(const OctreeConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    return Arena::arrayBytes<OctreeNode>(static_cast<std::size_t>(config.max_nodes));
}

Status Octree::init(const OctreeConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    nodes_ = arena.allocateArray<OctreeNode>(static_cast<std::size_t>(config.max_nodes));
    if (nodes_.size() != static_cast<std::size_t>(config.max_nodes)) {
        return Status(StatusCode::kOutOfMemory, "octree: arena too small for max_nodes",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    south_edge_m_ = config.north_edge_m - config.side_m;
    finest_m_ = cellSideM(config.max_depth);
    initialized_ = true;
    clear();
    return Status::ok();
}

void Octree::clear() noexcept {
    if (!initialized_) {
        return;
    }
    nodes_[0] = OctreeNode{};
    used_ = 1U;
    stats_ = InsertStats{};
}

double Octree::cellSideM(std::int32_t level) const noexcept {
    // A division by a power of two: exact, so every level's side is side_m scaled exactly.
    const std::int32_t l = (level < 0) ? 0 : ((level > kMaxDepth) ? kMaxDepth : level);
    return config_.side_m / static_cast<double>(1U << static_cast<std::uint32_t>(l));
}

std::int32_t Octree::levelFor(double footprint_m) const noexcept {
    if (!math::isFinite(footprint_m) || !(footprint_m > 0.0)) {
        return -1;
    }
    std::int32_t level = 0;
    double cell = config_.side_m;
    for (; level < config_.max_depth; ++level) {  // bound: max_depth halvings
        const double half = cell * 0.5;
        if (!(half >= footprint_m)) {
            break;
        }
        cell = half;
    }
    return level;
}

bool Octree::finestKey(const Vec3& site_m, std::uint32_t key[3]) const noexcept {
    const double side = static_cast<double>(1U << static_cast<std::uint32_t>(config_.max_depth));
    const double f[3] = {math::floor((site_m.x() - south_edge_m_) / finest_m_),
                         math::floor((site_m.y() - config_.west_edge_m) / finest_m_),
                         math::floor((site_m.z() - config_.top_z_m) / finest_m_)};
    for (std::int32_t a = 0; a < 3; ++a) {
        if (!(f[a] >= 0.0) || !(f[a] < side)) {  // checked in double: no overflowing conversion
            return false;
        }
        key[a] = static_cast<std::uint32_t>(f[a]);
    }
    return true;
}

Status Octree::checkSample(const Sample& sample) noexcept {
    if (!math::isFinite(sample.site_m.x()) || !math::isFinite(sample.site_m.y()) ||
        !math::isFinite(sample.site_m.z())) {
        ++stats_.refused_not_finite;
        return Status(StatusCode::kInvalidArgument, "octree: sample site_m not finite");
    }
    if (levelFor(sample.footprint_m) < 0) {
        ++stats_.refused_footprint;
        return Status(StatusCode::kInvalidArgument, "octree: sample footprint_m must be finite and > 0");
    }
    if (sample.source >= kMaxSources) {
        ++stats_.refused_source;
        return Status(StatusCode::kInvalidArgument, "octree: sample source must be 0..15", sample.source);
    }
    return Status::ok();
}

std::uint32_t Octree::newNode(std::uint32_t parent, std::uint32_t octant) noexcept {
    VTM_ASSERT(used_ < nodes_.size() && octant < 8U, used_, octant);
    const std::uint32_t n = used_;
    ++used_;
    const OctreeNode& p = nodes_[parent];
    OctreeNode& c = nodes_[n];
    c = OctreeNode{};
    c.level = static_cast<std::uint8_t>(p.level + 1U);
    c.key_x = (p.key_x << 1U) | (octant & 1U);
    c.key_y = (p.key_y << 1U) | ((octant >> 1U) & 1U);
    c.key_z = (p.key_z << 1U) | ((octant >> 2U) & 1U);
    nodes_[parent].child[octant] = n;
    return n;
}

void Octree::accumulate(OctreeNode& node, const Sample& sample) noexcept {
    const auto up = static_cast<float>(-sample.site_m.z());
    if (node.count == 0U) {
        node.highest_m = up;
        node.lowest_m = up;
    } else {
        node.highest_m = (up > node.highest_m) ? up : node.highest_m;
        node.lowest_m = (up < node.lowest_m) ? up : node.lowest_m;
    }
    if (node.count < kMaxNodeCount) {  // a saturated node keeps the mean of its first 65535
        node.sum_m += static_cast<double>(up);
        node.count = static_cast<std::uint16_t>(node.count + 1U);
    }
    node.sources = static_cast<std::uint16_t>(node.sources | (1U << sample.source));
}

Status Octree::insert(const Sample& sample) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "octree: insert before init");
    }
    VTM_RETURN_IF_ERROR(checkSample(sample));
    std::uint32_t key[3] = {0U, 0U, 0U};
    if (!finestKey(sample.site_m, key)) {
        ++stats_.refused_outside;
        return Status(StatusCode::kInvalidArgument, "octree: sample site_m outside the root cube");
    }
    const std::int32_t level = levelFor(sample.footprint_m);
    // Down through the nodes that exist (at most `level` steps) ...
    std::uint32_t at = 0U;
    std::int32_t l = 0;
    for (; l < level; ++l) {
        const std::uint32_t c = nodes_[at].child[octantAt(key, config_.max_depth, l + 1)];
        if (c == kNoNode) {
            break;
        }
        at = c;
    }
    // ... then create the rest, only if the pool holds all of them: a refusal changes nothing.
    const auto missing = static_cast<std::uint32_t>(level - l);
    if (missing > nodes_.size() - used_) {
        ++stats_.refused_pool_full;
        return Status(StatusCode::kOutOfMemory, "octree: node pool full (max_nodes)", level);
    }
    for (; l < level; ++l) {
        at = newNode(at, octantAt(key, config_.max_depth, l + 1));
    }
    accumulate(nodes_[at], sample);
    ++stats_.inserted;
    ++stats_.inserted_at_level[level];
    return Status::ok();
}

Status Octree::insert(Span<const Sample> samples) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "octree: insert before init");
    }
    Status first = Status::ok();
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const Status s = insert(samples[i]);
        if (first.isOk() && !s.isOk()) {
            first = s;
        }
    }
    return first;
}

const OctreeNode* Octree::find(const Vec3& site_m, std::int32_t level) const noexcept {
    std::uint32_t key[3] = {0U, 0U, 0U};
    if (!initialized_ || level < 0 || level > config_.max_depth || !math::isFinite(site_m.x()) ||
        !math::isFinite(site_m.y()) || !math::isFinite(site_m.z()) || !finestKey(site_m, key)) {
        return nullptr;
    }
    std::uint32_t at = 0U;
    for (std::int32_t l = 1; l <= level; ++l) {  // bound: level <= max_depth
        at = nodes_[at].child[octantAt(key, config_.max_depth, l)];
        if (at == kNoNode) {
            return nullptr;
        }
    }
    return &nodes_[at];
}

const OctreeNode& Octree::node(std::uint32_t index) const noexcept {
    VTM_ASSERT(index < used_, index, used_);
    return nodes_[(index < used_) ? index : 0U];
}

}  // namespace vtm::octree
