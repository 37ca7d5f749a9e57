// The kriged elevation grid: elevation and kriging variance per node, on fsw/terrain's grid
// convention (GridConfig; docs/terrain.md "Height map"): node (col, row) is the centre of
// cell (col, row), row 0 north, column 0 west. NO_DATA nodes read terrain::kNoData (NaN)
// and carry a reason.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::kriging {

// Per node. Stable values (telemetry).
enum class NodeReason : std::uint8_t {
    kEstimated = 0,
    kNoSamples = 1,  // no sample within search_radius_m
    kSingular = 2,   // the kriging system had no solution (samples at one position)
};

class KrigedMap {
public:
    // Per node 4 (elevation, float) + 4 (variance, float) + 1 (reason) bytes, each array
    // padded to the arena's block; 0 for an invalid grid.
    [[nodiscard]] static std::size_t workspaceBytes(const terrain::GridConfig& grid) noexcept;
    // kInvalidConfig naming the grid field, kOutOfMemory. Every node starts kNoSamples.
    [[nodiscard]] Status init(const terrain::GridConfig& grid, Arena& arena) noexcept;
    // Moves to another grid of at most the init grid's nodes and empties every node.
    // kNotInitialized, kInvalidConfig, kSizeMismatch beyond the capacity (map unchanged).
    [[nodiscard]] Status setGrid(const terrain::GridConfig& grid) noexcept;
    void clear() noexcept;
    // Writes one node (0 <= col < cols, 0 <= row < rows: VTM_ASSERT). NaN values unless
    // reason == kEstimated.
    void setNode(std::int32_t col, std::int32_t row, float elevation_m, float variance_m2, NodeReason reason) noexcept;

    [[nodiscard]] float elevation(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] float variance(std::int32_t col, std::int32_t row) const noexcept;
    [[nodiscard]] NodeReason reason(std::int32_t col, std::int32_t row) const noexcept;
    // Row-major (row 0 north) elevations of the current grid: cols * rows values, the input
    // of buildOrthophoto().
    [[nodiscard]] Span<const float> elevations() const noexcept;
    [[nodiscard]] double centreNorthM(std::int32_t row) const noexcept;
    [[nodiscard]] double centreEastM(std::int32_t col) const noexcept;
    [[nodiscard]] const terrain::GridConfig& grid() const noexcept { return grid_; }

    // Writes every estimated node into a terrain::HeightMap of the same grid (kSizeMismatch
    // otherwise) as a one-point cell (mergeCell), so the products of a HeightMap (elevation
    // images, GeoTIFF) take the kriged map. kNotInitialized.
    [[nodiscard]] Status writeTo(terrain::HeightMap& height_map) const noexcept;

private:
    [[nodiscard]] std::size_t index(std::int32_t col, std::int32_t row) const noexcept;
    terrain::GridConfig grid_{};
    std::size_t capacity_ = 0U;
    std::size_t cells_ = 0U;
    bool initialized_ = false;
    Span<float> elevation_{};
    Span<float> variance_{};
    Span<NodeReason> reason_{};
};

}  // namespace vtm::kriging
