// Height map on a fixed grid in the site frame (paper §6): each cell keeps the HIGHEST
// point that fell in it (the paper's "largest z" with z up; the site frame's z points down,
// so the highest point is the smallest site z), the lowest one, and the count; spread =
// highest - lowest. Cells without points are NO_DATA. Successive maps of the same grid merge
// cell by cell (max of highs, min of lows, counts added), so merging is exact: a map built
// from two point sets equals the merge of the maps of each set, bit for bit.
//
// Grid: cell (col, row) covers north in [origin_north + row * cell, + cell) and east in
// [origin_east + col * cell, + cell): row grows northwards, col eastwards (a picture of the
// map shows north up after flipping rows). Storage from an Arena at init; adding points and
// merging never allocate.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::terrain {

// Elevation of a cell without points.
constexpr float kNoData = -3.0e38F;

struct GridConfig {
    double origin_north_m = 0.0;  // south-west corner of cell (0, 0)
    double origin_east_m = 0.0;
    double cell_m = 0.1;          // (0, 100]
    std::int32_t cols = 256;      // east, 1..2048
    std::int32_t rows = 256;      // north, 1..2048
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

struct HeightMapStats {
    std::int64_t added = 0;    // points that fell in the grid
    std::int64_t outside = 0;  // points outside it (or non-finite)
};

class HeightMap {
public:
    // Bytes of arena for this grid: 10 bytes per cell plus alignment.
    [[nodiscard]] static std::size_t workspaceBytes(const GridConfig& config) noexcept;
    // kInvalidConfig or kOutOfMemory. The map starts empty.
    [[nodiscard]] Status init(const GridConfig& config, Arena& arena) noexcept;
    // Empties every cell (keeps the grid).
    void clear() noexcept;

    // Adds points (site frame). Points outside the grid are counted, not an error.
    // kNotInitialized before init.
    [[nodiscard]] Status add(Span<const TerrainPoint> points, HeightMapStats* stats = nullptr) noexcept;
    // Merges another map of the SAME grid (every GridConfig field equal: kSizeMismatch
    // otherwise) into this one.
    [[nodiscard]] Status merge(const HeightMap& other) noexcept;

    // Cell access (col < cols, row < rows: VTM_ASSERT). Elevations up, metres (= -site z).
    [[nodiscard]] float highest(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] float lowest(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] std::uint16_t count(std::int32_t col, std::int32_t row) const noexcept;  // saturates at 65535
    [[nodiscard]] float spread(std::int32_t col, std::int32_t row) const noexcept;  // kNoData when empty
    [[nodiscard]] std::int32_t filledCells() const noexcept;
    [[nodiscard]] const GridConfig& grid() const noexcept { return config_; }

private:
    [[nodiscard]] std::size_t index(std::int32_t col, std::int32_t row) const noexcept;
    GridConfig config_{};
    bool initialized_ = false;
    Span<float> high_{};
    Span<float> low_{};
    Span<std::uint16_t> count_{};
};

}  // namespace vtm::terrain
