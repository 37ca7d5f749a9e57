// writeHeightMapGeoTiff, writeOrthophotoGeoTiff (geotiff.hpp): one raster writer for both.
#include <gdal_priv.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <utility>

#include "gdal_session.hpp"
#include "geotiff_crs.hpp"
#include "vtm/ground/geotiff.hpp"
#include "vtm/ground/terrain_products.hpp"

#ifndef VTM_VERSION
#define VTM_VERSION "unknown"
#endif

namespace vtm::ground {
namespace {

// What goes into one file: bands of one type on one grid, cell (col, row) at pixel (col, row).
struct RasterBand {
    std::string description;
    std::string unit;    // "m", or "" for none
    const void* values;  // cols * rows values of the raster's type, row 0 (north) first
};
struct Raster {
    terrain::GridConfig grid;
    GDALDataType type = GDT_Float32;
    std::optional<double> no_data;  // GeoTIFF has one nodata value for all bands
    std::vector<RasterBand> bands;
    std::vector<std::pair<std::string, std::string>> metadata;
};

std::array<double, 6> geoTransform(const terrain::GridConfig& g) {
    return {g.west_edge_m, g.cell_m, 0.0, g.north_edge_m, 0.0, -g.cell_m};
}

std::vector<std::pair<std::string, std::string>> commonMetadata(const GeoTiffOptions& options) {
    return {{"VTM_SOURCE", options.source.empty() ? "VTM" : options.source},
            {"VTM_SITE_FRAME", "x north, y east, z down, metres; easting = site y, northing = site x"},
            {"VTM_SITE_ORIGIN", "latitude " + std::to_string(options.site.latitude_deg) + " deg, east longitude " +
                                    std::to_string(options.site.longitude_deg) + " deg (planetocentric)"},
            {"VTM_VERSION", VTM_VERSION}};
}

// Bands, nodata, descriptions and units into an open dataset; false on a GDAL error.
bool fillDataset(GDALDataset& ds, const Raster& r) {
    std::array<double, 6> gt = geoTransform(r.grid);
    if (ds.SetGeoTransform(gt.data()) != CE_None) return false;
    for (const auto& [key, value] : r.metadata) {
        if (ds.SetMetadataItem(key.c_str(), value.c_str()) != CE_None) return false;
    }
    for (int b = 0; b < static_cast<int>(r.bands.size()); ++b) {
        GDALRasterBand* band = ds.GetRasterBand(b + 1);
        void* values = const_cast<void*>(r.bands[static_cast<std::size_t>(b)].values);  // GF_Write reads it only
        if (band->RasterIO(GF_Write, 0, 0, r.grid.cols, r.grid.rows, values, r.grid.cols, r.grid.rows, r.type, 0, 0) !=
            CE_None) {
            return false;
        }
        const RasterBand& spec = r.bands[static_cast<std::size_t>(b)];
        band->SetDescription(spec.description.c_str());
        if (!spec.unit.empty() && band->SetUnitType(spec.unit.c_str()) != CE_None) return false;
        if (r.no_data && band->SetNoDataValue(*r.no_data) != CE_None) return false;
    }
    return true;
}

// Creates `temp`, writes the raster into it and closes it; "" or the reason.
std::string writeTemp(GDALDriver& driver, const std::string& temp, const Raster& r, const SiteOrigin& site) {
    detail::QuietGdalErrors quiet;
    GDALDataset* ds = driver.Create(temp.c_str(), r.grid.cols, r.grid.rows, static_cast<int>(r.bands.size()), r.type,
                                    nullptr);
    if (ds == nullptr) return "GDAL cannot create it: " + quiet.lastError();
    const OGRSpatialReference crs = detail::siteCrs(site);
    bool ok = ds->SetSpatialRef(&crs) == CE_None && fillDataset(*ds, r);
    GDALClose(ds);  // writes the file: a full disk shows up here as a GDAL error
    ok = ok && !quiet.failed();
    return ok ? "" : "GDAL: " + quiet.lastError();
}

void removeTemp(const std::string& temp) {
    (void)std::remove(temp.c_str());
    (void)std::remove((temp + ".aux.xml").c_str());  // GDAL's side-car, should it have written one
}

// The whole write: checks, PATH.partial, rename.
Outcome writeRaster(const std::string& path, const Raster& r, const SiteOrigin& site) {
    const std::string origin = detail::checkSiteOrigin(site);
    if (!origin.empty()) return Outcome::failure(path + ": " + origin);
    detail::registerGdalDrivers();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (driver == nullptr) return Outcome::failure(path + ": GDAL has no GTiff driver; nothing written");
    const std::string temp = path + ".partial";
    errno = 0;
    std::FILE* probe = std::fopen(temp.c_str(), "wb");  // the operating system's reason, as file_bytes gives it
    if (probe == nullptr) return Outcome::failure(path + ": cannot create: " + std::strerror(errno));
    (void)std::fclose(probe);
    const std::string error = writeTemp(*driver, temp, r, site);
    if (!error.empty()) {
        removeTemp(temp);
        return Outcome::failure(path + ": " + error);
    }
    errno = 0;
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        removeTemp(temp);
        return Outcome::failure(path + ": cannot create: " + reason);
    }
    return Outcome::success();
}

FloatImage cellValues(const terrain::HeightMap& map, bool count) {
    const terrain::GridConfig& g = map.grid();
    FloatImage out(g.cols, g.rows);
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            out.at(col, row) = count ? static_cast<float>(map.count(col, row)) : map.spread(col, row);
        }
    }
    return out;
}

}  // namespace

