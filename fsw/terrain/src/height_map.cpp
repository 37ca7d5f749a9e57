#include "vtm/terrain/height_map.hpp"

#include <cmath>

#include "vtm/core/assert.hpp"
#include "vtm/core/math.hpp"

namespace vtm::terrain {
namespace {

constexpr std::uint16_t kMaxCount = 65535U;

std::size_t cellCount(const GridConfig& c) noexcept {
    return static_cast<std::size_t>(c.cols) * static_cast<std::size_t>(c.rows);
}

bool sameGrid(const GridConfig& a, const GridConfig& b) noexcept {
    return a.north_edge_m == b.north_edge_m && a.west_edge_m == b.west_edge_m && a.cell_m == b.cell_m &&
           a.cols == b.cols && a.rows == b.rows;
}

}  // namespace

Status GridConfig::validate() const noexcept {
    if (!math::isFinite(north_edge_m) || !math::isFinite(west_edge_m)) {
        return Status(StatusCode::kInvalidConfig, "height map: grid north_edge_m and west_edge_m must be finite");
    }
    if (!(cell_m > 0.0) || !(cell_m <= 1.0e4)) {
        return Status(StatusCode::kInvalidConfig, "height map: grid cell_m must be in (0, 1e4]");
    }
    if (cols < 1 || cols > kMaxGridSide) {
        return Status(StatusCode::kInvalidConfig, "height map: grid cols must be 1..4096", cols);
    }
    if (rows < 1 || rows > kMaxGridSide) {
        return Status(StatusCode::kInvalidConfig, "height map: grid rows must be 1..4096", rows);
    }
    return Status::ok();
}

Status HeightMapConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(grid.validate());
    if (reducer != Reducer::kHighest && reducer != Reducer::kMean && reducer != Reducer::kLowest) {
        return Status(StatusCode::kInvalidConfig, "height map: reducer must be kHighest, kMean or kLowest",
                      static_cast<std::int64_t>(reducer));
    }
    return Status::ok();
}

std::size_t HeightMap::workspaceBytes(const HeightMapConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t n = cellCount(config.grid);
    const std::size_t floats = (config.reducer == Reducer::kMean) ? 3U : 2U;
    return Arena::blockBytes(n * sizeof(float)) * floats + Arena::blockBytes(n * sizeof(std::uint16_t));
}

Status HeightMap::init(const HeightMapConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t n = cellCount(config.grid);
    const bool mean = config.reducer == Reducer::kMean;
    high_ = arena.allocateArray<float>(n);
    low_ = arena.allocateArray<float>(n);
    sum_ = mean ? arena.allocateArray<float>(n) : Span<float>();
    count_ = arena.allocateArray<std::uint16_t>(n);
    if (high_.size() != n || low_.size() != n || count_.size() != n || (mean && sum_.size() != n)) {
        return Status(StatusCode::kOutOfMemory, "height map: arena too small for the grid",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    capacity_ = n;
    reducer_ = config.reducer;
    initialized_ = true;
    return setGrid(config.grid);
}

Status HeightMap::setGrid(const GridConfig& grid) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: setGrid before init");
    }
    VTM_RETURN_IF_ERROR(grid.validate());
    const std::size_t n = cellCount(grid);
    if (n > capacity_) {
        return Status(StatusCode::kSizeMismatch, "height map: grid cols * rows exceeds the capacity (init grid)",
                      static_cast<std::int64_t>(n));
    }
    grid_ = grid;
    cells_ = n;
    south_edge_m_ = grid.north_edge_m - static_cast<double>(grid.rows) * grid.cell_m;
    clear();
    return Status::ok();
}

void HeightMap::clear() noexcept {
    for (std::size_t i = 0; i < cells_; ++i) {
        high_[i] = kNoData;
        low_[i] = kNoData;
        count_[i] = 0U;
    }
    for (std::size_t i = 0; i < cells_ && i < sum_.size(); ++i) {
        sum_[i] = 0.0F;
    }
}

std::size_t HeightMap::index(std::int32_t col, std::int32_t row) const noexcept {
    VTM_ASSERT(initialized_ && col >= 0 && col < grid_.cols && row >= 0 && row < grid_.rows, col, row);
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(grid_.cols) + static_cast<std::size_t>(col);
}

void HeightMap::bin(double north_m, double east_m, double down_m, HeightMapStats& stats) noexcept {
    // floor of the cell coordinate; the range check is done in double so that a far point
    // cannot overflow the integer conversion. Rows are counted from the south edge here.
    const double fc = math::floor((east_m - grid_.west_edge_m) / grid_.cell_m);
    const double fs = math::floor((north_m - south_edge_m_) / grid_.cell_m);
    const bool inside = fc >= 0.0 && fc < static_cast<double>(grid_.cols) && fs >= 0.0 &&
                        fs < static_cast<double>(grid_.rows) && math::isFinite(down_m);
    if (!inside) {
        ++stats.outside;
        return;
    }
    const std::int32_t row = grid_.rows - 1 - static_cast<std::int32_t>(fs);
    const std::size_t k = index(static_cast<std::int32_t>(fc), row);
    const auto up = static_cast<float>(-down_m);
    const std::uint16_t n = count_[k];
    if (n == 0U) {
        high_[k] = up;
        low_[k] = up;
    } else {
        high_[k] = (up > high_[k]) ? up : high_[k];
        low_[k] = (up < low_[k]) ? up : low_[k];
    }
    if (n < kMaxCount) {  // a saturated cell keeps the mean of its first 65535 points
        if (!sum_.empty()) {
            sum_[k] += up;
        }
        count_[k] = static_cast<std::uint16_t>(n + 1U);
    }
    ++stats.added;
}

