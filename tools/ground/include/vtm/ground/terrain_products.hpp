// Ground-side renderings of terrain products for people: shaded relief of an elevation
// grid and PLY point clouds. Host only (heap, stdio).
#pragma once

#include <string>
#include <vector>

#include "vtm/core/eigen.hpp"
#include "vtm/ground/image.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::ground {

// The height map's elevations (HeightMap::elevation: its reducer's) as an image in the
// map's own convention, cell (col, row) at pixel (col, row): row 0 north, column 0 west,
// NaN (kNoData) where no point fell. Written to PFM or PNG as it is: north up.
FloatImage elevationImage(const terrain::HeightMap& map);

// RGB shaded relief of an elevation grid (metres, NaN = NO_DATA, row 0 north): colour by
// elevation (the disparity ramp: highest red ... lowest purple, between the 1st and 99th
// percentiles) times a Lambertian hill shade (sun from the north-west, 45 deg up; 30 %
// ambient; a missing neighbour counts as level). NO_DATA cells are black.
GreyImage shadedRelief(const FloatImage& elevation_m, double cell_m);

// The part of a grid that holds data: the bounding box of its finite cells (the grid
// itself when none is finite). For pictures of sparse maps.
FloatImage cropToFinite(const FloatImage& grid);

// Binary little-endian PLY with float x, y, z per vertex (site frame, metres).
Outcome writePly(const std::string& path, const std::vector<Vec3>& points);

}  // namespace vtm::ground
