// GeoTIFF: a height map with a known grid and known values written, then read back with
// GDAL's own API (size, geotransform, CRS parameters and geometry, values and nodata bit
// for bit, band descriptions, metadata) and with gdalinfo as a user runs it; the reader's
// grid and values; refusals and errors naming the file, leaving nothing behind.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <regex>
#include <string>

#include "ground_test_files.hpp"
#include "geotiff_test_map.hpp"
#include "vtm/ground/geotiff.hpp"

namespace vtm::ground {
namespace {

using namespace test;
constexpr double kPi = 3.14159265358979323846;


TEST(GeoTiff, GdalReadsTheGridValuesAndNodataBitForBit) {
    Written w(true, true);
    const Dataset ds = openWithGdal(w.path);
    ASSERT_TRUE(ds);
    EXPECT_STREQ(ds->GetDriver()->GetDescription(), "GTiff");
    ASSERT_EQ(ds->GetRasterXSize(), 5);
    ASSERT_EQ(ds->GetRasterYSize(), 4);
    ASSERT_EQ(ds->GetRasterCount(), 3);
    double gt[6] = {};
    ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
    const double expected_gt[6] = {-3.0, 0.5, 0.0, 12.5, 0.0, -0.5};  // west, cell, 0, north, 0, -cell
    for (int k = 0; k < 6; ++k) EXPECT_EQ(gt[k], expected_gt[k]) << k;
    const char* names[3] = {"elevation_m", "spread_m", "count"};
    for (int b = 1; b <= 3; ++b) {
        GDALRasterBand* band = ds->GetRasterBand(b);
        EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
        int has = 0;
        EXPECT_TRUE(std::isnan(band->GetNoDataValue(&has)));
        EXPECT_EQ(has, 1);
        EXPECT_STREQ(band->GetDescription(), names[b - 1]);
    }
    const std::vector<float> z = bandValues(*ds, 1), spread = bandValues(*ds, 2), count = bandValues(*ds, 3);
    for (std::int32_t row = 0; row < 4; ++row) {
        for (std::int32_t col = 0; col < 5; ++col) {
            const std::size_t i = static_cast<std::size_t>(row * 5 + col);
            const bool two = col == 0 && row == 0;
            EXPECT_EQ(bitsOf(z[i]), isHole(col, row) ? bitsOf(terrain::kNoData) : bitsOf(elevationOf(col, row))) << i;
            EXPECT_EQ(bitsOf(spread[i]), isHole(col, row) ? bitsOf(terrain::kNoData) : bitsOf(two ? 0.5F : 0.0F)) << i;
            EXPECT_EQ(count[i], isHole(col, row) ? 0.0F : (two ? 2.0F : 1.0F)) << i;
        }
    }
    EXPECT_STREQ(ds->GetRasterBand(1)->GetUnitType(), "m");
    EXPECT_STREQ(ds->GetRasterBand(2)->GetUnitType(), "m");
    EXPECT_STREQ(ds->GetRasterBand(3)->GetUnitType(), "");
    EXPECT_STREQ(ds->GetMetadataItem("VTM_SOURCE"), "geotiff_test");
    EXPECT_NE(std::strstr(ds->GetMetadataItem("VTM_UNITS"), "elevation up"), nullptr);
    EXPECT_NE(std::strstr(ds->GetMetadataItem("VTM_NO_DATA"), "NaN"), nullptr);
    EXPECT_STRNE(ds->GetMetadataItem("VTM_VERSION"), "");
    // One file, no side-car or temporary left.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(std::filesystem::path(w.path).parent_path()),
                            std::filesystem::directory_iterator()), 1);
}

