// fsw/terrain: triangulation against the analytic projection of known points (positions
// and the range sigma of Z^2 / (f B) sigma_d), and the height map's cell rules (highest,
// lowest, count, NO_DATA) against points placed in known cells; merging equals building
// from all points at once, bit for bit. No heap on the run path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "no_heap_guard.hpp"
#include "vtm/core/random.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::terrain {
namespace {

using test::NoHeapScope;

RectifiedGeometry testGeometry(double baseline_m) {
    RectifiedGeometry g;
    g.fx_px = 800.0;
    g.fy_px = 800.0;
    g.cx_left_px = 330.5;
    g.cx_right_px = 290.25;
    g.cy_px = 240.0;
    g.baseline_m = baseline_m;
    // A camera 1.9 m up (site z down), looking north and 20 deg down: rect +z = view.
    const double t = 20.0 * 3.14159265358979323846 / 180.0;
    Mat3 R;
    // columns: rect x (east), rect y (down-ish), rect z (view) in the site frame
    R.col(0) = Vec3(0.0, 1.0, 0.0);
    R.col(2) = Vec3(std::cos(t), 0.0, std::sin(t));
    R.col(1) = R.col(2).cross(R.col(0));
    g.R_site_from_rect = R;
    g.left_centre_site_m = Vec3(3.0, -2.0, -1.9);
    return g;
}

// Pixel and disparity of a site point in the rectified pair (the analytic forward model).
void project(const RectifiedGeometry& g, const Vec3& site, double& x, double& y, double& d) {
    const Vec3 p = g.R_site_from_rect.transpose() * (site - g.left_centre_site_m);
    x = g.fx_px * p.x() / p.z() + g.cx_left_px;
    y = g.fy_px * p.y() / p.z() + g.cy_px;
    const double xr = g.fx_px * (p.x() - g.baseline_m) / p.z() + g.cx_right_px;
    d = x - xr;
}

TEST(Triangulation, KnownPointsComeBackFromTheirPixelAndDisparity) {
    for (const double b : {0.42, 5.0, -3.0}) {
        const RectifiedGeometry g = testGeometry(b);
        Random rng(7U);
        TriangulationLimits limits;
        limits.max_range_m = 1000.0;
        limits.max_sigma_ratio = 1.0;
        for (int i = 0; i < 200; ++i) {
            const double range = 2.0 + 60.0 * rng.uniform01();
            const double ax = -0.3 + 0.6 * rng.uniform01();
            const double ay = -0.3 + 0.6 * rng.uniform01();
            const Vec3 dir_rect = Vec3(ax, ay, 1.0).normalized();
            const Vec3 site = g.left_centre_site_m + g.R_site_from_rect * (range * dir_rect);
            double x = 0.0, y = 0.0, d = 0.0;
            project(g, site, x, y, d);
            TerrainPoint p{};
            ASSERT_TRUE(triangulatePixel(g, limits, x, y, d, 0.25, p).isOk()) << "b " << b << " range " << range;
            const double err = (Vec3(p.x_m, p.y_m, p.z_m) - site).norm();
            EXPECT_LT(err, 2e-6 * (range + 3.0)) << "b " << b << " range " << range;  // float storage
            // sigma_range against the numeric derivative of the range with respect to d.
            const double h = 0.02;  // points are floats: a step well above their rounding
            TerrainPoint lo{}, hi{};
            ASSERT_TRUE(triangulatePixel(g, limits, x, y, d - h, 0.25, lo).isOk());
            ASSERT_TRUE(triangulatePixel(g, limits, x, y, d + h, 0.25, hi).isOk());
            const Vec3 c = g.left_centre_site_m;
            const double dr = ((Vec3(hi.x_m, hi.y_m, hi.z_m) - c).norm() - (Vec3(lo.x_m, lo.y_m, lo.z_m) - c).norm());
            const double numeric = std::fabs(dr / (2.0 * h)) * 0.25;
            EXPECT_NEAR(p.sigma_range_m, numeric, 5e-3 * numeric + 1e-5) << "b " << b << " range " << range;
        }
    }
}

TEST(Triangulation, DisparitiesAtOrBeyondInfinityAndOutOfLimitsAreRefused) {
    const RectifiedGeometry g = testGeometry(0.42);
    TriangulationLimits limits;
    TerrainPoint p{};
    const double at_infinity = g.cx_left_px - g.cx_right_px;
    EXPECT_EQ(triangulatePixel(g, limits, 300.0, 200.0, at_infinity, 0.25, p).code(), StatusCode::kNoData);
    EXPECT_EQ(triangulatePixel(g, limits, 300.0, 200.0, at_infinity - 1.0, 0.25, p).code(), StatusCode::kNoData);
    // 800 * 0.42 / 1 px = 336 m: beyond max_range_m 200.
    EXPECT_EQ(triangulatePixel(g, limits, 330.5, 240.0, at_infinity + 1.0, 0.25, p).code(), StatusCode::kNoData);
    // 33.6 m with sigma 0.25 px -> sigma_Z = 33.6^2 / 336 * 0.25 = 0.84 m = 2.5 %: accepted at 5 %.
    EXPECT_TRUE(triangulatePixel(g, limits, 330.5, 240.0, at_infinity + 10.0, 0.25, p).isOk());
    EXPECT_NEAR(p.sigma_range_m, 33.6 * 33.6 / 336.0 * 0.25, 1e-4);
    EXPECT_EQ(triangulatePixel(g, limits, 330.5, 240.0, at_infinity + 10.0, 1.0, p).code(), StatusCode::kNoData);
}

TEST(Triangulation, ImagesCountEveryPixelAndNeverAllocate) {
    const RectifiedGeometry g = testGeometry(0.42);
    constexpr int kW = 64, kH = 48;
    std::vector<std::int16_t> disp(kW * kH, kNoDisparity);
    for (int i = 0; i < kW * kH; i += 2) {
        disp[static_cast<std::size_t>(i)] = static_cast<std::int16_t>((40 + 20) * kDisparityScale);  // 16.8 m
    }
    disp[1] = static_cast<std::int16_t>(30 * kDisparityScale);  // at cx_l - cx_r - 10: behind
    std::vector<TerrainPoint> out(1000);
    TriangulationStats stats;
    NoHeapScope scope;
    ASSERT_TRUE(triangulate(g, TriangulationLimits{}, ImageView<const std::int16_t>(disp.data(), kW, kH), {},
                            Span<TerrainPoint>(out.data(), out.size()), stats)
                    .isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(stats.points, 1000);
    EXPECT_EQ(stats.dropped, kW * kH / 2 - 1000);
    EXPECT_EQ(stats.refused, 1);
    EXPECT_EQ(stats.no_disparity, kW * kH / 2 - 1);
    std::vector<float> sigma(10);
    EXPECT_EQ(triangulate(g, TriangulationLimits{}, ImageView<const std::int16_t>(disp.data(), kW, kH),
                          ImageView<const float>(sigma.data(), 5, 2), Span<TerrainPoint>(out.data(), out.size()), stats)
                  .code(),
              StatusCode::kSizeMismatch);
    RectifiedGeometry bad = g;
    bad.baseline_m = 0.0;
    const Status s = triangulate(bad, TriangulationLimits{}, ImageView<const std::int16_t>(disp.data(), kW, kH), {},
                                 Span<TerrainPoint>(out.data(), out.size()), stats);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::strstr(s.reason(), "baseline_m"), nullptr) << s.reason();
}

struct MapFixture {
    explicit MapFixture(const GridConfig& g, Reducer reducer = Reducer::kHighest)
        : config{g, reducer}, pool(HeightMap::workspaceBytes(config)), arena(pool.data(), pool.size()) {
        status = map.init(config, arena);
    }
    HeightMapConfig config;
    std::vector<std::byte> pool;
    Arena arena;
    HeightMap map;
    Status status;
};

// North edge 1 m, west edge 10 m, 0.5 m cells, 20 columns (east 10..20 m) and 12 rows
// (north 1 .. -5 m).
GridConfig grid() {
    GridConfig c;
    c.north_edge_m = 1.0;
    c.west_edge_m = 10.0;
    c.cell_m = 0.5;
    c.cols = 20;
    c.rows = 12;
    return c;
}

TerrainPoint at(double north, double east, double up) {
    TerrainPoint p{};
    p.x_m = static_cast<float>(north);
    p.y_m = static_cast<float>(east);
    p.z_m = static_cast<float>(-up);
    return p;
}

// Points whose cells are worked out by hand from the convention (row 0 north, rows run
// south; column 0 west; a cell holds its south and west edges).
const TerrainPoint kPoints[] = {
    // cell (col 3, row 7): east [11.5, 12), north [1 - 8 * 0.5, 1 - 7 * 0.5) = [-3, -2.5)
    at(-2.9, 11.6, 0.30), at(-2.6, 11.9, 0.75), at(-2.75, 11.7, -0.1),
    at(-5.0, 10.0, 2.0),     // the grid's south-west corner: cell (0, 11), the last row
    at(0.99, 19.99, 4.0),    // just inside the north-east corner: cell (19, 0)
    at(-2.5, 12.0, 1.5),     // on the south edge of row 6 and the west edge of col 4: cell (4, 6)
    at(1.0, 10.0, 1.0),      // the grid's north edge (open): outside
    at(0.0, 9.99, 1.0),      // west of the grid: outside
    at(std::nan(""), 12.0, 1.0),  // not finite: outside
};
constexpr std::size_t kPointCount = sizeof(kPoints) / sizeof(kPoints[0]);

TEST(HeightMap, PointsLandInTheDocumentedRowAndColumnAndEmptyCellsAreNoData) {
    MapFixture f(grid());
    ASSERT_TRUE(f.status.isOk());
    HeightMapStats stats;
    NoHeapScope scope;
    ASSERT_TRUE(f.map.add(Span<const TerrainPoint>(kPoints, kPointCount), &stats).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(stats.added, 6);
    EXPECT_EQ(stats.outside, 3);
    EXPECT_EQ(f.map.count(3, 7), 3);
    EXPECT_EQ(f.map.count(0, 11), 1);
    EXPECT_FLOAT_EQ(f.map.elevation(0, 11), 2.0F);
    EXPECT_EQ(f.map.count(19, 0), 1);
    EXPECT_FLOAT_EQ(f.map.elevation(19, 0), 4.0F);
    EXPECT_EQ(f.map.count(4, 6), 1);
    EXPECT_FLOAT_EQ(f.map.elevation(4, 6), 1.5F);
    EXPECT_EQ(f.map.filledCells(), 4);
    // Cell centres: north_edge - (row + 0.5) cell, west_edge + (col + 0.5) cell.
    EXPECT_DOUBLE_EQ(f.map.centreNorthM(7), -2.75);
    EXPECT_DOUBLE_EQ(f.map.centreEastM(3), 11.75);
    // NO_DATA (a NaN) from every accessor where nothing fell.
    EXPECT_EQ(f.map.count(4, 4), 0);
    EXPECT_TRUE(isNoData(f.map.elevation(4, 4)));
    EXPECT_TRUE(isNoData(f.map.highest(4, 4)));
    EXPECT_TRUE(isNoData(f.map.lowest(4, 4)));
    EXPECT_TRUE(isNoData(f.map.spread(4, 4)));
    EXPECT_TRUE(std::isnan(kNoData));
    f.map.clear();
    EXPECT_EQ(f.map.filledCells(), 0);
    EXPECT_TRUE(isNoData(f.map.elevation(3, 7)));
}

TEST(HeightMap, EachReducerGivesItsElevationAndEveryMapKeepsHighestLowestSpreadAndCount) {
    for (const Reducer r : {Reducer::kHighest, Reducer::kMean, Reducer::kLowest}) {
        MapFixture f(grid(), r);
        ASSERT_TRUE(f.status.isOk());
        NoHeapScope scope;
        ASSERT_TRUE(f.map.add(Span<const TerrainPoint>(kPoints, kPointCount)).isOk());
        EXPECT_EQ(scope.heapCalls(), 0U);
        EXPECT_EQ(f.map.reducer(), r);
        // Cell (3, 7) holds 0.30, 0.75 and -0.1 m.
        EXPECT_FLOAT_EQ(f.map.highest(3, 7), 0.75F);
        EXPECT_FLOAT_EQ(f.map.lowest(3, 7), -0.1F);
        EXPECT_FLOAT_EQ(f.map.spread(3, 7), 0.85F);
        EXPECT_EQ(f.map.count(3, 7), 3);
        const float expected = r == Reducer::kHighest ? 0.75F : r == Reducer::kLowest ? -0.1F : 0.95F / 3.0F;
        EXPECT_NEAR(f.map.elevation(3, 7), expected, 1e-6) << static_cast<int>(r);
        // A cell of one point: every reducer gives that point.
        EXPECT_FLOAT_EQ(f.map.elevation(0, 11), 2.0F);
        EXPECT_FLOAT_EQ(f.map.spread(0, 11), 0.0F);
        EXPECT_TRUE(isNoData(f.map.elevation(5, 5)));
    }
}

TEST(HeightMap, DoublePointsBinAsTheirFloatPointsDo) {
    MapFixture a(grid(), Reducer::kMean), b(grid(), Reducer::kMean), s(grid(), Reducer::kMean);
    HeightMapStats sa, sb, ss;
    ASSERT_TRUE(a.map.add(Span<const TerrainPoint>(kPoints, kPointCount), &sa).isOk());
    std::vector<Vec3> sites;
    for (const TerrainPoint& p : kPoints) {
        sites.emplace_back(static_cast<double>(p.x_m), static_cast<double>(p.y_m), static_cast<double>(p.z_m));
    }
    NoHeapScope scope;
    for (const Vec3& site : sites) {
        ASSERT_TRUE(b.map.add(site, &sb).isOk());  // one at a time
    }
    ASSERT_TRUE(s.map.add(Span<const Vec3>(sites.data(), sites.size()), &ss).isOk());  // a span
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(sa.added, sb.added);
    EXPECT_EQ(sa.outside, sb.outside);
    EXPECT_EQ(sa.added, ss.added);
    EXPECT_EQ(sa.outside, ss.outside);
    for (int r = 0; r < grid().rows; ++r) {
        for (int c = 0; c < grid().cols; ++c) {
            const float ea = a.map.elevation(c, r), eb = b.map.elevation(c, r), es = s.map.elevation(c, r);
            EXPECT_EQ(std::memcmp(&ea, &eb, sizeof ea), 0) << c << "," << r;
            EXPECT_EQ(std::memcmp(&ea, &es, sizeof ea), 0) << c << "," << r;
            EXPECT_EQ(a.map.count(c, r), b.map.count(c, r));
            EXPECT_EQ(a.map.count(c, r), s.map.count(c, r));
        }
    }
}

TEST(HeightMap, ASaturatedCellKeepsTheMeanOfItsFirst65535PointsAndItsExtremes) {
    MapFixture f(grid(), Reducer::kMean);
    std::vector<TerrainPoint> pts(65535, at(-2.75, 11.7, 1.0));
    pts.push_back(at(-2.75, 11.7, 100.0));
    ASSERT_TRUE(f.map.add(Span<const TerrainPoint>(pts.data(), pts.size())).isOk());
    EXPECT_EQ(f.map.count(3, 7), 65535);
    EXPECT_FLOAT_EQ(f.map.elevation(3, 7), 1.0F);
    EXPECT_FLOAT_EQ(f.map.highest(3, 7), 100.0F);
}

TEST(HeightMap, MergingTwoMapsEqualsOneMapOfAllPointsBitForBit) {
    Random rng(11U);
    std::vector<TerrainPoint> a(3000), b(2000);
    for (auto* v : {&a, &b}) {
        for (TerrainPoint& p : *v) {
            const double n = -6.0 + 8.0 * rng.uniform01();
            const double e = 9.0 + 12.0 * rng.uniform01();
            const double u = 0.5 * std::sin(n) + 0.1 * rng.uniform01();
            p = at(n, e, u);
        }
    }
    MapFixture all(grid()), first(grid()), second(grid());
    ASSERT_TRUE(all.map.add(Span<const TerrainPoint>(a.data(), a.size())).isOk());
    ASSERT_TRUE(all.map.add(Span<const TerrainPoint>(b.data(), b.size())).isOk());
    ASSERT_TRUE(first.map.add(Span<const TerrainPoint>(a.data(), a.size())).isOk());
    ASSERT_TRUE(second.map.add(Span<const TerrainPoint>(b.data(), b.size())).isOk());
    NoHeapScope scope;
    ASSERT_TRUE(first.map.merge(second.map).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    int filled = 0;
    for (int r = 0; r < grid().rows; ++r) {
        for (int c = 0; c < grid().cols; ++c) {
            const float h1 = first.map.highest(c, r), h2 = all.map.highest(c, r);
            const float l1 = first.map.lowest(c, r), l2 = all.map.lowest(c, r);
            EXPECT_EQ(std::memcmp(&h1, &h2, sizeof h1), 0) << c << "," << r;
            EXPECT_EQ(std::memcmp(&l1, &l2, sizeof l1), 0) << c << "," << r;
            EXPECT_EQ(first.map.count(c, r), all.map.count(c, r));
            filled += first.map.count(c, r) > 0 ? 1 : 0;
        }
    }
    EXPECT_GT(filled, 150);
    // The mean merges its sums: the same mean up to float rounding.
    MapFixture mall(grid(), Reducer::kMean), mfirst(grid(), Reducer::kMean), msecond(grid(), Reducer::kMean);
    ASSERT_TRUE(mall.map.add(Span<const TerrainPoint>(a.data(), a.size())).isOk());
    ASSERT_TRUE(mall.map.add(Span<const TerrainPoint>(b.data(), b.size())).isOk());
    ASSERT_TRUE(mfirst.map.add(Span<const TerrainPoint>(a.data(), a.size())).isOk());
    ASSERT_TRUE(msecond.map.add(Span<const TerrainPoint>(b.data(), b.size())).isOk());
    ASSERT_TRUE(mfirst.map.merge(msecond.map).isOk());
    for (int r = 0; r < grid().rows; ++r) {
        for (int c = 0; c < grid().cols; ++c) {
            EXPECT_EQ(mfirst.map.count(c, r), mall.map.count(c, r));
            if (mall.map.count(c, r) > 0) {
                EXPECT_NEAR(mfirst.map.elevation(c, r), mall.map.elevation(c, r), 1e-5) << c << "," << r;
            }
        }
    }
    GridConfig other = grid();
    other.west_edge_m += 0.5;
    MapFixture shifted(other);
    EXPECT_EQ(first.map.merge(shifted.map).code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(first.map.merge(mall.map).code(), StatusCode::kSizeMismatch);  // another reducer
}

TEST(HeightMap, SetGridMovesTheMapWithinItsCapacityAndEmptiesIt) {
    MapFixture f(grid(), Reducer::kMean);
    ASSERT_TRUE(f.map.add(Span<const TerrainPoint>(kPoints, kPointCount)).isOk());
    GridConfig moved = grid();
    moved.north_edge_m = 101.0;  // 100 m further north, 10 x 10 cells of 1 m
    moved.cell_m = 1.0;
    moved.cols = 10;
    moved.rows = 10;
    NoHeapScope scope;
    ASSERT_TRUE(f.map.setGrid(moved).isOk());
    EXPECT_EQ(f.map.filledCells(), 0);
    ASSERT_TRUE(f.map.add(Vec3(97.5, 12.5, -3.0)).isOk());  // row floor(101 - 97.5) = 3, col 2
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_FLOAT_EQ(f.map.elevation(2, 3), 3.0F);
    EXPECT_EQ(f.map.filledCells(), 1);
    GridConfig big = grid();
    big.cols = 21;  // 21 x 12 > 20 x 12 cells
    EXPECT_EQ(f.map.setGrid(big).code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(f.map.grid().cols, 10);  // the refused grid left the map as it was
    EXPECT_EQ(f.map.filledCells(), 1);
    big.cell_m = -1.0;
    EXPECT_NE(std::strstr(f.map.setGrid(big).reason(), "cell_m"), nullptr);
}

TEST(HeightMap, BadConfigsAndSmallArenasAreRefusedNamingTheField) {
    HeightMapConfig c{grid(), Reducer::kHighest};
    EXPECT_TRUE(c.validate().isOk());
    c.grid.cell_m = 0.0;
    EXPECT_NE(std::strstr(c.validate().reason(), "cell_m"), nullptr);
    c.grid = grid();
    c.grid.cols = kMaxGridSide + 1;
    EXPECT_NE(std::strstr(c.validate().reason(), "cols"), nullptr);
    c.grid = grid();
    c.grid.rows = 0;
    EXPECT_NE(std::strstr(c.validate().reason(), "rows"), nullptr);
    c.grid = grid();
    c.grid.north_edge_m = std::nan("");
    EXPECT_NE(std::strstr(c.validate().reason(), "north_edge_m"), nullptr);
    c.grid = grid();
    c.reducer = static_cast<Reducer>(9);
    EXPECT_NE(std::strstr(c.validate().reason(), "reducer"), nullptr);
    EXPECT_EQ(HeightMap::workspaceBytes(c), 0U);
    c.reducer = Reducer::kMean;
    EXPECT_GT(HeightMap::workspaceBytes(c), HeightMap::workspaceBytes(HeightMapConfig{grid(), Reducer::kHighest}));
    std::vector<std::byte> small(100);
    Arena arena(small.data(), small.size());
    HeightMap map;
    EXPECT_EQ(map.init(c, arena).code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(map.add(Span<const TerrainPoint>()).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(map.add(Vec3(0.0, 0.0, 0.0)).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(map.add(Span<const Vec3>()).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(map.setGrid(grid()).code(), StatusCode::kNotInitialized);
}

}  // namespace
}  // namespace vtm::terrain
