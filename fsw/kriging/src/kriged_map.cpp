// KrigedMap: elevation, kriging variance and reason per node of a terrain grid.
#include "vtm/core/assert.hpp"
#include "vtm/kriging/kriged_map.hpp"

namespace vtm::kriging {

std::size_t KrigedMap::workspaceBytes(const terrain::GridConfig& grid) noexcept {
    if (!grid.validate().isOk()) {
        return 0U;
    }
    const std::size_t n = static_cast<std::size_t>(grid.cols) * static_cast<std::size_t>(grid.rows);
    return 2U * Arena::arrayBytes<float>(n) + Arena::arrayBytes<NodeReason>(n);
}

Status KrigedMap::init(const terrain::GridConfig& grid, Arena& arena) noexcept {
    VTM_RETURN_IF_ERROR(grid.validate());
    const std::size_t n = static_cast<std::size_t>(grid.cols) * static_cast<std::size_t>(grid.rows);
    elevation_ = arena.allocateArray<float>(n);
    variance_ = arena.allocateArray<float>(n);
    reason_ = arena.allocateArray<NodeReason>(n);
    if (elevation_.size() != n || variance_.size() != n || reason_.size() != n) {
        return Status(StatusCode::kOutOfMemory, "kriged map: arena smaller than workspaceBytes(grid)",
                      static_cast<std::int64_t>(n));
    }
    grid_ = grid;
    capacity_ = n;
    cells_ = n;
    initialized_ = true;
    clear();
    return Status::ok();
}

Status KrigedMap::setGrid(const terrain::GridConfig& grid) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriged map: setGrid before init");
    }
    VTM_RETURN_IF_ERROR(grid.validate());
    const std::size_t n = static_cast<std::size_t>(grid.cols) * static_cast<std::size_t>(grid.rows);
    if (n > capacity_) {
        return Status(StatusCode::kSizeMismatch, "kriged map: grid cols * rows exceeds the init grid's",
                      static_cast<std::int64_t>(n));
    }
    grid_ = grid;
    cells_ = n;
    clear();
    return Status::ok();
}

void KrigedMap::clear() noexcept {
    for (std::size_t k = 0; k < cells_; ++k) {
        elevation_[k] = terrain::kNoData;
        variance_[k] = terrain::kNoData;
        reason_[k] = NodeReason::kNoSamples;
    }
}

std::size_t KrigedMap::index(std::int32_t col, std::int32_t row) const noexcept {
    const bool inside = initialized_ && col >= 0 && row >= 0 && col < grid_.cols && row < grid_.rows;
    VTM_ASSERT(inside, col, row);
    return inside ? static_cast<std::size_t>(row) * static_cast<std::size_t>(grid_.cols) +
                        static_cast<std::size_t>(col)
                  : 0U;
}

void KrigedMap::setNode(std::int32_t col, std::int32_t row, float elevation_m, float variance_m2,
                        NodeReason reason) noexcept {
    const std::size_t k = index(col, row);
    const bool estimated = reason == NodeReason::kEstimated;
    elevation_[k] = estimated ? elevation_m : terrain::kNoData;
    variance_[k] = estimated ? variance_m2 : terrain::kNoData;
    reason_[k] = reason;
}

float KrigedMap::elevation(std::int32_t col, std::int32_t row) const noexcept { return elevation_[index(col, row)]; }
float KrigedMap::variance(std::int32_t col, std::int32_t row) const noexcept { return variance_[index(col, row)]; }
NodeReason KrigedMap::reason(std::int32_t col, std::int32_t row) const noexcept { return reason_[index(col, row)]; }

Span<const float> KrigedMap::elevations() const noexcept {
    return initialized_ ? Span<const float>(elevation_.data(), cells_) : Span<const float>();
}

double KrigedMap::centreNorthM(std::int32_t row) const noexcept {
    return grid_.north_edge_m - (static_cast<double>(row) + 0.5) * grid_.cell_m;
}

double KrigedMap::centreEastM(std::int32_t col) const noexcept {
    return grid_.west_edge_m + (static_cast<double>(col) + 0.5) * grid_.cell_m;
}

Status KrigedMap::writeTo(terrain::HeightMap& height_map) const noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriged map: writeTo before init");
    }
    const terrain::GridConfig& g = height_map.grid();
    if (g.cols != grid_.cols || g.rows != grid_.rows || g.cell_m != grid_.cell_m ||
        g.north_edge_m != grid_.north_edge_m || g.west_edge_m != grid_.west_edge_m) {
        return Status(StatusCode::kSizeMismatch, "kriged map: height_map grid differs from the kriged grid");
    }
    for (std::int32_t row = 0; row < grid_.rows; ++row) {
        for (std::int32_t col = 0; col < grid_.cols; ++col) {
            const std::size_t k = index(col, row);
            if (reason_[k] != NodeReason::kEstimated) {
                continue;
            }
            const float h = elevation_[k];
            VTM_RETURN_IF_ERROR(height_map.mergeCell(col, row, terrain::CellSummary{h, h, h, 1U}));
        }
    }
    return Status::ok();
}

}  // namespace vtm::kriging
