#include "vtm/octree/height_products.hpp"

#include "vtm/core/assert.hpp"

namespace vtm::octree {
namespace {

std::size_t binsOf(std::int32_t level) noexcept {
    const std::size_t side = std::size_t{1} << static_cast<std::uint32_t>(level);
    return side * side;
}

terrain::HeightMapConfig mapConfig(const OctreeConfig& octree, std::int32_t level, terrain::Reducer reducer) noexcept {
    terrain::HeightMapConfig c;
    c.grid.north_edge_m = octree.north_edge_m;
    c.grid.west_edge_m = octree.west_edge_m;
    // side / 2^level exactly (a power of two), so rows * cell_m is side_m again and the
    // map's south edge is the cube's: a point's bin is its octree key at this level.
    c.grid.cell_m = octree.side_m / static_cast<double>(1U << static_cast<std::uint32_t>(level));
    c.grid.cols = 1 << level;
    c.grid.rows = 1 << level;
    c.reducer = reducer;
    return c;
}

bool sameCube(const OctreeConfig& a, const OctreeConfig& b) noexcept {
    return a.north_edge_m == b.north_edge_m && a.west_edge_m == b.west_edge_m && a.top_z_m == b.top_z_m &&
           a.side_m == b.side_m && a.max_depth == b.max_depth;
}

}  // namespace

Status ProductConfig::validate(const OctreeConfig& octree) const noexcept {
    VTM_RETURN_IF_ERROR(octree.validate());
    if (count < 1 || count > kMaxProducts) {
        return Status(StatusCode::kInvalidConfig, "products.count: must be 1..6", count);
    }
    if (reducer != terrain::Reducer::kHighest && reducer != terrain::Reducer::kMean &&
        reducer != terrain::Reducer::kLowest) {
        return Status(StatusCode::kInvalidConfig, "products.reducer: must be kHighest, kMean or kLowest",
                      static_cast<std::int64_t>(reducer));
    }
    const std::int32_t deepest = (octree.max_depth < kMaxProductLevel) ? octree.max_depth : kMaxProductLevel;
    for (std::int32_t p = 0; p < count; ++p) {
        const std::int32_t l = levels[static_cast<std::size_t>(p)];
        const bool increasing = (p == 0) || l > levels[static_cast<std::size_t>(p - 1)];
        if (l < 0 || l > deepest || !increasing) {
            return Status(StatusCode::kInvalidConfig,
                          "products.levels: each 0..min(max_depth, 12), strictly increasing", l);
        }
    }
    return Status::ok();
}

std::size_t HeightProducts::workspaceBytes(const ProductConfig& products, const OctreeConfig& octree) noexcept {
    if (!products.validate(octree).isOk()) {
        return 0U;
    }
    std::size_t bytes = 0U;
    for (std::int32_t p = 0; p < products.count; ++p) {
        const std::int32_t l = products.levels[static_cast<std::size_t>(p)];
        const std::size_t n = binsOf(l);
        bytes += terrain::HeightMap::workspaceBytes(mapConfig(octree, l, products.reducer));
        bytes += Arena::arrayBytes<std::uint8_t>(n) + Arena::arrayBytes<std::uint16_t>(n);
    }
    return bytes;
}

Status HeightProducts::init(const ProductConfig& products, const OctreeConfig& octree, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(products.validate(octree));
    for (std::int32_t i = 0; i < products.count; ++i) {
        Product& p = products_[static_cast<std::size_t>(i)];
        p.level = products.levels[static_cast<std::size_t>(i)];
        VTM_RETURN_IF_ERROR(p.map.init(mapConfig(octree, p.level, products.reducer), arena));
        const std::size_t n = binsOf(p.level);
        p.data_level = arena.allocateArray<std::uint8_t>(n);
        p.sources = arena.allocateArray<std::uint16_t>(n);
        if (p.data_level.size() != n || p.sources.size() != n) {
            return Status(StatusCode::kOutOfMemory, "height products: arena too small",
                          static_cast<std::int64_t>(workspaceBytes(products, octree)));
        }
        clearProduct(p);
    }
    config_ = products;
    octree_ = octree;
    initialized_ = true;
    return Status::ok();
}

Status HeightProducts::extract(const Octree& tree) noexcept {
    if (!initialized_ || !tree.initialized()) {
        return Status(StatusCode::kNotInitialized, "height products: extract before init (products or octree)");
    }
    if (!sameCube(tree.config(), octree_)) {
        return Status(StatusCode::kSizeMismatch, "height products: octree root cube or max_depth differs from init");
    }
    stats_ = ExtractStats{};
    for (std::int32_t i = 0; i < config_.count; ++i) {
        Product& p = products_[static_cast<std::size_t>(i)];
        clearProduct(p);
        addFineNodes(p, tree);
        for (std::int32_t l = p.level - 1; l >= 0; --l) {  // finest coarse level first
            if (tree.stats().inserted_at_level[l] > 0) {
                fillFromLevel(p, tree, l);
            }
        }
    }
    return Status::ok();
}

void HeightProducts::clearProduct(Product& p) noexcept {
    p.map.clear();
    for (std::size_t k = 0; k < p.data_level.size(); ++k) {
        p.data_level[k] = kNoLevel;
        p.sources[k] = 0U;
    }
}

void HeightProducts::write(Product& p, const OctreeNode& node, std::uint32_t col, std::uint32_t row_from_south,
                           std::uint8_t data_level) noexcept {
    const std::uint32_t side = 1U << static_cast<std::uint32_t>(p.level);
    const auto c = static_cast<std::int32_t>(col);
    const auto r = static_cast<std::int32_t>(side - 1U - row_from_south);
    terrain::CellSummary s;
    s.highest_m = node.highest_m;
    s.lowest_m = node.lowest_m;
    s.sum_m = static_cast<float>(node.sum_m);
    s.count = node.count;
    const Status merged = p.map.mergeCell(c, r, s);
    VTM_ASSERT(merged.isOk(), c, r);  // keys at this level are inside the grid by construction
    const std::size_t k = static_cast<std::size_t>(r) * side + col;
    p.data_level[k] = data_level;
    p.sources[k] = static_cast<std::uint16_t>(p.sources[k] | node.sources);
}

void HeightProducts::addFineNodes(Product& p, const Octree& tree) noexcept {
    const std::uint32_t used = tree.nodeCount();
    for (std::uint32_t i = 0; i < used; ++i) {
        const OctreeNode& n = tree.node(i);
        if (n.count == 0U || n.level < p.level) {
            continue;
        }
        const auto shift = static_cast<std::uint32_t>(n.level - p.level);
        write(p, n, n.key_y >> shift, n.key_x >> shift, static_cast<std::uint8_t>(p.level));
        ++stats_.fine_writes;
    }
    stats_.node_visits += used;
}

void HeightProducts::fillFromLevel(Product& p, const Octree& tree, std::int32_t coarse) noexcept {
    const std::uint32_t used = tree.nodeCount();
    const auto shift = static_cast<std::uint32_t>(p.level - coarse);
    const std::uint32_t span = 1U << shift;  // bins a side under one coarse cell
    const std::uint32_t side = 1U << static_cast<std::uint32_t>(p.level);
    const auto mark = static_cast<std::uint8_t>(coarse);
    for (std::uint32_t i = 0; i < used; ++i) {
        const OctreeNode& n = tree.node(i);
        if (n.count == 0U || n.level != coarse) {
            continue;
        }
        for (std::uint32_t dr = 0; dr < span; ++dr) {
            const std::uint32_t rs = (n.key_x << shift) + dr;
            for (std::uint32_t dc = 0; dc < span; ++dc) {
                const std::uint32_t col = (n.key_y << shift) + dc;
                const std::uint8_t have = p.data_level[static_cast<std::size_t>(side - 1U - rs) * side + col];
                if (have == kNoLevel || have == mark) {  // empty, or filled by this same level
                    write(p, n, col, rs, mark);
                    ++stats_.coarse_writes;
                }
            }
        }
    }
    stats_.node_visits += used;
}

std::int32_t HeightProducts::level(std::int32_t product) const noexcept {
    VTM_ASSERT(product >= 0 && product < config_.count, product);
    return products_[static_cast<std::size_t>((product >= 0 && product < kMaxProducts) ? product : 0)].level;
}

const terrain::HeightMap& HeightProducts::map(std::int32_t product) const noexcept {
    VTM_ASSERT(product >= 0 && product < config_.count, product);
    return products_[static_cast<std::size_t>((product >= 0 && product < kMaxProducts) ? product : 0)].map;
}

std::size_t HeightProducts::binIndex(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept {
    const bool ok = initialized_ && product >= 0 && product < config_.count;
    VTM_ASSERT(ok, product);
    const Product& p = products_[static_cast<std::size_t>(ok ? product : 0)];
    const std::int32_t side = 1 << p.level;
    const bool inside = col >= 0 && col < side && row >= 0 && row < side;
    VTM_ASSERT(inside, col, row);
    return inside ? static_cast<std::size_t>(row) * static_cast<std::size_t>(side) + static_cast<std::size_t>(col) : 0U;
}

std::uint8_t HeightProducts::dataLevel(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = binIndex(product, col, row);
    return products_[static_cast<std::size_t>((product >= 0 && product < kMaxProducts) ? product : 0)].data_level[k];
}

std::uint16_t HeightProducts::sources(std::int32_t product, std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = binIndex(product, col, row);
    return products_[static_cast<std::size_t>((product >= 0 && product < kMaxProducts) ? product : 0)].sources[k];
}

}  // namespace vtm::octree
