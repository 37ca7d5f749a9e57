// The height map: the one elevation product of every executive (paper §6; docs/terrain.md
// "Height map"). Site-frame points (x north, y east, z down) are binned into a fixed grid;
// each cell reduces its points to one elevation (up = -site z, metres) by the reducer the
// configuration chooses, and keeps its highest and lowest point and its count whatever
// the reducer.
//
// Grid convention (the only one; docs/terrain.md states it too):
//   - origin: the grid's NORTH-WEST corner (GridConfig::north_edge_m, west_edge_m);
//   - row 0 is the northern row, rows run SOUTH; column 0 is the western column, columns
//     run EAST: a picture of the map with row 0 at the top shows north up, east right,
//     with no flipping;
//   - cell (col, row) covers east [west_edge + col * cell, + cell) and north
//     [north_edge - (row + 1) * cell, north_edge - row * cell): a cell includes its
//     south and west edges. In arithmetic: south_edge = north_edge - rows * cell (double,
//     once per grid), a point's row counted from the south is floor((north - south_edge)
//     / cell) and row = rows - 1 - that; col = floor((east - west_edge) / cell);
//   - NO_DATA: a cell without points reads kNoData (a quiet NaN) from elevation(),
//     highest(), lowest() and spread(), and 0 from count().
// Reducers: kHighest (the paper's "largest z" with z up: a rock's top, not the ground
// under an overhang), kMean (points added while count < 65535, sum in float in the order
// they came, divided by the count when read), kLowest.
// Storage from an Arena at init (workspaceBytes); adding points, regridding and merging
// never allocate. Only + - * / and floor: the same bits on every target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::terrain {

// What every accessor returns for a cell without points (test with isNoData()).
constexpr float kNoData = std::numeric_limits<float>::quiet_NaN();
[[nodiscard]] constexpr bool isNoData(float elevation_m) noexcept { return !(elevation_m == elevation_m); }

// Largest grid side, cells.
constexpr std::int32_t kMaxGridSide = 4096;

// How a cell's points become its elevation. Values are stable (telemetry).
enum class Reducer : std::uint8_t {
    kHighest = 0,  // largest elevation (paper §6)
    kMean = 1,     // mean elevation
    kLowest = 2,   // smallest elevation
};

// The grid in the site frame (convention above).
struct GridConfig {
    double north_edge_m = 25.6;  // north edge of row 0 (the grid's north-west corner)
    double west_edge_m = 0.0;    // west edge of column 0
    double cell_m = 0.1;         // (0, 1e4]
    std::int32_t cols = 256;     // east, 1..kMaxGridSide
    std::int32_t rows = 256;     // south, 1..kMaxGridSide
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

struct HeightMapConfig {
    // The grid at init; its cols * rows is the map's capacity (setGrid may change the grid
    // within it).
    GridConfig grid{};
    Reducer reducer = Reducer::kHighest;
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

// The statistics of some points that fall in one cell, already reduced (the octree's
// nodes, fsw/octree): elevations up, metres; sum_m is the sum of the elevations the mean
// is made of (read with kMean only). count 0 means no points.
struct CellSummary {
    float highest_m = kNoData;
    float lowest_m = kNoData;
    float sum_m = 0.0F;
    std::uint32_t count = 0U;
};

struct HeightMapStats {
    std::int64_t added = 0;    // points that fell in the grid
    std::int64_t outside = 0;  // points outside it (or non-finite)
};

class HeightMap {
public:
    // Bytes of arena for this configuration: per cell 4 (highest) + 4 (lowest) + 2 (count)
    // bytes, + 4 (sum) with kMean, plus alignment; 0 if the configuration is invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const HeightMapConfig& config) noexcept;
    // kInvalidConfig or kOutOfMemory. The map starts empty.
    [[nodiscard]] Status init(const HeightMapConfig& config, Arena& arena) noexcept;
    // Moves the map to another grid of at most the init grid's cells (an executive that
    // maps under its camera each request) and empties it. kNotInitialized; kInvalidConfig
    // naming the field; kSizeMismatch when cols * rows exceeds the capacity. A refused
    // grid leaves the map as it was.
    [[nodiscard]] Status setGrid(const GridConfig& grid) noexcept;
    // Empties every cell (keeps the grid).
    void clear() noexcept;

    // Adds points (site frame). Points outside the grid or not finite are counted, not an
    // error. kNotInitialized before init.
    [[nodiscard]] Status add(Span<const TerrainPoint> points, HeightMapStats* stats = nullptr) noexcept;
    // Adds one site point given in double (x north, y east, z down): the same binning and
    // reduction as add() (a TerrainPoint is this with its floats widened). kNotInitialized.
    [[nodiscard]] Status add(const Vec3& site_m, HeightMapStats* stats = nullptr) noexcept;
    // The same for a span of double site points, in order.
    [[nodiscard]] Status add(Span<const Vec3> sites_m, HeightMapStats* stats = nullptr) noexcept;
    // Merges another map of the SAME grid and reducer (kSizeMismatch otherwise) into this
    // one: max of the highs, min of the lows, counts added (saturating), and with kMean
    // the sums added (when the counts saturate, the sum becomes the merged mean times
    // 65535). Highest and lowest merge exactly (a map merged from parts equals the map of
    // all points bit for bit); a mean only up to float rounding.
    [[nodiscard]] Status merge(const HeightMap& other) noexcept;
    // Merges a summary into cell (col, row) by the same rule as merge() (a summary of
    // count 0 changes nothing): how a producer that has already reduced its points writes
    // cell statistics directly. kNotInitialized; kInvalidArgument for a cell outside the
    // grid (nothing changed).
    [[nodiscard]] Status mergeCell(std::int32_t col, std::int32_t row, const CellSummary& summary) noexcept;

    // Cell access (0 <= col < cols, 0 <= row < rows: VTM_ASSERT). Elevations up, metres
    // (= -site z); kNoData for a cell without points.
    [[nodiscard]] float elevation(std::int32_t col, std::int32_t row) const noexcept;  // the reducer's
    [[nodiscard]] float highest(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] float lowest(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] float spread(std::int32_t col, std::int32_t row) const noexcept;  // highest - lowest
    [[nodiscard]] std::uint16_t count(std::int32_t col, std::int32_t row) const noexcept;  // saturates at 65535
    // Site coordinates of a cell's centre: north_edge - (row + 0.5) cell, west_edge + (col + 0.5) cell.
    [[nodiscard]] double centreNorthM(std::int32_t row) const noexcept;
    [[nodiscard]] double centreEastM(std::int32_t col) const noexcept;
    [[nodiscard]] std::int32_t filledCells() const noexcept;
    [[nodiscard]] const GridConfig& grid() const noexcept { return grid_; }
    [[nodiscard]] Reducer reducer() const noexcept { return reducer_; }

private:
    [[nodiscard]] std::size_t index(std::int32_t col, std::int32_t row) const noexcept;
    void bin(double north_m, double east_m, double down_m, HeightMapStats& stats) noexcept;
    void mergeSummary(std::size_t k, const CellSummary& summary) noexcept;
    GridConfig grid_{};
    double south_edge_m_ = 0.0;  // north_edge_m - rows * cell_m
    std::size_t capacity_ = 0U;  // cells
    std::size_t cells_ = 0U;     // cols * rows of the current grid
    Reducer reducer_ = Reducer::kHighest;
    bool initialized_ = false;
    Span<float> high_{};
    Span<float> low_{};
    Span<float> sum_{};  // kMean only
    Span<std::uint16_t> count_{};
};

}  // namespace vtm::terrain
