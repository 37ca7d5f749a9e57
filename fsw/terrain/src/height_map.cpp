#include "vtm/terrain/height_map.hpp"

#include <cmath>

#include "vtm/core/assert.hpp"
#include "vtm/core/math.hpp"

namespace vtm::terrain {
namespace {

constexpr std::int32_t kMaxGridSide = 2048;
constexpr std::uint16_t kMaxCount = 65535U;

std::size_t cellCount(const GridConfig& c) noexcept {
    return static_cast<std::size_t>(c.cols) * static_cast<std::size_t>(c.rows);
}

bool sameGrid(const GridConfig& a, const GridConfig& b) noexcept {
    return a.origin_north_m == b.origin_north_m && a.origin_east_m == b.origin_east_m && a.cell_m == b.cell_m &&
           a.cols == b.cols && a.rows == b.rows;
}

}  // namespace

Status GridConfig::validate() const noexcept {
    if (!math::isFinite(origin_north_m) || !math::isFinite(origin_east_m)) {
        return Status(StatusCode::kInvalidConfig, "height map: origin_north_m and origin_east_m must be finite");
    }
    if (!(cell_m > 0.0) || !(cell_m <= 100.0)) {
        return Status(StatusCode::kInvalidConfig, "height map: cell_m must be in (0, 100]");
    }
    if (cols < 1 || cols > kMaxGridSide) {
        return Status(StatusCode::kInvalidConfig, "height map: cols must be 1..2048", cols);
    }
    if (rows < 1 || rows > kMaxGridSide) {
        return Status(StatusCode::kInvalidConfig, "height map: rows must be 1..2048", rows);
    }
    return Status::ok();
}

std::size_t HeightMap::workspaceBytes(const GridConfig& config) noexcept {
    const std::size_t n = config.validate().isOk() ? cellCount(config) : 0U;
    return Arena::blockBytes(n * sizeof(float)) * 2U + Arena::blockBytes(n * sizeof(std::uint16_t));
}

Status HeightMap::init(const GridConfig& config, Arena& arena) noexcept {
    const Status valid = config.validate();
    if (!valid.isOk()) {
        return valid;
    }
    const std::size_t n = cellCount(config);
    high_ = arena.allocateArray<float>(n);
    low_ = arena.allocateArray<float>(n);
    count_ = arena.allocateArray<std::uint16_t>(n);
    if (high_.size() != n || low_.size() != n || count_.size() != n) {
        initialized_ = false;
        return Status(StatusCode::kOutOfMemory, "height map: arena too small for the grid",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    initialized_ = true;
    clear();
    return Status::ok();
}

void HeightMap::clear() noexcept {
    for (std::size_t i = 0; i < count_.size(); ++i) {
        high_[i] = kNoData;
        low_[i] = kNoData;
        count_[i] = 0U;
    }
}

std::size_t HeightMap::index(std::int32_t col, std::int32_t row) const noexcept {
    VTM_ASSERT(initialized_ && col >= 0 && col < config_.cols && row >= 0 && row < config_.rows, col, row);
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(config_.cols) + static_cast<std::size_t>(col);
}

Status HeightMap::add(Span<const TerrainPoint> points, HeightMapStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "height map: add before init");
    }
    HeightMapStats local;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const TerrainPoint& p = points[i];
        // floor of the cell coordinate; the range check is done in double so that a far
        // point cannot overflow the integer conversion.
        const double fc = std::floor((static_cast<double>(p.y_m) - config_.origin_east_m) / config_.cell_m);
        const double fr = std::floor((static_cast<double>(p.x_m) - config_.origin_north_m) / config_.cell_m);
        const bool inside = fc >= 0.0 && fc < static_cast<double>(config_.cols) && fr >= 0.0 &&
                            fr < static_cast<double>(config_.rows) && math::isFinite(static_cast<double>(p.z_m));
        if (!inside) {
            ++local.outside;
            continue;
        }
        const std::size_t k = index(static_cast<std::int32_t>(fc), static_cast<std::int32_t>(fr));
        const float up = -p.z_m;
        if (count_[k] == 0U) {
            high_[k] = up;
            low_[k] = up;
        } else {
            high_[k] = (up > high_[k]) ? up : high_[k];
            low_[k] = (up < low_[k]) ? up : low_[k];
        }
        count_[k] = (count_[k] < kMaxCount) ? static_cast<std::uint16_t>(count_[k] + 1U) : kMaxCount;
        ++local.added;
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
    if (!sameGrid(config_, other.config_)) {
        return Status(StatusCode::kSizeMismatch, "height map: merge of maps on different grids");
    }
    for (std::size_t k = 0; k < count_.size(); ++k) {
        const std::uint16_t n = other.count_[k];
        if (n == 0U) {
            continue;
        }
        if (count_[k] == 0U) {
            high_[k] = other.high_[k];
            low_[k] = other.low_[k];
        } else {
            high_[k] = (other.high_[k] > high_[k]) ? other.high_[k] : high_[k];
            low_[k] = (other.low_[k] < low_[k]) ? other.low_[k] : low_[k];
        }
        const std::uint32_t sum = static_cast<std::uint32_t>(count_[k]) + n;
        count_[k] = (sum < kMaxCount) ? static_cast<std::uint16_t>(sum) : kMaxCount;
    }
    return Status::ok();
}

float HeightMap::highest(std::int32_t col, std::int32_t row) const noexcept { return high_[index(col, row)]; }
float HeightMap::lowest(std::int32_t col, std::int32_t row) const noexcept { return low_[index(col, row)]; }
std::uint16_t HeightMap::count(std::int32_t col, std::int32_t row) const noexcept { return count_[index(col, row)]; }

float HeightMap::spread(std::int32_t col, std::int32_t row) const noexcept {
    const std::size_t k = index(col, row);
    return (count_[k] == 0U) ? kNoData : high_[k] - low_[k];
}

std::int32_t HeightMap::filledCells() const noexcept {
    std::int32_t n = 0;
    for (std::size_t k = 0; k < count_.size(); ++k) {
        n += (count_[k] != 0U) ? 1 : 0;
    }
    return n;
}

}  // namespace vtm::terrain
