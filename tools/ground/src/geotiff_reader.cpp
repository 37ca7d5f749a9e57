// readElevationGeoTiff (geotiff.hpp): the elevation band and the grid of a VTM GeoTIFF.
#include <gdal_priv.h>

#include <cmath>
#include <memory>

#include "gdal_session.hpp"
#include "geotiff_crs.hpp"
#include "vtm/ground/geotiff.hpp"

namespace vtm::ground {
namespace {

using Elevation = Result<ElevationGeoTiff>;

struct DatasetCloser {
    void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

// The grid from the raster size and geotransform; "" or what is refused.
std::string gridOf(GDALDataset& ds, terrain::GridConfig& grid) {
    double gt[6] = {0, 0, 0, 0, 0, 0};
    if (ds.GetGeoTransform(gt) != CE_None) return "no geotransform";
    if (gt[2] != 0.0 || gt[4] != 0.0) return "rotated geotransform (terms 2 and 4 not 0)";
    if (!(gt[1] > 0.0) || gt[5] != -gt[1]) {
        return "pixels not square cells with north up (pixel width " + std::to_string(gt[1]) + ", height " +
               std::to_string(gt[5]) + ")";
    }
    const int cols = ds.GetRasterXSize(), rows = ds.GetRasterYSize();
    if (cols > terrain::kMaxGridSide || rows > terrain::kMaxGridSide) {
        return std::to_string(cols) + "x" + std::to_string(rows) + " pixels, over the " +
               std::to_string(terrain::kMaxGridSide) + " a side of a height map";
    }
    grid = terrain::GridConfig{gt[3], gt[0], gt[1], cols, rows};
    return grid.validate().isOk() ? "" : "not a valid height-map grid (cell size or corner)";
}

// Band 1's type and nodata; "" or what is refused.
std::string checkElevationBand(GDALRasterBand* band) {
    if (band == nullptr) return "no raster band";
    if (band->GetRasterDataType() != GDT_Float32) {
        return std::string("band 1 is ") + GDALGetDataTypeName(band->GetRasterDataType()) + ", not Float32";
    }
    int has_no_data = 0;
    const double no_data = band->GetNoDataValue(&has_no_data);
    if (has_no_data == 0 || !std::isnan(no_data)) return "band 1 has no nodata value NaN";
    return "";
}

std::string readValues(GDALRasterBand& band, ElevationGeoTiff& out) {
    const terrain::GridConfig& g = out.grid;
    out.elevation_m = FloatImage(g.cols, g.rows);
    if (band.RasterIO(GF_Read, 0, 0, g.cols, g.rows, out.elevation_m.pixels.data(), g.cols, g.rows, GDT_Float32, 0,
                      0) != CE_None) {
        return "cannot read band 1";
    }
    return "";
}

// Everything after opening; "" or the reason.
std::string readOpen(GDALDataset& ds, ElevationGeoTiff& out) {
    if (std::string(ds.GetDriver()->GetDescription()) != "GTiff") return "not a GeoTIFF";
    std::string error = gridOf(ds, out.grid);
    if (error.empty()) error = checkElevationBand(ds.GetRasterCount() > 0 ? ds.GetRasterBand(1) : nullptr);
    if (!error.empty()) return error;
    const OGRSpatialReference* crs = ds.GetSpatialRef();
    if (crs == nullptr) return "no CRS";
    error = detail::recogniseSiteCrs(*crs, out.site);
    if (!error.empty()) return "CRS is not the VTM site frame's: " + error;
    return readValues(*ds.GetRasterBand(1), out);
}

}  // namespace

Result<ElevationGeoTiff> readElevationGeoTiff(const std::string& path) {
    detail::registerGdalDrivers();
    detail::QuietGdalErrors quiet;
    const char* const drivers[] = {"GTiff", nullptr};
    Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers));
    if (!ds) return Elevation::failure(path + ": cannot open as GeoTIFF: " + quiet.lastError());
    ElevationGeoTiff out;
    const std::string error = readOpen(*ds, out);
    if (!error.empty()) return Elevation::failure(path + ": " + error);
    return Elevation::success(std::move(out));
}

}  // namespace vtm::ground