Outcome writeHeightMapGeoTiff(const std::string& path, const terrain::HeightMap& map, const GeoTiffOptions& options,
                              const HeightMapBands& bands) {
    if (map.filledCells() == 0) return Outcome::failure(path + ": the height map has no cell with data; nothing written");
    const FloatImage elevation = elevationImage(map);
    const FloatImage spread = bands.spread ? cellValues(map, false) : FloatImage();
    const FloatImage count = bands.count ? cellValues(map, true) : FloatImage();
    Raster r{map.grid(), GDT_Float32, std::numeric_limits<double>::quiet_NaN(),
             {{"elevation_m", "m", elevation.pixels.data()}}, commonMetadata(options)};
    if (bands.spread) r.bands.push_back({"spread_m", "m", spread.pixels.data()});
    if (bands.count) r.bands.push_back({"count", "", count.pixels.data()});
    r.metadata.emplace_back("VTM_UNITS", "m, elevation up (from the site origin's level plane); count: points");
    r.metadata.emplace_back("VTM_NO_DATA", "NaN (count: 0)");
    return writeRaster(path, r, options.site);
}

Outcome writeOrthophotoGeoTiff(const std::string& path, const GreyImage& image, const terrain::GridConfig& grid,
                               const GeoTiffOptions& options, std::optional<std::uint8_t> no_data) {
    if (image.channels != 1 || image.width != grid.cols || image.height != grid.rows || image.empty()) {
        return Outcome::failure(path + ": orthophoto is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + "x" + std::to_string(image.channels) +
                                ", the grid " + std::to_string(grid.cols) + "x" + std::to_string(grid.rows) +
                                "x1 (one 8-bit band, a pixel per cell); nothing written");
    }
    if (!grid.validate().isOk()) return Outcome::failure(path + ": invalid grid; nothing written");
    Raster r{grid, GDT_Byte, std::nullopt, {{"orthophoto", "", image.pixels.data()}}, commonMetadata(options)};
    if (no_data) r.no_data = static_cast<double>(*no_data);
    r.metadata.emplace_back("VTM_UNITS", "grey level, 8 bit");
    r.metadata.emplace_back("VTM_NO_DATA", no_data ? std::to_string(*no_data) : std::string("none"));
    return writeRaster(path, r, options.site);
}

}  // namespace vtm::ground
