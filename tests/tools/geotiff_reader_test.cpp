// GeoTIFF: the reader gives back the grid and the values that were written; files of
// another kind are refused by name; the writer's errors name the file and leave nothing
// behind; the orthophoto is one 8-bit band on the same grid and CRS.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "geotiff_test_map.hpp"

namespace vtm::ground {
namespace {

using namespace test;

TEST(GeoTiffReader, GivesBackTheGridTheSiteAndTheValues) {
    Written w(true, false);
    const Result<ElevationGeoTiff> r = readElevationGeoTiff(w.path);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.grid.north_edge_m, kGrid.north_edge_m);
    EXPECT_EQ(r.value.grid.west_edge_m, kGrid.west_edge_m);
    EXPECT_EQ(r.value.grid.cell_m, kGrid.cell_m);
    EXPECT_EQ(r.value.grid.cols, kGrid.cols);
    EXPECT_EQ(r.value.grid.rows, kGrid.rows);
    EXPECT_EQ(r.value.site.latitude_deg, kSite.latitude_deg);
    EXPECT_EQ(r.value.site.longitude_deg, kSite.longitude_deg);
    for (std::int32_t row = 0; row < kGrid.rows; ++row) {
        for (std::int32_t col = 0; col < kGrid.cols; ++col) {
            const float expected = isHole(col, row) ? terrain::kNoData : elevationOf(col, row);
            EXPECT_EQ(bitsOf(r.value.elevation_m.at(col, row)), bitsOf(expected)) << col << "," << row;
        }
    }
}

// A GeoTIFF written with GDAL directly: 5 x 4, one band of `type`, the given geotransform
// and CRS (WKT or user input such as "EPSG:32633"), nodata NaN when `nodata`.
std::string gdalFile(const TempDir& dir, const char* name, GDALDataType type, const double gt[6], const char* crs,
                     bool nodata) {
    GDALAllRegister();
    const std::string path = dir.file(name);
    GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), 5, 4, 1, type, nullptr);
    EXPECT_NE(ds, nullptr);
    EXPECT_EQ(ds->SetGeoTransform(const_cast<double*>(gt)), CE_None);
    OGRSpatialReference srs;
    EXPECT_EQ(srs.SetFromUserInput(crs), OGRERR_NONE);
    EXPECT_EQ(ds->SetSpatialRef(&srs), CE_None);
    if (nodata) {
        EXPECT_EQ(ds->GetRasterBand(1)->SetNoDataValue(std::nan("")), CE_None);
    }
    GDALClose(ds);
    return path;
}

std::string siteWkt() {
    Written w(false, false);
    const Dataset ds = openWithGdal(w.path);
    char* wkt = nullptr;
    EXPECT_EQ(ds->GetSpatialRef()->exportToWkt(&wkt), OGRERR_NONE);
    const std::string out = wkt;
    CPLFree(wkt);
    return out;
}

TEST(GeoTiffReader, RefusesOtherFilesNamingTheReason) {
    TempDir dir;
    const double gt[6] = {-3.0, 0.5, 0.0, 12.5, 0.0, -0.5};
    const double rotated[6] = {-3.0, 0.5, 0.1, 12.5, 0.0, -0.5};
    const double south_up[6] = {-3.0, 0.5, 0.0, 10.5, 0.0, 0.5};
    const std::string site = siteWkt();
    const std::string text = dir.file("text.tif");
    writeBytes(text, textBytes("not a tiff\n"));
    const struct {
        std::string path;
        std::string reason;
    } cases[] = {
        {text, "cannot open as GeoTIFF: "},
        {gdalFile(dir, "byte.tif", GDT_Byte, gt, site.c_str(), false), "band 1 is Byte, not Float32"},
        {gdalFile(dir, "nonodata.tif", GDT_Float32, gt, site.c_str(), false), "band 1 has no nodata value NaN"},
        {gdalFile(dir, "rotated.tif", GDT_Float32, rotated, site.c_str(), true), "rotated geotransform (terms 2 and 4 not 0)"},
        {gdalFile(dir, "southup.tif", GDT_Float32, south_up, site.c_str(), true), "pixels not square cells with north up"},
        {gdalFile(dir, "utm.tif", GDT_Float32, gt, "EPSG:32633", true), "CRS is not the VTM site frame's: not on the Mars sphere"},
        {gdalFile(dir, "geo.tif", GDT_Float32, gt, "+proj=longlat +R=3396190 +no_defs", true),
         "CRS is not the VTM site frame's: CRS is not projected"},
    };
    for (const auto& c : cases) {
        const Result<ElevationGeoTiff> r = readElevationGeoTiff(c.path);
        EXPECT_FALSE(r.ok) << c.path;
        EXPECT_EQ(r.error.rfind(c.path + ": " + c.reason, 0), 0U) << r.error;
    }
}

