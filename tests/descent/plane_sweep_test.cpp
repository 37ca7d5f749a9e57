// vtm_descent_tests: the descent plane sweep on simulator-rendered nadir pairs (128 x 128,
// 12 bit) of a sloped plane, against the renderer's per-pixel truth; the focus-of-
// expansion mask against its analytic position; errors; determinism; no heap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "descent_scene.hpp"
#include "no_heap_guard.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent {
namespace {

constexpr std::int32_t kSize = 128;
constexpr double kAlt1 = 100.0;  // camera 1 above the plane's elevation at the origin
constexpr double kAlt2 = 60.0;
const Vec3 kEye1(0.0, 0.0, -kAlt1);
const Vec3 kEye2(3.0, -4.0, -kAlt2);  // 5 m drift: the focus of expansion is inside the image

sim::TerrainParams slopedPlane() {
    sim::TerrainParams p;
    p.kind = sim::TerrainKind::kPlane;
    p.finest_cell_m = 0.1;
    p.samples_log2 = 6;
    p.levels = 8;
    p.plane_slope_north = 0.1;  // rises 0.1 m per metre north
    p.albedo_wavelength_m = 4.0;
    p.texture_longest_wavelength_m = 4.0;  // texture at the scale of a few pixels (0.65 m at 100 m)
    p.texture_contrast = 0.5;
    p.albedo_variation = 0.6;
    return p;
}

struct Pair {
    CameraModel camera;
    test::RenderedFrame f1;
    test::RenderedFrame f2;
    PairGeometry geometry;
};

const Pair& pair() {
    static Pair p = [] {
        Pair q;
        const sim::Terrain& t = test::buildTerrain(slopedPlane());
        q.camera = makePinhole(kSize, kSize, 45.0);
        // A 12-bit sensor at about half scale, light vignetting.
        sim::SensorParams sensor;
        sensor.gain_dn_per_e = 0.16;
        sensor.full_well_e = 60000.0;
        sensor.vignetting = 0.05;
        q.f1 = test::render(t, q.camera, test::nadirPose(kEye1), 0U, sensor);
        q.f2 = test::render(t, q.camera, test::nadirPose(kEye2), 1U, sensor);
        q.geometry.camera = q.camera;
        q.geometry.site_from_cam1 = q.f1.pose;
        q.geometry.site_from_cam2 = q.f2.pose;
        return q;
    }();
    return p;
}

Config testConfig(Score score = Score::kSad) {
    Config c;
    c.max_width = kSize;
    c.max_height = kSize;
    c.planes = 48;
    c.depth_min_m = 80.0;
    c.depth_max_m = 125.0;
    c.window = 7;
    c.score = score;
    c.min_parallax_px = 4.0;
    c.band_rows = 16;
    return c;
}

struct SweepRun {
    std::vector<float> depth;
    std::vector<float> score;
    std::vector<std::uint8_t> reason;
    SweepStats stats;
    Status status;
    std::uint64_t heapCalls = 0;
};

SweepRun runSweep(const Config& config, const PairGeometry& geometry) {
    const Pair& p = pair();
    SweepRun r;
    const std::size_t n = static_cast<std::size_t>(kSize) * kSize;
    r.depth.assign(n, 0.0F);
    r.score.assign(n, 0.0F);
    r.reason.assign(n, 255U);
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    PlaneSweep sweep;
    EXPECT_TRUE(sweep.init(config, arena).isOk());
    arena.freeze();
    const SweepOutput out{ImageView<float>(r.depth.data(), kSize, kSize), ImageView<float>(r.score.data(), kSize, kSize),
                          ImageView<std::uint8_t>(r.reason.data(), kSize, kSize)};
    vtm::test::NoHeapScope guard;
    r.status = sweep.compute(ImageView<const std::uint16_t>(p.f1.image.data(), kSize, kSize),
                             ImageView<const std::uint16_t>(p.f2.image.data(), kSize, kSize), geometry, out, &r.stats);
    r.heapCalls = guard.heapCalls();
    return r;
}

// Image-2 position of image-1 pixel (x, y) at `depth` along camera 1's axis, from the
// pair's true geometry: the test's own projection, not the module's.
Vec2 image2At(double x, double y, double depth) {
    struct Motion {
        Mat3 K, Kinv, R;
        Vec3 t;
    };
    static const Motion m = [] {
        const Pair& p = pair();
        Motion q;
        q.R = p.geometry.site_from_cam2.R.transpose() * p.geometry.site_from_cam1.R;
        q.t = p.geometry.site_from_cam2.R.transpose() * (p.geometry.site_from_cam1.t_m - p.geometry.site_from_cam2.t_m);
        q.K << p.camera.fx_px, 0, p.camera.cx_px, 0, p.camera.fy_px, p.camera.cy_px, 0, 0, 1;
        q.Kinv = q.K.inverse();
        return q;
    }();
    const Vec3 X1 = m.Kinv * Vec3(x, y, 1.0) * depth;
    const Vec3 q = m.K * (m.R * X1 + m.t);
    return Vec2(q.x() / q.z(), q.y() / q.z());
}

// Registration error of the valid pixels, image-2 pixels: distance between image 1's
// pixel mapped through the estimated depth's plane and through the true depth's plane.
// (Depth error itself scales with 1 / parallax, which vanishes at the focus of expansion.)
std::vector<double> registrationErrors(const SweepRun& r) {
    const Pair& p = pair();
    std::vector<double> e;
    for (std::int32_t y = 0; y < kSize; ++y) {
        for (std::int32_t x = 0; x < kSize; ++x) {
            const auto i = static_cast<std::size_t>(y * kSize + x);
            if (r.reason[i] == static_cast<std::uint8_t>(Reason::kValid)) {
                e.push_back((image2At(x, y, r.depth[i]) - image2At(x, y, p.f1.depth_m[i])).norm());
            }
        }
    }
    std::sort(e.begin(), e.end());
    return e;
}

double quantile(const std::vector<double>& sorted, double q) {
    return sorted.empty() ? 1e9 : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

void expectAccurate(const SweepRun& r) {
    ASSERT_TRUE(r.status.isOk()) << r.status.reason();
    // Image 2 sees about (60/100)^2 of image 1's ground.
    EXPECT_GT(r.stats.valid_pixels, kSize * kSize / 6);
    const std::vector<double> e = registrationErrors(r);
    EXPECT_LT(quantile(e, 0.5), 0.1) << "median registration error, image-2 px";
    EXPECT_LT(quantile(e, 0.95), 0.3) << "95th percentile registration error, image-2 px";
    EXPECT_LT(quantile(e, 1.0), 1.0) << "largest registration error, image-2 px";
    // In depth: 95 % of the valid pixels within 1.5 % (the mask keeps >= 4 px of parallax
    // over a range of 45 % of the depth, so 0.1 px is at worst about 1.1 %).
    const Pair& p = pair();
    std::vector<double> d;
    for (std::size_t i = 0; i < r.depth.size(); ++i) {
        if (r.reason[i] == 0U) {
            d.push_back(std::fabs(static_cast<double>(r.depth[i]) - p.f1.depth_m[i]) / p.f1.depth_m[i]);
        }
    }
    std::sort(d.begin(), d.end());
    EXPECT_LT(quantile(d, 0.5), 0.005);
    EXPECT_LT(quantile(d, 0.95), 0.015);
}

TEST(PlaneSweep, SlopedPlaneDepthIsRecoveredWithSad) {
    const SweepRun r = runSweep(testConfig(), pair().geometry);
    expectAccurate(r);
    EXPECT_EQ(r.heapCalls, 0U);
    // The 100 m / 60 m pair: image 2 is 100/60 = 1.67 times larger.
    EXPECT_NEAR(r.stats.scale, kAlt1 / kAlt2, 0.05);
}

TEST(PlaneSweep, SlopedPlaneDepthIsRecoveredWithNcc) {
    const SweepRun r = runSweep(testConfig(Score::kNcc), pair().geometry);
    expectAccurate(r);
    EXPECT_EQ(r.heapCalls, 0U);
    for (std::size_t i = 0; i < r.score.size(); ++i) {
        if (r.reason[i] == 0U) {
            ASSERT_GE(r.score[i], 0.0F);
            ASSERT_LE(r.score[i], 2.0F);
        }
    }
}

// The largest image-2 step between neighbouring planes of an n-plane sweep of c's range
// over the pixels that got a depth.
double largestStepOverValidPixels(const Config& c, const SweepRun& r, std::int32_t n) {
    const double far = 1.0 / c.depth_max_m;
    const double step = (1.0 / c.depth_min_m - far) / static_cast<double>(n - 1);
    double largest = 0.0;
    for (std::int32_t y = 0; y < kSize; ++y) {
        for (std::int32_t x = 0; x < kSize; ++x) {
            if (r.reason[static_cast<std::size_t>(y * kSize + x)] != 0U) {
                continue;
            }
            for (std::int32_t k = 0; k + 1 < n; ++k) {
                const double d =
                    (image2At(x, y, 1.0 / (far + step * (k + 1))) - image2At(x, y, 1.0 / (far + step * k))).norm();
                largest = std::max(largest, d);
            }
        }
    }
    return largest;
}

// max_plane_step_px: fewer planes where the parallax allows, no step above the limit
// where a depth is published (within the 33 x 33 grid's reach), not many more planes than
// the published depths need, and the depths meet the same truth bounds as the full sweep.
TEST(PlaneSweep, FewerPlanesWhereTheParallaxAllowsWithTheSameAccuracy) {
    Config c = testConfig(Score::kNcc);
    const SweepRun all = runSweep(c, pair().geometry);
    ASSERT_TRUE(all.status.isOk());
    EXPECT_EQ(all.stats.planes, c.planes);
    c.max_plane_step_px = 1.5;
    const SweepRun fewer = runSweep(c, pair().geometry);
    expectAccurate(fewer);
    EXPECT_EQ(fewer.heapCalls, 0U);
    std::printf("[ planes ] %d of %d, largest parallax %.1f px\n", fewer.stats.planes, c.planes,
                fewer.stats.max_parallax_px);
    ASSERT_GE(fewer.stats.planes, 3);
    ASSERT_LT(fewer.stats.planes, c.planes);
    EXPECT_LE(largestStepOverValidPixels(c, fewer, fewer.stats.planes), 1.05 * c.max_plane_step_px);
    // Not wasteful: the module counts over every point image 2 sees at both ends of the
    // range, the published depths are fewer (window and focus-of-expansion masks), so it
    // may keep a plane or two more than they need, not three.
    EXPECT_GT(largestStepOverValidPixels(c, fewer, fewer.stats.planes - 3), c.max_plane_step_px);
    // The accuracy of the full sweep, within 0.05 px of registration at the median.
    EXPECT_LT(quantile(registrationErrors(fewer), 0.5), quantile(registrationErrors(all), 0.5) + 0.05);
    // A limit below what the capacity allows sweeps every plane: the same bits as 0.
    c.max_plane_step_px = 0.01;
    const SweepRun capped = runSweep(c, pair().geometry);
    ASSERT_TRUE(capped.status.isOk());
    EXPECT_EQ(capped.stats.planes, c.planes);
    EXPECT_EQ(0, std::memcmp(capped.depth.data(), all.depth.data(), all.depth.size() * sizeof(float)));
}

TEST(PlaneSweep, CheckCameraAcceptsOnlyAnUndistortedPinhole) {
    EXPECT_TRUE(checkCamera(pair().camera).isOk());
    CameraModel distorted = pair().camera;
    distorted.k1 = 0.01;
    const Status st = checkCamera(distorted);
    EXPECT_EQ(st.code(), StatusCode::kUnsupported);
    EXPECT_NE(std::string(st.reason()).find("undistorted"), std::string::npos);
}

// A sweep initialised for another depth range and retargeted with setDepthRange() gives
// the bits of one initialised for the right range (a lander's range changes every pair).
TEST(PlaneSweep, SetDepthRangeRetargetsWithoutNewMemory) {
    const Config right = testConfig();
    const SweepRun reference = runSweep(right, pair().geometry);
    ASSERT_TRUE(reference.status.isOk());
    Config wrong = right;
    wrong.depth_min_m = 10.0 * right.depth_min_m;
    wrong.depth_max_m = 10.0 * right.depth_max_m;
    wrong.min_parallax_px = 0.0;
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(wrong));
    Arena arena(pool.data(), pool.size());
    PlaneSweep sweep;
    EXPECT_EQ(sweep.setDepthRange(1.0, 2.0, 0.0).code(), StatusCode::kNotInitialized);
    ASSERT_TRUE(sweep.init(wrong, arena).isOk());
    arena.freeze();
    // A refused range names the field and leaves the previous one in force.
    const Status bad = sweep.setDepthRange(right.depth_max_m, right.depth_min_m, right.min_parallax_px);
    EXPECT_EQ(bad.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::string(bad.reason()).find("depth_max_m"), std::string::npos);
    EXPECT_EQ(sweep.config().depth_min_m, wrong.depth_min_m);
    ASSERT_TRUE(sweep.setDepthRange(right.depth_min_m, right.depth_max_m, right.min_parallax_px).isOk());
    const std::size_t n = static_cast<std::size_t>(kSize) * kSize;
    std::vector<float> depth(n), score(n);
    std::vector<std::uint8_t> reason(n);
    const Pair& p = pair();
    const SweepOutput out{ImageView<float>(depth.data(), kSize, kSize), ImageView<float>(score.data(), kSize, kSize),
                          ImageView<std::uint8_t>(reason.data(), kSize, kSize)};
    ASSERT_TRUE(sweep.compute(ImageView<const std::uint16_t>(p.f1.image.data(), kSize, kSize),
                              ImageView<const std::uint16_t>(p.f2.image.data(), kSize, kSize), pair().geometry, out)
                    .isOk());
    EXPECT_EQ(0, std::memcmp(depth.data(), reference.depth.data(), n * sizeof(float)));
    EXPECT_EQ(reason, reference.reason);
}

// Image-1 pixel of the focus of expansion: where camera 2's centre projects in camera 1.
Vec2 focusOfExpansion() {
    const Pair& p = pair();
    const Vec3 c2 = p.geometry.site_from_cam1.R.transpose() * (kEye2 - kEye1);
    return Vec2(p.camera.fx_px * c2.x() / c2.z() + p.camera.cx_px, p.camera.fy_px * c2.y() / c2.z() + p.camera.cy_px);
}

TEST(PlaneSweep, LowParallaxMaskSurroundsTheFocusOfExpansion) {
    const Config c = testConfig();
    const SweepRun r = runSweep(c, pair().geometry);
    ASSERT_TRUE(r.status.isOk());
    const Vec2 foe = focusOfExpansion();
    ASSERT_TRUE(foe.x() > 20.0 && foe.x() < kSize - 20.0 && foe.y() > 20.0 && foe.y() < kSize - 20.0);
    // Radial flow: a pixel rho from the FOE moves to rho * z / (z - dz) about the FOE in
    // image 2, so the parallax between the two extreme planes is rho * (s_near - s_far).
    const double dz = kAlt1 - kAlt2;
    const double spread = c.depth_min_m / (c.depth_min_m - dz) - c.depth_max_m / (c.depth_max_m - dz);
    const double radius = c.min_parallax_px / spread;
    std::int32_t masked = 0;
    for (std::int32_t y = 0; y < kSize; ++y) {
        for (std::int32_t x = 0; x < kSize; ++x) {
            const double rho = (Vec2(x, y) - foe).norm();
            const bool low = r.reason[static_cast<std::size_t>(y * kSize + x)] == static_cast<std::uint8_t>(Reason::kLowParallax);
            masked += low ? 1 : 0;
            if (rho < 0.9 * radius) {
                EXPECT_TRUE(low) << x << "," << y;
            }
            if (rho > 1.1 * radius) {
                EXPECT_FALSE(low) << x << "," << y;
            }
        }
    }
    EXPECT_EQ(masked, r.stats.reason_counts[static_cast<std::int32_t>(Reason::kLowParallax)]);
    EXPECT_GT(masked, 20);
}

TEST(PlaneSweep, TwoRunsAndAnyBandHeightGiveTheSameBits) {
    const SweepRun a = runSweep(testConfig(), pair().geometry);
    const SweepRun b = runSweep(testConfig(), pair().geometry);
    Config other = testConfig();
    other.band_rows = 5;
    const SweepRun c = runSweep(other, pair().geometry);
    ASSERT_TRUE(a.status.isOk() && b.status.isOk() && c.status.isOk());
    const std::size_t bytes = a.depth.size() * sizeof(float);
    EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(a.depth.data(), c.depth.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(a.score.data(), c.score.data(), bytes), 0);
    EXPECT_EQ(a.reason, c.reason);
}

TEST(PlaneSweep, EveryPixelGetsADepthOrAReason) {
    const SweepRun r = runSweep(testConfig(), pair().geometry);
    ASSERT_TRUE(r.status.isOk());
    std::int32_t total = 0;
    for (const std::int32_t n : r.stats.reason_counts) {
        total += n;
    }
    EXPECT_EQ(total, kSize * kSize);
    for (std::size_t i = 0; i < r.depth.size(); ++i) {
        ASSERT_LT(r.reason[i], kReasonCount);
        ASSERT_EQ(std::isfinite(r.depth[i]), r.reason[i] == 0U) << i;
    }
    // The window leaves image 1 on the outer 3 rows and columns.
    EXPECT_EQ(r.reason[0], static_cast<std::uint8_t>(Reason::kBorder));
    EXPECT_EQ(r.reason[static_cast<std::size_t>(kSize * kSize - 1)], static_cast<std::uint8_t>(Reason::kBorder));
    // Image 1's outer ring is not seen by the closer camera 2.
    EXPECT_EQ(r.reason[static_cast<std::size_t>(5 * kSize + 5)], static_cast<std::uint8_t>(Reason::kOutOfView));
}

TEST(PlaneSweep, TrueDepthThroughTheHeightMapIsThePlane) {
    // The depth-to-height-map step alone, fed the renderer's true depth (with a NaN hole),
    // into a mean height map: every cell holds the mean elevation of the points in it,
    // which for the plane is its value at the cell centre within the slope's spread over
    // the cell; empty cells are NO_DATA; every valid pixel is counted once.
    const Pair& p = pair();
    std::vector<float> depth = p.f1.depth_m;
    for (std::int32_t y = 60; y < 68; ++y) {
        for (std::int32_t x = 0; x < kSize; ++x) {
            depth[static_cast<std::size_t>(y * kSize + x)] = std::numeric_limits<float>::quiet_NaN();
        }
    }
    // 4 m cells over 120 m x 120 m around the nadir point (the image covers about 83 m).
    constexpr std::int32_t kCells = 30;
    terrain::HeightMapConfig mc;
    mc.grid.north_edge_m = 60.0;
    mc.grid.west_edge_m = -60.0;
    mc.grid.cell_m = 4.0;
    mc.grid.cols = kCells;
    mc.grid.rows = kCells;
    mc.reducer = terrain::Reducer::kMean;
    std::vector<std::byte> pool(terrain::HeightMap::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    terrain::HeightMap map;
    ASSERT_TRUE(map.init(mc, arena).isOk());
    terrain::HeightMapStats stats;
    vtm::test::NoHeapScope guard;
    const Status s = addDepthToHeightMap(ImageView<const float>(depth.data(), kSize, kSize), p.camera,
                                         p.geometry.site_from_cam1, map, &stats);
    EXPECT_EQ(guard.heapCalls(), 0U);
    ASSERT_TRUE(s.isOk()) << s.reason();
    EXPECT_EQ(stats.outside, 0);
    EXPECT_EQ(stats.added, kSize * kSize - 8 * kSize);
    std::int64_t points = 0;
    for (std::int32_t row = 0; row < kCells; ++row) {
        for (std::int32_t col = 0; col < kCells; ++col) {
            points += map.count(col, row);
            if (map.count(col, row) == 0U) {
                EXPECT_TRUE(terrain::isNoData(map.elevation(col, row)));
                continue;
            }
            const double north = mc.grid.north_edge_m - (row + 0.5) * mc.grid.cell_m;  // row 0 north
            EXPECT_NEAR(map.elevation(col, row), 0.1 * north, 0.1 * 0.5 * mc.grid.cell_m + 1e-3) << row << "," << col;
        }
    }
    EXPECT_EQ(points, kSize * kSize - 8 * kSize);
    // The corner cells lie outside the image's footprint.
    EXPECT_EQ(map.count(0, 0), 0U);
    RigidPose bad = p.geometry.site_from_cam1;
    bad.t_m.x() = std::numeric_limits<double>::quiet_NaN();
    const Status b = addDepthToHeightMap(ImageView<const float>(depth.data(), kSize, kSize), p.camera, bad, map);
    EXPECT_EQ(b.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::string(b.reason()).find("site_from_cam"), std::string::npos);
    EXPECT_EQ(addDepthToHeightMap(ImageView<const float>(depth.data(), kSize - 1, kSize), p.camera,
                                  p.geometry.site_from_cam1, map)
                  .code(),
              StatusCode::kSizeMismatch);
}

TEST(PlaneSweep, ErrorsNameTheInput) {
    const Pair& p = pair();
    Config c = testConfig();
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    PlaneSweep sweep;
    std::vector<float> depth(kSize * kSize);
    const SweepOutput out{ImageView<float>(depth.data(), kSize, kSize), {}, {}};
    const ImageView<const std::uint16_t> i1(p.f1.image.data(), kSize, kSize);
    const ImageView<const std::uint16_t> i2(p.f2.image.data(), kSize, kSize);
    EXPECT_EQ(sweep.compute(i1, i2, p.geometry, out).code(), StatusCode::kNotInitialized);
    ASSERT_TRUE(sweep.init(c, arena).isOk());
    auto reasonOf = [&](const ImageView<const std::uint16_t>& a, const ImageView<const std::uint16_t>& b,
                        const PairGeometry& g, const SweepOutput& o) { return std::string(sweep.compute(a, b, g, o).reason()); };
    EXPECT_NE(reasonOf(i1, ImageView<const std::uint16_t>(p.f2.image.data(), kSize, kSize - 1), p.geometry, out).find("image2"), std::string::npos);
    EXPECT_NE(reasonOf(i1, i2, p.geometry, SweepOutput{ImageView<float>(depth.data(), kSize - 1, kSize), {}, {}}).find("depth_m"), std::string::npos);
    std::vector<std::uint16_t> bright = p.f2.image;
    bright[100] = 5000U;
    EXPECT_NE(reasonOf(i1, ImageView<const std::uint16_t>(bright.data(), kSize, kSize), p.geometry, out).find("image2: grey level"), std::string::npos);
    PairGeometry g = p.geometry;
    g.camera.k1 = 0.01;
    EXPECT_EQ(sweep.compute(i1, i2, g, out).code(), StatusCode::kUnsupported);
    g = p.geometry;
    g.site_from_cam2.R(0, 0) = 2.0;
    EXPECT_NE(reasonOf(i1, i2, g, out).find("site_from_cam2"), std::string::npos);
    g = p.geometry;
    g.site_from_cam2.t_m = g.site_from_cam1.t_m;
    EXPECT_NE(reasonOf(i1, i2, g, out).find("site_from_cam2"), std::string::npos);
    g = p.geometry;
    g.site_from_cam2.t_m.z() += 100.0;  // camera 2 below the nearest plane
    EXPECT_EQ(sweep.compute(i1, i2, g, out).code(), StatusCode::kDegenerate);
}

TEST(PlaneSweepConfig, EveryBadFieldIsNamedAndTheWorkspaceFits) {
    auto reason = [](const Config& c) { return std::string(c.validate().reason()); };
    Config c = testConfig();
    EXPECT_TRUE(c.validate().isOk());
    c.planes = 2;
    EXPECT_NE(reason(c).find("planes"), std::string::npos);
    c = testConfig();
    c.depth_max_m = c.depth_min_m;
    EXPECT_NE(reason(c).find("depth_max_m"), std::string::npos);
    c = testConfig();
    c.depth_min_m = -1.0;
    EXPECT_NE(reason(c).find("depth_min_m"), std::string::npos);
    c = testConfig();
    c.window = 8;
    EXPECT_NE(reason(c).find("window"), std::string::npos);
    c = testConfig();
    c.band_rows = 0;
    EXPECT_NE(reason(c).find("band_rows"), std::string::npos);
    c = testConfig();
    c.min_parallax_px = -1.0;
    EXPECT_NE(reason(c).find("min_parallax_px"), std::string::npos);
    c = testConfig();
    c.max_plane_step_px = -0.5;
    EXPECT_NE(reason(c).find("max_plane_step_px"), std::string::npos);
    c.max_plane_step_px = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(reason(c).find("max_plane_step_px"), std::string::npos);
    c = testConfig();
    c.max_width = 8;
    EXPECT_NE(reason(c).find("max_width"), std::string::npos);
    EXPECT_EQ(PlaneSweep::workspaceBytes(c), 0U);
    // Exactly workspaceBytes is enough; much less is kOutOfMemory.
    c = testConfig();
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(c));
    Arena exact(pool.data(), pool.size());
    PlaneSweep sweep;
    EXPECT_TRUE(sweep.init(c, exact).isOk());
    Arena small(pool.data(), pool.size() / 2U);
    EXPECT_EQ(sweep.init(c, small).code(), StatusCode::kOutOfMemory);
    // The flight case (1024 x 1024, 64 planes, 32-row bands) stays within 4 MiB.
    Config flight;
    EXPECT_LT(PlaneSweep::workspaceBytes(flight), std::size_t{4} << 20U);
}

}  // namespace
}  // namespace vtm::descent
