// The height map of the GeoTIFF tests, its known values and GDAL helpers to read files
// back independently of the code under test.
#pragma once

#include <gtest/gtest.h>

#include <gdal_priv.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "height_map_fixture.hpp"
#include "vtm/ground/geotiff.hpp"

namespace vtm::ground::test {

// 5 x 4 cells of 0.5 m; north-west corner at north 12.5, east -3 (site frame). Site origin
// 4.5 deg S, 137.4 deg E. Holes at (2, 1) and (4, 3); cell (0, 0) holds two points.
constexpr terrain::GridConfig kGrid{12.5, -3.0, 0.5, 5, 4};
constexpr SiteOrigin kSite{-4.5, 137.4};

inline bool isHole(std::int32_t col, std::int32_t row) { return (col == 2 && row == 1) || (col == 4 && row == 3); }
// Elevation of cell (col, row), exact in float; (0, 0): the higher of 1.0 and 1.5.
inline float elevationOf(std::int32_t col, std::int32_t row) {
    return (col == 0 && row == 0) ? 1.5F : 0.25F * static_cast<float>(col) - 0.5F * static_cast<float>(row) + 0.125F;
}

inline void fill(test::TestHeightMap& m) {
    m.put(0, 0, 1.0F);
    for (std::int32_t row = 0; row < kGrid.rows; ++row) {
        for (std::int32_t col = 0; col < kGrid.cols; ++col) {
            if (!isHole(col, row)) m.put(col, row, elevationOf(col, row));
        }
    }
}

inline std::uint32_t bitsOf(float f) {
    std::uint32_t u = 0;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

struct DatasetCloser {
    void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

inline Dataset openWithGdal(const std::string& path) {
    GDALAllRegister();
    return Dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
}

inline std::vector<float> bandValues(GDALDataset& ds, int band) {
    std::vector<float> v(static_cast<std::size_t>(kGrid.cols * kGrid.rows));
    EXPECT_EQ(ds.GetRasterBand(band)->RasterIO(GF_Read, 0, 0, kGrid.cols, kGrid.rows, v.data(), kGrid.cols, kGrid.rows,
                                                GDT_Float32, 0, 0),
              CE_None);
    return v;
}

// A written height-map GeoTIFF in a temporary directory.
struct Written {
    test::TempDir dir;
    std::string path = dir.file("map.tif");
    Written(bool spread, bool count) {
        test::TestHeightMap m(kGrid);
        fill(m);
        const Outcome o = writeHeightMapGeoTiff(path, m.map(), GeoTiffOptions{kSite, "geotiff_test"},
                                                HeightMapBands{spread, count});
        EXPECT_TRUE(o.ok) << o.error;
    }
};

}  // namespace vtm::ground::test