void expectNothingAt(const std::string& path) {
    EXPECT_FALSE(std::filesystem::exists(path)) << path;
    EXPECT_FALSE(std::filesystem::exists(path + ".partial")) << path;
}

TEST(GeoTiffWriter, ErrorsNameTheFileAndLeaveNothingBehind) {
    TempDir dir;
    TestHeightMap empty(kGrid);
    TestHeightMap m(kGrid);
    fill(m);
    const std::string path = dir.file("map.tif");
    EXPECT_EQ(writeHeightMapGeoTiff(path, empty.map(), {}).error, path + ": the height map has no cell with data; nothing written");
    expectNothingAt(path);
    const std::string missing = dir.file("no/such/dir/map.tif");
    EXPECT_EQ(writeHeightMapGeoTiff(missing, m.map(), {}).error, missing + ": cannot create: No such file or directory");
    expectNothingAt(missing);
    EXPECT_EQ(writeHeightMapGeoTiff(path, m.map(), GeoTiffOptions{SiteOrigin{91.0, 0.0}, ""}).error,
              path + ": site origin latitude 91.000000 deg outside [-90, 90]");
    expectNothingAt(path);
    // GDAL without its GTiff driver (as a GDAL built without it would be).
    GDALAllRegister();
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    ASSERT_NE(gtiff, nullptr);
    GetGDALDriverManager()->DeregisterDriver(gtiff);
    const Outcome no_driver = writeHeightMapGeoTiff(path, m.map(), {});
    GetGDALDriverManager()->RegisterDriver(gtiff);
    EXPECT_EQ(no_driver.error, path + ": GDAL has no GTiff driver; nothing written");
    expectNothingAt(path);
}

TEST(GeoTiffWriter, OrthophotoIsOneByteBandOnTheElevationGridAndCrs) {
    TempDir dir;
    GreyImage ortho(kGrid.cols, kGrid.rows);
    for (std::int32_t i = 0; i < kGrid.cols * kGrid.rows; ++i) ortho.pixels[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(10 * i);
    const std::string path = dir.file("ortho.tif");
    const Outcome o = writeOrthophotoGeoTiff(path, ortho, kGrid, GeoTiffOptions{kSite, "test"}, std::uint8_t{0});
    ASSERT_TRUE(o.ok) << o.error;
    Written elevation(false, false);
    const Dataset ds = openWithGdal(path), dz = openWithGdal(elevation.path);
    ASSERT_TRUE(ds && dz);
    ASSERT_EQ(ds->GetRasterCount(), 1);
    GDALRasterBand* band = ds->GetRasterBand(1);
    EXPECT_EQ(band->GetRasterDataType(), GDT_Byte);
    int has = 0;
    EXPECT_EQ(band->GetNoDataValue(&has), 0.0);
    EXPECT_EQ(has, 1);
    double gt[6] = {}, gz[6] = {};
    ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
    ASSERT_EQ(dz->GetGeoTransform(gz), CE_None);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(gt[k], gz[k]) << k;
    EXPECT_TRUE(ds->GetSpatialRef()->IsSame(dz->GetSpatialRef()));
    GreyImage back(kGrid.cols, kGrid.rows);
    ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 5, 4, back.pixels.data(), 5, 4, GDT_Byte, 0, 0), CE_None);
    EXPECT_EQ(back.pixels, ortho.pixels);
    const std::string wrong = dir.file("wrong.tif");
    EXPECT_EQ(writeOrthophotoGeoTiff(wrong, GreyImage(4, 4), kGrid, {}).error,
              wrong + ": orthophoto is 4x4x1, the grid 5x4x1 (one 8-bit band, a pixel per cell); nothing written");
    expectNothingAt(wrong);
}

}  // namespace
}  // namespace vtm::ground
