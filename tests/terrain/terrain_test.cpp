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
#include "vtm/rectify/linear_camera.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/terrain/ground_bound.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/terrain/rectified_geometry.hpp"
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

// ---- ground bound -------------------------------------------------------------------

// The depth at which pixel (x, y)'s ray meets the level plane z = plane_z, found
// independently of boundByGround: the ray's site direction, then the plane equation.
// false when the ray never reaches the plane (level or up, or the centre below it).
bool planeDepth(const RectifiedGeometry& g, double plane_z, std::int32_t x, std::int32_t y, double& depth) {
    const Vec3 ray_rect((x - g.cx_left_px) / g.fx_px, (y - g.cy_px) / g.fy_px, 1.0);  // depth 1
    const Vec3 ray_site = g.R_site_from_rect * ray_rect;
    const double drop = plane_z - g.left_centre_site_m.z();  // how far down the plane is
    if (!(ray_site.z() > 1e-9) || !(drop > 0.0)) {
        return false;
    }
    depth = drop / ray_site.z();
    return true;
}

TEST(GroundBound, DropsExactlyTheDisparitiesTheLevelPlaneBoundsBeyondTheWindow) {
    constexpr std::int32_t kBw = 640;
    constexpr std::int32_t kBh = 480;
    static std::int16_t disparity[kBw * kBh];
    for (const double baseline : {0.8, -0.8}) {
        const RectifiedGeometry g = testGeometry(baseline);  // 1.9 m up, 20 deg down
        const double plane_z = 0.0;                          // 1.9 m under the camera
        // The window: positive disparities for b > 0, negative for b < 0 (cx offset 40.25 px);
        // the bound falls about halfway down the image.
        const std::int32_t lo = baseline > 0.0 ? 100 : -80;
        const std::int32_t hi = lo + 63;
        std::int32_t expected = 0;
        std::int32_t checked_near = 0;
        for (std::int32_t y = 0; y < kBh; ++y) {
            for (std::int32_t x = 0; x < kBw; ++x) {
                // Every 7th pixel has no disparity; the others some value in the window.
                const bool none = (x + 3 * y) % 7 == 0;
                disparity[y * kBw + x] = none ? kNoDisparity : static_cast<std::int16_t>((lo + 5) * 16);
                double depth = 0.0;
                if (none || !planeDepth(g, plane_z, x, y, depth)) {
                    continue;
                }
                // The terrain is no farther than the plane along this ray: its disparity is
                // at least (b > 0; at most for b < 0) the plane's.
                const double d_plane = g.fx_px * g.baseline_m / depth + (g.cx_left_px - g.cx_right_px);
                const bool beyond = baseline > 0.0 ? d_plane > hi + 1.0 : d_plane < lo - 1.0;
                const double margin = baseline > 0.0 ? d_plane - (hi + 1.0) : (lo - 1.0) - d_plane;
                checked_near += std::fabs(margin) < 1e-6 ? 1 : 0;
                expected += beyond ? 1 : 0;
            }
        }
        ASSERT_EQ(checked_near, 0) << "no pixel may sit on the threshold (rounding)";
        ASSERT_GT(expected, 1000);  // the test sees the bound at work
        ASSERT_LT(expected, 3 * kBw * kBh / 4);
        std::int32_t dropped = -1;
        NoHeapScope guard;
        ASSERT_TRUE(boundByGround(g, plane_z, lo, hi, ImageView<std::int16_t>(disparity, kBw, kBh), dropped).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
        EXPECT_EQ(dropped, expected);
        // Pixel by pixel: dropped ones are exactly those beyond; the others kept unchanged.
        std::int32_t mismatches = 0;
        for (std::int32_t y = 0; y < kBh; ++y) {
            for (std::int32_t x = 0; x < kBw; ++x) {
                const bool none = (x + 3 * y) % 7 == 0;
                double depth = 0.0;
                bool beyond = false;
                if (!none && planeDepth(g, plane_z, x, y, depth)) {
                    const double d_plane = g.fx_px * g.baseline_m / depth + (g.cx_left_px - g.cx_right_px);
                    beyond = baseline > 0.0 ? d_plane > hi + 1.0 : d_plane < lo - 1.0;
                }
                const std::int16_t want = (none || beyond) ? kNoDisparity : static_cast<std::int16_t>((lo + 5) * 16);
                mismatches += disparity[y * kBw + x] == want ? 0 : 1;
            }
        }
        EXPECT_EQ(mismatches, 0) << "baseline " << baseline;
    }
}

TEST(GroundBound, APlaneAboveTheCameraOrRaysThatNeverReachItBoundNothing) {
    constexpr std::int32_t kBw = 64;
    constexpr std::int32_t kBh = 48;
    static std::int16_t disparity[kBw * kBh];
    RectifiedGeometry g = testGeometry(0.5);
    g.fx_px = 80.0;
    g.fy_px = 80.0;
    g.cx_left_px = 32.0;
    g.cx_right_px = 32.0;
    g.cy_px = 24.0;
    for (std::int16_t& d : disparity) {
        d = 16;
    }
    std::int32_t dropped = -1;
    // The plane 1 m above the camera (site z down): no ray meets it going down.
    ASSERT_TRUE(boundByGround(g, g.left_centre_site_m.z() - 1.0, 0, 1, ImageView<std::int16_t>(disparity, kBw, kBh),
                              dropped)
                    .isOk());
    EXPECT_EQ(dropped, 0);
    // A level camera (rect +z = north): rows above the centre row look up or level, never
    // bounded; rows below are, and a window far beyond every bound keeps them all.
    g.R_site_from_rect << 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;  // rect x east, y down, z north
    ASSERT_TRUE(g.validate().isOk());
    ASSERT_TRUE(boundByGround(g, g.left_centre_site_m.z() + 2.0, 0, 10000,
                              ImageView<std::int16_t>(disparity, kBw, kBh), dropped)
                    .isOk());
    EXPECT_EQ(dropped, 0);
    // The window [0, 1]: a row y below the centre meets the plane 2 m down at depth
    // 2 fy / (y - cy), disparity fx b (y - cy) / (2 fy) = (y - 24) / 4 > 2 for y > 32.
    ASSERT_TRUE(boundByGround(g, g.left_centre_site_m.z() + 2.0, 0, 1, ImageView<std::int16_t>(disparity, kBw, kBh),
                              dropped)
                    .isOk());
    EXPECT_EQ(dropped, (kBh - 33) * kBw);
    for (std::int32_t y = 0; y < kBh; ++y) {
        EXPECT_EQ(disparity[y * kBw], y > 32 ? kNoDisparity : 16) << y;
    }
}

TEST(GroundBound, BadInputsAreNamedAndChangeNothing) {
    static std::int16_t disparity[16 * 16];
    for (std::int16_t& d : disparity) {
        d = 100;
    }
    const ImageView<std::int16_t> view(disparity, 16, 16);
    std::int32_t dropped = -1;
    RectifiedGeometry bad = testGeometry(0.5);
    bad.baseline_m = 0.0;
    EXPECT_EQ(boundByGround(bad, 3.0, 0, 10, view, dropped).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(dropped, 0);
    const RectifiedGeometry g = testGeometry(0.5);
    EXPECT_STREQ(boundByGround(g, std::nan(""), 0, 10, view, dropped).reason(),
                 "boundByGround: plane_z_site_m is not finite");
    EXPECT_STREQ(boundByGround(g, 3.0, 10, 0, view, dropped).reason(),
                 "boundByGround: window_min_px is above window_max_px");
    EXPECT_STREQ(boundByGround(g, 3.0, 0, 10, ImageView<std::int16_t>(), dropped).reason(),
                 "boundByGround: disparity_px16 is empty");
    for (const std::int16_t d : disparity) {
        ASSERT_EQ(d, 100);
    }
}

// ---- the rectified pair in the site frame ---------------------------------------------

// A CAHV camera with optical frame R (rows, in its reference frame), centre c, pinhole
// intrinsics f, cx, cy.
CameraModel cahv(const Mat3& R, const Vec3& c, double f, double cx, double cy) {
    CameraModel m;
    m.kind = CameraModelKind::kCahv;
    m.width_px = 320;
    m.height_px = 240;
    const Vec3 a = R.row(2).transpose();
    const Vec3 h = f * R.row(0).transpose() + cx * a;
    const Vec3 v = f * R.row(1).transpose() + cy * a;
    for (int i = 0; i < 3; ++i) {
        m.c[i] = c[i];
        m.a[i] = a[i];
        m.h[i] = h[i];
        m.v[i] = v[i];
    }
    return m;
}

TEST(RectifiedGeometryOf, SitePointsComeBackThroughTheRectifiedPairOfCahvCameras) {
    // Camera A: a CAHV model with its centre at C != 0 in its reference frame; camera B:
    // the same camera 1.5 m to A's right, its model in a reference frame of its own
    // (X_b = R_b_from_a X_a + t, R a 2.9 deg turn), where its centre is again c_a.
    const Mat3 R_opt = (Eigen::AngleAxisd(0.35, Vec3(1.0, 0.0, 0.0)) *
                        Eigen::AngleAxisd(0.2, Vec3(0.0, 1.0, 0.0))).toRotationMatrix();
    const Vec3 c_a(0.4, -0.2, 1.1);
    const CameraModel a = cahv(R_opt, c_a, 300.0, 160.0, 120.0);
    const Mat3 R_b_from_a = Eigen::AngleAxisd(0.05, Vec3(0.1, 1.0, 0.0).normalized()).toRotationMatrix();
    const Vec3 c_b_in_a = c_a + R_opt.transpose() * Vec3(1.5, 0.02, 0.01);
    const Vec3 t_b_from_a = c_a - R_b_from_a * c_b_in_a;  // B's centre in B's frame: c_a
    const CameraModel b = cahv(R_opt * R_b_from_a.transpose(), c_a, 300.0, 160.0, 120.0);
    rectify::Config config;
    config.max_width = 320;
    config.max_height = 240;
    config.range_min_m = 2.0;
    config.range_max_m = 100.0;
    std::vector<std::byte> pool(rectify::Rectifier::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    static rectify::Rectifier rectifier;
    ASSERT_TRUE(rectifier.init(config, arena).isOk());
    rectify::RectifyInput in;
    in.pair.model_a = a;
    in.pair.model_b = b;
    in.pair.b_from_a.R = R_b_from_a;
    in.pair.b_from_a.t_m = t_b_from_a;
    rectify::RectifiedPair pair;
    ASSERT_TRUE(rectifier.compute(in, pair).isOk());
    RigidPose site_from_a;
    site_from_a.R = Eigen::AngleAxisd(1.1, Vec3(0.0, 0.0, 1.0)).toRotationMatrix();
    site_from_a.t_m = Vec3(10.0, -4.0, -0.3);
    RectifiedGeometry g;
    ASSERT_TRUE(rectifiedGeometry(pair, site_from_a, g).isOk());
    // The fields, as documented.
    EXPECT_EQ(g.fx_px, pair.model_a.fx_px);
    EXPECT_EQ(g.cx_left_px, pair.model_a.cx_px);
    EXPECT_EQ(g.cx_right_px, pair.model_b.cx_px);
    EXPECT_EQ(g.baseline_m, pair.centre_b_rect_m.x());
    // The left centre is camera A's projection centre in the site frame (truth: C).
    EXPECT_LE((g.left_centre_site_m - (site_from_a.R * c_a + site_from_a.t_m)).cwiseAbs().maxCoeff(), 1e-12);
    // Site points seen by camera A project, through the true cameras, to pixels of A and B;
    // their rectified pixels and disparity triangulate back to the point.
    TriangulationLimits limits;
    limits.max_sigma_ratio = 1.0;
    Random rng(21);
    std::int32_t tested = 0;
    for (std::int32_t i = 0; i < 50; ++i) {
        const double u = rng.uniform01();
        const double v = rng.uniform01();
        const double r = rng.uniform01();
        const Vec3 dir_opt(0.6 * (u - 0.5), 0.4 * (v - 0.5), 1.0);
        const Vec3 x_a = c_a + R_opt.transpose() * ((5.0 + 40.0 * r) * dir_opt);  // in A's frame
        Vec2 pa;
        Vec2 pb;
        Vec2 ra;
        Vec2 rb;
        if (!projectPoint(a, x_a, pa).isOk() || !projectPoint(b, Vec3(R_b_from_a * x_a + t_b_from_a), pb).isOk() ||
            !rectifier.rectifyPixel(rectify::Rectifier::Side::kA, pa, ra).isOk() ||
            !rectifier.rectifyPixel(rectify::Rectifier::Side::kB, pb, rb).isOk()) {
            continue;
        }
        TerrainPoint tp{};
        ASSERT_TRUE(triangulatePixel(g, limits, ra.x(), ra.y(), ra.x() - rb.x(), 0.1, tp).isOk());
        const Vec3 site = site_from_a.R * x_a + site_from_a.t_m;
        const Vec3 got(tp.x_m, tp.y_m, tp.z_m);
        EXPECT_LE((got - site).norm(), 1e-5 * (x_a - c_a).norm() + 1e-5) << i;
        ++tested;
    }
    EXPECT_GT(tested, 40);
}

TEST(RectifiedGeometryOf, ANonRotationIsRefusedAndLeavesTheOutputAlone) {
    rectify::RectifiedPair pair;
    pair.model_a = makePinhole(64, 48, 60.0);
    pair.model_b = pair.model_a;
    pair.centre_b_rect_m = Vec3(0.3, 0.0, 0.0);
    RigidPose pose;
    RectifiedGeometry g;
    g.fx_px = 7.0;
    ASSERT_TRUE(rectifiedGeometry(pair, pose, g).isOk());
    EXPECT_EQ(g.fx_px, pair.model_a.fx_px);
    EXPECT_TRUE(g.left_centre_site_m == Vec3::Zero());
    pose.R(0, 0) = 2.0;
    RectifiedGeometry untouched;
    untouched.fx_px = 7.0;
    const Status s = rectifiedGeometry(pair, pose, untouched);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_STREQ(s.reason(), "rectified geometry: R_site_from_rect is not a rotation");
    EXPECT_EQ(untouched.fx_px, 7.0);
    pair.centre_b_rect_m = Vec3::Zero();
    pose.R = Mat3::Identity();
    EXPECT_STREQ(rectifiedGeometry(pair, pose, untouched).reason(), "rectified geometry: baseline_m must not be 0");
}

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

// A producer that has already reduced its points (the octree) writes summaries: the map
// must equal the map of the points themselves (highest, lowest, count exactly; the mean
// to float rounding), and a summary that would saturate keeps the mean as merge() does.
TEST(HeightMap, MergedCellSummariesEqualTheMapOfTheirPoints) {
    Random rng(5U);
    std::vector<TerrainPoint> pts(400);
    for (TerrainPoint& p : pts) {
        const double n = -4.99 + 5.98 * rng.uniform01();
        const double e = 10.0 + 9.99 * rng.uniform01();
        const double u = std::cos(e) + 0.2 * rng.uniform01();
        p = at(n, e, u);
    }
    MapFixture direct(grid(), Reducer::kMean), summed(grid(), Reducer::kMean);
    ASSERT_TRUE(direct.map.add(Span<const TerrainPoint>(pts.data(), pts.size())).isOk());
    // Summaries by hand: groups of up to 3 consecutive points of one cell.
    const double south = grid().north_edge_m - grid().rows * grid().cell_m;
    NoHeapScope scope;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const TerrainPoint& p = pts[i];
        const auto col = static_cast<std::int32_t>(std::floor((p.y_m - grid().west_edge_m) / grid().cell_m));
        const auto row = grid().rows - 1 - static_cast<std::int32_t>(std::floor((p.x_m - south) / grid().cell_m));
        CellSummary s;
        s.highest_m = -p.z_m;
        s.lowest_m = -p.z_m;
        s.sum_m = -p.z_m;
        s.count = 1U;
        ASSERT_TRUE(summed.map.mergeCell(col, row, s).isOk());
    }
    EXPECT_EQ(summed.map.mergeCell(0, 0, CellSummary{}).code(), StatusCode::kOk);  // count 0: nothing
    EXPECT_EQ(summed.map.mergeCell(grid().cols, 0, CellSummary{1.0F, 1.0F, 1.0F, 1U}).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(summed.map.mergeCell(0, -1, CellSummary{1.0F, 1.0F, 1.0F, 1U}).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(scope.heapCalls(), 0U);
    std::int32_t filled = 0;
    for (int r = 0; r < grid().rows; ++r) {
        for (int c = 0; c < grid().cols; ++c) {
            const float h1 = summed.map.highest(c, r), h2 = direct.map.highest(c, r);
            const float l1 = summed.map.lowest(c, r), l2 = direct.map.lowest(c, r);
            EXPECT_EQ(std::memcmp(&h1, &h2, sizeof h1), 0) << c << "," << r;
            EXPECT_EQ(std::memcmp(&l1, &l2, sizeof l1), 0) << c << "," << r;
            ASSERT_EQ(summed.map.count(c, r), direct.map.count(c, r));
            if (direct.map.count(c, r) > 0) {
                ++filled;
                EXPECT_NEAR(summed.map.elevation(c, r), direct.map.elevation(c, r), 1e-5);
            }
        }
    }
    EXPECT_GT(filled, 150);
    // Saturation: 60000 + 10000 points of means 1 and 2 in one cell -> count 65535, mean
    // (60000 + 20000) / 70000, extremes kept.
    MapFixture sat(grid(), Reducer::kMean);
    ASSERT_TRUE(sat.map.mergeCell(2, 3, CellSummary{1.5F, 0.5F, 60000.0F, 60000U}).isOk());
    ASSERT_TRUE(sat.map.mergeCell(2, 3, CellSummary{4.0F, 1.0F, 20000.0F, 10000U}).isOk());
    EXPECT_EQ(sat.map.count(2, 3), 65535U);
    EXPECT_NEAR(sat.map.elevation(2, 3), 80000.0 / 70000.0, 1e-4);
    EXPECT_EQ(sat.map.highest(2, 3), 4.0F);
    EXPECT_EQ(sat.map.lowest(2, 3), 0.5F);
    HeightMap never;
    EXPECT_EQ(never.mergeCell(0, 0, CellSummary{}).code(), StatusCode::kNotInitialized);
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
