// Height maps and orthophotos as GeoTIFF through GDAL, so that GDAL and QGIS open them
// directly (docs/geotiff.md). Host only: library vtm_ground_geotiff, never flight code.
//
// Grid: the height map's (docs/terrain.md): pixel (col, row) is cell (col, row), row 0
// north, columns east. Geotransform (x = easting, y = northing, metres):
//   (west_edge_m, cell_m, 0, north_edge_m, 0, -cell_m)
// so the file's upper-left corner is the grid's north-west corner.
//
// CRS ("VTM site frame, Mars"): transverse Mercator on the IAU 2015 Mars sphere (radius
// 3,396,190 m, planetocentric), centred on the site origin's latitude and east longitude,
// scale 1, false easting and northing 0. Easting = site y, northing = site x: within
// (d / R)^2 / 2 (4e-8 at d = 1 km from the origin) the site frame's metres. Elevation up,
// metres, relative to the site origin's level plane (not the areoid).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vtm/ground/image.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::ground {

constexpr double kMarsRadiusM = 3396190.0;  // IAU 2015 Mars sphere

// Where the site origin is on Mars: planetocentric latitude and east longitude, degrees.
struct SiteOrigin {
    double latitude_deg = 0.0;   // [-90, 90]
    double longitude_deg = 0.0;  // [-180, 360]
};

struct GeoTiffOptions {
    SiteOrigin site{};
    std::string source;  // metadata VTM_SOURCE, e.g. "vtm descent"; "" for none
};

// Extra Float32 bands after the elevation (band 1), in this order when asked for.
struct HeightMapBands {
    bool spread = false;  // highest - lowest, metres (NaN where no data)
    bool count = false;   // points in the cell (0 where no data), as Float32
};

// Writes band 1 = HeightMap::elevation (Float32, metres up; nodata NaN), then the extra
// bands; metadata VTM_SOURCE, VTM_UNITS, VTM_NO_DATA, VTM_SITE_FRAME, VTM_VERSION. Written
// to PATH.partial and renamed: a failed write leaves no file. Refused (one line naming the
// file): a map without a cell with data, a site origin out of range, an unwritable path,
// no GTiff driver in GDAL, a GDAL error.
Outcome writeHeightMapGeoTiff(const std::string& path, const terrain::HeightMap& map, const GeoTiffOptions& options,
                              const HeightMapBands& bands = {});

// Writes an 8-bit one-band orthophoto on the grid `grid` (image width = cols, height = rows,
// row 0 north). no_data: the level declared as GDAL nodata, if any.
Outcome writeOrthophotoGeoTiff(const std::string& path, const GreyImage& image, const terrain::GridConfig& grid,
                               const GeoTiffOptions& options, std::optional<std::uint8_t> no_data = std::nullopt);

// The elevation band of a GeoTIFF that writeHeightMapGeoTiff wrote (or any file of the same
// kind: band 1 Float32 with nodata NaN, north up, square cells, the CRS above).
struct ElevationGeoTiff {
    terrain::GridConfig grid;
    FloatImage elevation_m;  // cell (col, row) at pixel (col, row); NaN = NO_DATA
    SiteOrigin site;
};

// Refused, naming the file and the reason: not a GeoTIFF, band 1 not Float32, nodata not
// NaN, a rotated, flipped or non-square geotransform, more than terrain::kMaxGridSide
// cells a side, a CRS other than the VTM site frame's (projection, sphere, scale, offsets).
Result<ElevationGeoTiff> readElevationGeoTiff(const std::string& path);

}  // namespace vtm::ground