TEST(GeoTiff, TheCrsIsTransverseMercatorOnTheMarsSphereAtTheSiteOrigin) {
    Written w(false, false);
    const Dataset ds = openWithGdal(w.path);
    ASSERT_TRUE(ds);
    const OGRSpatialReference* crs = ds->GetSpatialRef();
    ASSERT_NE(crs, nullptr);
    EXPECT_TRUE(crs->IsProjected());
    EXPECT_STREQ(crs->GetAttrValue("PROJECTION"), SRS_PT_TRANSVERSE_MERCATOR);
    EXPECT_EQ(crs->GetProjParm(SRS_PP_LATITUDE_OF_ORIGIN), -4.5);
    EXPECT_EQ(crs->GetProjParm(SRS_PP_CENTRAL_MERIDIAN), 137.4);
    EXPECT_EQ(crs->GetProjParm(SRS_PP_SCALE_FACTOR), 1.0);
    EXPECT_EQ(crs->GetProjParm(SRS_PP_FALSE_EASTING, 1.0), 0.0);
    EXPECT_EQ(crs->GetProjParm(SRS_PP_FALSE_NORTHING, 1.0), 0.0);
    EXPECT_EQ(crs->GetSemiMajor(), 3396190.0);
    EXPECT_EQ(crs->GetInvFlattening(), 0.0);  // a sphere
    EXPECT_EQ(crs->GetLinearUnits(), 1.0);
    // Geometry: 1 km north of the origin along the central meridian is an arc of 1 km on the
    // sphere, so the latitude grows by 1000 / R radians; the origin maps to itself.
    OGRSpatialReference geo;
    ASSERT_EQ(geo.CopyGeogCSFrom(crs), OGRERR_NONE);
    geo.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // lon, lat
    std::unique_ptr<OGRCoordinateTransformation> to_geo(OGRCreateCoordinateTransformation(crs, &geo));
    ASSERT_TRUE(to_geo);
    double x[2] = {0.0, 0.0}, y[2] = {0.0, 1000.0};  // easting, northing
    ASSERT_TRUE(to_geo->Transform(2, x, y));
    EXPECT_NEAR(x[0], 137.4, 1e-9);
    EXPECT_NEAR(y[0], -4.5, 1e-9);
    EXPECT_NEAR(x[1], 137.4, 1e-9);
    EXPECT_NEAR(y[1], -4.5 + 1000.0 / 3396190.0 * 180.0 / kPi, 1e-9);
}

std::string runGdalinfo(const std::string& path) {
    std::string out;
    std::FILE* p = ::popen((std::string(VTM_GDALINFO) + " '" + path + "' 2>&1").c_str(), "r");
    if (p == nullptr) return out;
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    EXPECT_EQ(::pclose(p), 0) << out;
    return out;
}

// Degrees as gdalinfo prints them: 137d23'59.82"E.
std::string dms(double value, char positive, char negative) {
    const double a = std::fabs(value);
    const int d = static_cast<int>(a);
    const int m = static_cast<int>((a - d) * 60.0);
    const double sec = (a - d - m / 60.0) * 3600.0;
    char buf[48];
    std::snprintf(buf, sizeof buf, "%dd%2d'%5.2f\"%c", d, m, sec, value < 0.0 ? negative : positive);
    return buf;
}

TEST(GeoTiff, GdalinfoNamesTheCrsTheCornersAndTheNodata) {
    if (std::string(VTM_GDALINFO).empty() || !std::filesystem::exists(VTM_GDALINFO)) {
        GTEST_SKIP() << "gdalinfo not installed (Debian package gdal-bin): not checked";
    }
    Written w(false, false);
    const std::string info = runGdalinfo(w.path);
    EXPECT_NE(info.find("Driver: GTiff/GeoTIFF"), std::string::npos) << info;
    EXPECT_NE(info.find("Size is 5, 4"), std::string::npos) << info;
    EXPECT_NE(info.find("PROJCRS[\"VTM site frame, Mars (2015) sphere, transverse Mercator\""), std::string::npos) << info;
    EXPECT_NE(info.find("Transverse Mercator"), std::string::npos) << info;
    EXPECT_NE(info.find("ELLIPSOID[\"Mars (2015) - Sphere\",3396190,0"), std::string::npos) << info;
    // Corners: west -3, east -3 + 5 * 0.5 = -0.5; north 12.5, south 12.5 - 4 * 0.5 = 10.5.
    EXPECT_TRUE(std::regex_search(info, std::regex(R"(Upper Left\s+\(\s*-3\.0+,\s*12\.50+\))"))) << info;
    EXPECT_TRUE(std::regex_search(info, std::regex(R"(Lower Right\s+\(\s*-0\.50+,\s*10\.50+\))"))) << info;
    // And where the upper-left corner is on Mars: 12.5 m north of the origin is 12.5 / R
    // radians of latitude, 3 m west 3 / (R cos lat) radians of longitude (to 1e-12 here).
    const double r = kMarsRadiusM, deg = 180.0 / kPi;
    const double lat = -4.5 + 12.5 / r * deg, lon = 137.4 - 3.0 / (r * std::cos(4.5 / deg)) * deg;
    const std::string upper_left = "Upper Left  (  -3.0000000,  12.5000000) (" + dms(lon, 'E', 'W') + ",";
    EXPECT_NE(info.find(upper_left), std::string::npos) << upper_left << "\n" << info;
    EXPECT_NE(info.find(dms(lat, 'N', 'S') + ")"), std::string::npos) << dms(lat, 'N', 'S') << "\n" << info;
    EXPECT_NE(info.find("NoData Value=nan"), std::string::npos) << info;
    EXPECT_NE(info.find("Type=Float32"), std::string::npos) << info;
}

}  // namespace
}  // namespace vtm::ground
