// The occlusion test of the orthophoto: does the line of sight from a grid node to a camera's
// projection centre pass under the elevation grid's surface? (docs/kriging.md "Orthophoto")
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::kriging::detail {

struct ElevationSurface {
    terrain::GridConfig grid{};
    Span<const float> elevation_m{};  // cols * rows, row 0 north; NaN = NO_DATA
    double highest_m = 0.0;           // the largest finite elevation of the grid
};

// The highest finite elevation of the grid (-inf when every node is NO_DATA).
[[nodiscard]] double highestElevation(Span<const float> elevation_m) noexcept;

// Elevation of the surface through the node centres (bilinear) at a horizontal position;
// NaN outside the nodes' span or next to a NO_DATA node.
[[nodiscard]] double surfaceElevation(const ElevationSurface& s, double north_m, double east_m) noexcept;

// March from the node (site point, z down) towards the eye in steps of half a cell, from one
// cell away, at most 2 (cols + rows) + 2 steps: occluded when the surface lies more than
// margin_m above the line. The march stops where the line rises above the grid's highest
// node or leaves the grid.
[[nodiscard]] bool occluded(const ElevationSurface& s, const Vec3& node_site_m, const Vec3& eye_site_m,
                            double margin_m) noexcept;

}  // namespace vtm::kriging::detail