Status HeightMap::add(Span<const TerrainPoint> points, HeightMapStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: add before init");
    }
    HeightMapStats local;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const TerrainPoint& p = points[i];
        bin(static_cast<double>(p.x_m), static_cast<double>(p.y_m), static_cast<double>(p.z_m), local);
    }
    if (stats != nullptr) {
        stats->added += local.added;
        stats->outside += local.outside;
    }
    return Status::ok();
}

Status HeightMap::add(const Vec3& site_m, HeightMapStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: add before init");
    }
    HeightMapStats local;
    bin(site_m.x(), site_m.y(), site_m.z(), local);
    if (stats != nullptr) {
        stats->added += local.added;
        stats->outside += local.outside;
    }
    return Status::ok();
}

Status HeightMap::add(Span<const Vec3> sites_m, HeightMapStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: add before init");
    }
    HeightMapStats local;
    for (std::size_t i = 0; i < sites_m.size(); ++i) {
        const Vec3& p = sites_m[i];
        bin(p.x(), p.y(), p.z(), local);
    }
    if (stats != nullptr) {
        stats->added += local.added;
        stats->outside += local.outside;
    }
    return Status::ok();
}

Status HeightMap::merge(const HeightMap& other) noexcept {
    if (!initialized_ || !other.initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: merge with a map before init");
    }
    if (!sameGrid(grid_, other.grid_) || reducer_ != other.reducer_) {
        return Status(StatusCode::kSizeMismatch, "height map: merge of maps on different grids or reducers");
    }
    for (std::size_t k = 0; k < cells_; ++k) {
        CellSummary part;
        part.highest_m = other.high_[k];
        part.lowest_m = other.low_[k];
        part.sum_m = other.sum_.empty() ? 0.0F : other.sum_[k];
        part.count = other.count_[k];
        mergeSummary(k, part);
    }
    return Status::ok();
}

Status HeightMap::mergeCell(std::int32_t col, std::int32_t row, const CellSummary& summary) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: mergeCell before init");
    }
    if (col < 0 || col >= grid_.cols || row < 0 || row >= grid_.rows) {
        return Status(StatusCode::kInvalidArgument, "height map: mergeCell col/row outside the grid", col);
    }
    mergeSummary(index(col, row), summary);
    return Status::ok();
}

void HeightMap::mergeSummary(std::size_t k, const CellSummary& summary) noexcept {
    const std::uint32_t n = summary.count;
    if (n == 0U) {
        return;
    }
    if (count_[k] == 0U) {
        high_[k] = summary.highest_m;
        low_[k] = summary.lowest_m;
    } else {
        high_[k] = (summary.highest_m > high_[k]) ? summary.highest_m : high_[k];
        low_[k] = (summary.lowest_m < low_[k]) ? summary.lowest_m : low_[k];
    }
    const std::uint64_t total = static_cast<std::uint64_t>(count_[k]) + n;
    if (!sum_.empty()) {
        const float sum = sum_[k] + summary.sum_m;
        sum_[k] = (total <= kMaxCount) ? sum : (sum / static_cast<float>(total)) * static_cast<float>(kMaxCount);
    }
    count_[k] = (total < kMaxCount) ? static_cast<std::uint16_t>(total) : kMaxCount;
}

float HeightMap::elevation(std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = index(col, row);
    if (count_[k] == 0U) {
        return kNoData;
    }
    switch (reducer_) {
        case Reducer::kHighest: return high_[k];
        case Reducer::kLowest: return low_[k];
        case Reducer::kMean: return sum_[k] / static_cast<float>(count_[k]);
    }
    return kNoData;
}

float HeightMap::highest(std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = index(col, row);
    return (count_[k] == 0U) ? kNoData : high_[k];
}

float HeightMap::lowest(std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = index(col, row);
    return (count_[k] == 0U) ? kNoData : low_[k];
}

std::uint16_t HeightMap::count(std::int32_t col, std::int32_t row) const noexcept { return count_[index(col, row)]; }

float HeightMap::spread(std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = index(col, row);
    return (count_[k] == 0U) ? kNoData : high_[k] - low_[k];
}

double HeightMap::centreNorthM(std::int32_t row) const noexcept {
    return grid_.north_edge_m - (static_cast<double>(row) + 0.5) * grid_.cell_m;
}

double HeightMap::centreEastM(std::int32_t col) const noexcept {
    return grid_.west_edge_m + (static_cast<double>(col) + 0.5) * grid_.cell_m;
}

std::int32_t HeightMap::filledCells() const noexcept {
    std::int32_t n = 0;
    for (std::size_t k = 0; k < cells_; ++k) {
        n += (count_[k] != 0U) ? 1 : 0;
    }
    return n;
}

}  // namespace vtm::terrain
