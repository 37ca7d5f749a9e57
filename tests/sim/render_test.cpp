// vtm_sim_render_tests: the camera renderer against analytic scenes (plane, dome), its
// ground truth against the camera models, the true disparity of a rectified pair, the
// sensor model (exposure, vignetting, noise, clipping), determinism and the no-heap rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "terrain_pool.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"

namespace vtm::sim {
namespace {

constexpr std::int32_t kW = 96;
constexpr std::int32_t kH = 64;
constexpr double kHfovDeg = 60.0;

TerrainParams planeParams() {
    TerrainParams p;
    p.kind = TerrainKind::kPlane;
    p.finest_cell_m = 0.05;
    p.samples_log2 = 5;
    p.levels = 8;
    p.base_elevation_m = 0.3;
    p.plane_slope_north = 0.05;
    p.plane_slope_east = -0.03;
    return p;
}

TerrainParams domeParams() {
    TerrainParams p = planeParams();
    p.kind = TerrainKind::kDome;
    p.plane_slope_north = 0.0;
    p.plane_slope_east = 0.0;
    p.base_elevation_m = 0.0;
    p.centre_north_m = 3.0;
    p.finest_cell_m = 0.01;
    p.samples_log2 = 8;
    p.levels = 6;
    p.dome_centre_north_m = 3.0;
    p.dome_centre_east_m = 0.0;
    p.dome_radius_m = 1.0;
    return p;
}

TerrainParams smallMarsParams() {
    TerrainParams p = defaultMarsTerrainParams();
    p.seed = 11U;
    p.finest_cell_m = 0.02;
    p.samples_log2 = 7;
    p.levels = 8;
    p.rock_region_radius_m = 15.0;
    return p;
}

// The three worlds, each in a pool slot of its own (built once per process).
const Terrain& planeTerrain() { return terrainInPool(planeParams(), 0); }
const Terrain& domeTerrain() { return terrainInPool(domeParams(), 1); }
const Terrain& smallMarsTerrain() { return terrainInPool(smallMarsParams(), 2); }

// A CAHVOR camera of kW x kH pixels: a 60 degree pinhole's C, A, H, V, the distortion
// axis O 2 degrees off A, and a moderate barrel distortion.
CameraModel cahvorCamera() {
    CameraModel m = cahvFromPinhole(makePinhole(kW, kH, kHfovDeg));
    m.kind = CameraModelKind::kCahvor;
    const double tilt = 2.0 * 3.14159265358979323846 / 180.0;
    m.o[0] = std::sin(tilt);
    m.o[2] = std::cos(tilt);
    m.r[0] = 0.0;
    m.r[1] = -0.08;
    m.r[2] = 0.01;
    EXPECT_TRUE(validateCameraModel(m).isOk()) << validateCameraModel(m).reason();
    return m;
}

CameraModel pinholeCamera() {
    CameraModel m = makePinhole(kW, kH, kHfovDeg);
    m.k1 = -0.05;
    m.p1 = 0.001;
    return m;
}

SensorParams noiselessSensor(std::int32_t bit_depth) {
    SensorParams s;
    s.bit_depth = bit_depth;
    s.shot_noise = false;
    s.read_noise_e = 0.0;
    s.vignetting = 0.0;
    s.dark_offset_dn = 0.0;
    s.gain_dn_per_e = bit_depth == 12 ? 0.1 : 0.01;
    s.exposure_s = 0.01;  // albedo 0.25 facing the sun: 0.25/pi * 1.35e7 * 0.01 = 10700 e-
    s.full_well_e = 1e6;
    return s;
}

// Everything one render produces, in owning buffers.
struct Frame {
    std::vector<std::uint8_t> image8 = std::vector<std::uint8_t>(kW * kH);
    std::vector<std::uint16_t> image16 = std::vector<std::uint16_t>(kW * kH);
    std::vector<float> range = std::vector<float>(kW * kH);
    std::vector<float> depth = std::vector<float>(kW * kH);
    std::vector<float> point = std::vector<float>(3 * kW * kH);
    std::vector<float> normal = std::vector<float>(3 * kW * kH);
    RenderStats stats;

    FrameOutput output() {
        FrameOutput o;
        o.image8 = ImageView<std::uint8_t>(image8.data(), kW, kH);
        o.image16 = ImageView<std::uint16_t>(image16.data(), kW, kH);
        o.truth.range_m = ImageView<float>(range.data(), kW, kH);
        o.truth.depth_m = ImageView<float>(depth.data(), kW, kH);
        o.truth.point_site_m = ImageView<float>(point.data(), 3 * kW, kH);
        o.truth.normal_site = ImageView<float>(normal.data(), 3 * kW, kH);
        return o;
    }
    [[nodiscard]] Vec3 pointAt(std::int32_t x, std::int32_t y) const {
        const float* p = &point[static_cast<std::size_t>(3 * (y * kW + x))];
        return Vec3(static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2]));
    }
    [[nodiscard]] double dn(std::int32_t x, std::int32_t y, std::int32_t bits) const {
        const std::size_t i = static_cast<std::size_t>(y * kW + x);
        return bits == 12 ? static_cast<double>(image16[i]) : static_cast<double>(image8[i]);
    }
};

FrameRequest request(const Terrain& t, const CameraModel& model, const RigidPose& pose, const SensorParams& s) {
    FrameRequest r;
    r.terrain = &t;
    r.model = model;
    r.pose = pose;
    r.sensor = s;
    r.lighting.shadows = false;
    return r;
}

void render(const FrameRequest& r, Frame& f) {
    const Status s = renderFrame(r, f.output(), &f.stats);
    ASSERT_TRUE(s.isOk()) << s.reason();
}

// A camera 1.5 m above the ground at the origin, looking 3 m north and 1.2 m down.
RigidPose groundView(double ground_elevation_m) {
    return poseLookingAt(Vec3(0.0, 0.0, -(ground_elevation_m + 1.5)), Vec3(3.0, 0.2, -(ground_elevation_m + 0.3)));
}

// Site ray of pixel (x, y), as any user of the camera model computes it.
bool siteRay(const CameraModel& m, const RigidPose& pose, std::int32_t x, std::int32_t y, Vec3& origin, Vec3& dir) {
    CameraRay ray;
    if (!backProjectPixel(m, Vec2(x, y), ray).isOk()) {
        return false;
    }
    origin = pose.R * ray.origin_m + pose.t_m;
    dir = pose.R * ray.direction;
    return true;
}

Vec3 opticalAxisSite(const CameraModel& m, const RigidPose& pose) {
    const Vec3 a = m.kind == CameraModelKind::kPinholeBrown ? Vec3::UnitZ() : Vec3(m.a[0], m.a[1], m.a[2]);
    return pose.R * a;
}

// Ray parameter of the analytic plane elevation = base + sn * north + se * east (z = -elevation).
double planeT(const TerrainParams& p, const Vec3& o, const Vec3& d) {
    const double num = p.base_elevation_m + p.plane_slope_north * o.x() + p.plane_slope_east * o.y() + o.z();
    const double den = p.plane_slope_north * d.x() + p.plane_slope_east * d.y() + d.z();
    return -num / den;
}

// Nearest intersection with the sphere of the dome (NaN if none).
double sphereT(const TerrainParams& p, const Vec3& o, const Vec3& d) {
    const Vec3 c(p.dome_centre_north_m, p.dome_centre_east_m, -p.base_elevation_m);
    const Vec3 oc = o - c;
    const double b = oc.dot(d);
    const double disc = b * b - (oc.squaredNorm() - p.dome_radius_m * p.dome_radius_m);
    return disc < 0.0 ? std::numeric_limits<double>::quiet_NaN() : -b - std::sqrt(disc);
}

void expectPlaneDepth(const CameraModel& model) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    const RigidPose pose = groundView(p.base_elevation_m);
    Frame f;
    render(request(t, model, pose, noiselessSensor(8)), f);
    EXPECT_EQ(f.stats.hit_pixels, kW * kH);
    const Vec3 axis = opticalAxisSite(model, pose);
    double worst_m = 0.0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            Vec3 o;
            Vec3 d;
            ASSERT_TRUE(siteRay(model, pose, x, y, o, d));
            const double range_m = planeT(p, o, d);
            const double depth_m = range_m * d.dot(axis);
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            // Float storage: half an ulp of ~10 m is 5e-7 m; the plane heights are floats too.
            const double tol_m = 1e-6 + 2e-7 * range_m;
            EXPECT_NEAR(f.depth[i], depth_m, tol_m) << x << "," << y;
            EXPECT_NEAR(f.range[i], range_m, tol_m) << x << "," << y;
            worst_m = std::max(worst_m, std::fabs(static_cast<double>(f.depth[i]) - depth_m));
        }
    }
    ::testing::Test::RecordProperty("worst_depth_error_m", std::to_string(worst_m));
}

TEST(SimRender, PlaneDepthIsAnalyticPinholeBrown) { expectPlaneDepth(pinholeCamera()); }
TEST(SimRender, PlaneDepthIsAnalyticCahvor) { expectPlaneDepth(cahvorCamera()); }

// Dome: every hit on the dome lies on the analytic sphere within the error of the
// bilinear surface: c^2/4 times the curvature of the height field (R^2 / (R^2 - r^2)^1.5).
void expectDomeOnSphere(const CameraModel& model) {
    const TerrainParams p = domeParams();
    const Terrain& t = domeTerrain();
    const RigidPose pose = poseLookingAt(Vec3(0.0, 0.0, -1.2), Vec3(3.0, 0.0, -0.4));
    Frame f;
    render(request(t, model, pose, noiselessSensor(8)), f);
    const Vec3 centre(p.dome_centre_north_m, p.dome_centre_east_m, -p.base_elevation_m);
    const double c = p.finest_cell_m;
    const double R = p.dome_radius_m;
    int on_dome = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const Vec3 hit = f.pointAt(x, y);
            const double r = std::hypot(hit.x() - centre.x(), hit.y() - centre.y());
            if (!std::isfinite(hit.x()) || r > 0.9 * R) {
                continue;
            }
            ++on_dome;
            const double rr = std::min(r + 2.0 * c, 0.95 * R);
            const double curvature = R * R / std::pow(R * R - rr * rr, 1.5);
            const double tol_m = c * c * curvature / 4.0 + 2e-6;
            EXPECT_NEAR((hit - centre).norm(), R, tol_m) << x << "," << y;
            Vec3 o;
            Vec3 d;
            ASSERT_TRUE(siteRay(model, pose, x, y, o, d));
            const double t_sphere = sphereT(p, o, d);
            const Vec3 n = (o + t_sphere * d - centre).normalized();
            const double cos_inc = std::fabs(n.dot(d));
            if (cos_inc < 0.1) {
                continue;  // grazing: a tiny height error moves the hit far along the ray
            }
            EXPECT_NEAR(f.range[static_cast<std::size_t>(y * kW + x)], t_sphere, tol_m / cos_inc) << x << "," << y;
        }
    }
    EXPECT_GT(on_dome, kW * kH / 10);
}

TEST(SimRender, DomeHitsLieOnTheAnalyticSpherePinholeBrown) { expectDomeOnSphere(pinholeCamera()); }
TEST(SimRender, DomeHitsLieOnTheAnalyticSphereCahvor) { expectDomeOnSphere(cahvorCamera()); }

// The truth is self-consistent: the stored 3-D point projects back to its pixel, and
// range and depth are the distance and the axial distance of that point.
TEST(SimRender, TruthProjectsBackToItsPixel) {
    const Terrain& t = smallMarsTerrain();
    const double ground = t.elevationAt(0.0, 0.0);
    for (const CameraModel& model : {cahvorCamera(), pinholeCamera()}) {
        const RigidPose pose = groundView(ground);
        Frame f;
        render(request(t, model, pose, noiselessSensor(8)), f);
        ASSERT_GT(f.stats.hit_pixels, kW * kH / 2);
        CameraRay centre_ray;
        ASSERT_TRUE(backProjectPixel(model, Vec2(0.0, 0.0), centre_ray).isOk());
        const Vec3 centre_site = pose.R * centre_ray.origin_m + pose.t_m;
        const Vec3 axis = opticalAxisSite(model, pose);
        double worst_px = 0.0;
        for (std::int32_t y = 0; y < kH; ++y) {
            for (std::int32_t x = 0; x < kW; ++x) {
                const Vec3 p = f.pointAt(x, y);
                const std::size_t i = static_cast<std::size_t>(y * kW + x);
                if (!std::isfinite(p.x())) {
                    EXPECT_TRUE(std::isnan(f.range[i]) && std::isnan(f.depth[i]));
                    continue;
                }
                Vec2 pixel;
                ASSERT_TRUE(projectPoint(model, pose.R.transpose() * (p - pose.t_m), pixel)
                                .isOk());
                worst_px = std::max(worst_px, (pixel - Vec2(x, y)).norm());
                const double range = (p - centre_site).norm();
                EXPECT_NEAR(f.range[i], range, 1e-6 * range + 1e-6);
                EXPECT_NEAR(f.depth[i], (p - centre_site).dot(axis), 1e-6 * range + 1e-6);
                const Vec3 n(f.normal[3 * i], f.normal[3 * i + 1], f.normal[3 * i + 2]);
                EXPECT_NEAR(n.norm(), 1.0, 1e-6);
                EXPECT_LT(n.z(), 0.0);  // up
            }
        }
        EXPECT_LT(worst_px, 1e-3);
    }
}

// ---- true disparity -------------------------------------------------------------------

struct DisparityTruth {
    std::vector<float> disparity = std::vector<float>(kW * kH);
    std::vector<std::uint8_t> code = std::vector<std::uint8_t>(kW * kH);
    std::vector<float> depth = std::vector<float>(kW * kH);
};

void computeDisparity(const Terrain& t, const CameraModel& m, const RigidPose& left, double baseline_m,
                      DisparityTruth& out) {
    StereoTruthRequest r;
    r.terrain = &t;
    r.left_model = m;
    r.left_pose = left;
    r.baseline_m = baseline_m;
    const StereoTruthOutput o{ImageView<float>(out.disparity.data(), kW, kH),
                              ImageView<std::uint8_t>(out.code.data(), kW, kH),
                              ImageView<float>(out.depth.data(), kW, kH)};
    const Status s = rectifiedDisparity(r, o);
    ASSERT_TRUE(s.isOk()) << s.reason();
}

TEST(SimRender, RectifiedDisparityOverThePlaneIsAnalytic) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    const CameraModel m = makePinhole(kW, kH, kHfovDeg);
    const RigidPose left = groundView(p.base_elevation_m);
    const double baseline_m = 0.3;
    DisparityTruth d;
    computeDisparity(t, m, left, baseline_m, d);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            Vec3 o;
            Vec3 dir;
            ASSERT_TRUE(siteRay(m, left, x, y, o, dir));
            const double depth_m = planeT(p, o, dir) * dir.dot(opticalAxisSite(m, left));
            const double expected_px = m.fx_px * baseline_m / depth_m;
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            EXPECT_NEAR(d.disparity[i], expected_px, 1e-5 * expected_px);
            // The plane hides nothing; only the left border falls outside the right image.
            const auto expected_code = x - expected_px < -0.5 ? DisparityTruthCode::kOutOfView
                                                                : DisparityTruthCode::kVisible;
            EXPECT_EQ(d.code[i], static_cast<std::uint8_t>(expected_code)) << x << "," << y;
        }
    }
}

// Over the Mars world: a visible left pixel moved by its disparity lands, in the right
// camera's own truth, on the same 3-D point (up to the interpolation between the two
// right pixels around x - d), and the point re-projects to exactly (x - d, y).
TEST(SimRender, DisparityLeadsToTheSamePointInTheRightTruth) {
    const Terrain& t = smallMarsTerrain();
    const CameraModel m = makePinhole(kW, kH, kHfovDeg);
    const RigidPose left = groundView(t.elevationAt(0.0, 0.0));
    const double baseline_m = 0.4;
    DisparityTruth d;
    computeDisparity(t, m, left, baseline_m, d);
    const RigidPose right = rightPoseOfRectifiedPair(left, baseline_m);
    Frame fr;
    render(request(t, m, right, noiselessSensor(8)), fr);
    int visible = 0;
    int close = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            if (d.code[i] != static_cast<std::uint8_t>(DisparityTruthCode::kVisible)) {
                continue;
            }
            Vec3 o;
            Vec3 dir;
            ASSERT_TRUE(siteRay(m, left, x, y, o, dir));
            const Vec3 p_left = o + dir * (static_cast<double>(d.depth[i]) / dir.dot(opticalAxisSite(m, left)));
            const double xr = x - static_cast<double>(d.disparity[i]);
            Vec2 pixel;
            ASSERT_TRUE(projectPoint(m, right.R.transpose() * (p_left - right.t_m), pixel).isOk());
            EXPECT_NEAR(pixel.x(), xr, 1e-3);
            EXPECT_NEAR(pixel.y(), y, 1e-3);
            const auto x0 = static_cast<std::int32_t>(std::floor(xr));
            const std::int32_t x1 = std::min(x0 + 1, kW - 1);
            const double w1 = xr - x0;
            const Vec3 p_right = fr.pointAt(std::max(x0, 0), y) * (1.0 - w1) + fr.pointAt(x1, y) * w1;
            ++visible;
            close += (p_right - p_left).norm() < 0.01 * d.depth[i] ? 1 : 0;
        }
    }
    ASSERT_GT(visible, kW * kH / 2);
    EXPECT_GT(close, visible * 97 / 100);
}

// A dome in front of the plane hides part of the plane from the right camera: the codes
// agree with the analytic test "the segment right centre -> point crosses the sphere".
TEST(SimRender, OcclusionCodesAgreeWithTheAnalyticDome) {
    const TerrainParams p = domeParams();
    const Terrain& t = domeTerrain();
    const CameraModel m = makePinhole(kW, kH, kHfovDeg);
    const RigidPose left = poseLookingAt(Vec3(0.0, -0.5, -1.0), Vec3(4.0, 0.0, 0.0));
    const double baseline_m = 0.6;
    DisparityTruth d;
    computeDisparity(t, m, left, baseline_m, d);
    const Vec3 rc = rightPoseOfRectifiedPair(left, baseline_m).t_m;
    int occluded = 0;
    int agree = 0;
    int compared = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * kW + x);
            const auto code = static_cast<DisparityTruthCode>(d.code[i]);
            if (code != DisparityTruthCode::kVisible && code != DisparityTruthCode::kOccluded) {
                continue;
            }
            Vec3 o;
            Vec3 dir;
            ASSERT_TRUE(siteRay(m, left, x, y, o, dir));
            const Vec3 point = o + dir * (static_cast<double>(d.depth[i]) / dir.dot(opticalAxisSite(m, left)));
            const double dist = (point - rc).norm();
            const double ts = sphereT(p, rc, (point - rc) / dist);
            const bool hidden = std::isfinite(ts) && ts < dist - 1e-2;
            ++compared;
            agree += hidden == (code == DisparityTruthCode::kOccluded) ? 1 : 0;
            occluded += code == DisparityTruthCode::kOccluded ? 1 : 0;
        }
    }
    EXPECT_GT(occluded, 30);
    EXPECT_GE(agree, compared * 98 / 100);
}

// ---- sensor ---------------------------------------------------------------------------

TEST(SimRender, DoublingExposureDoublesTheSignal) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    FrameRequest r = request(t, pinholeCamera(), groundView(p.base_elevation_m), noiselessSensor(12));
    r.sensor.dark_offset_dn = 20.0;
    Frame a;
    Frame b;
    render(r, a);
    r.sensor.exposure_s *= 2.0;
    render(r, b);
    int compared = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double sa = a.dn(x, y, 12) - 20.0;
            const double sb = b.dn(x, y, 12) - 20.0;
            if (b.dn(x, y, 12) < 4095.0 && sa > 20.0) {
                ++compared;
                EXPECT_NEAR(sb, 2.0 * sa, 1.5);  // two roundings of half a DN each
            }
        }
    }
    EXPECT_GT(compared, kW * kH * 9 / 10);
}

TEST(SimRender, VignettingDarkensCornersByTheConfiguredFactor) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    FrameRequest r = request(t, pinholeCamera(), groundView(p.base_elevation_m), noiselessSensor(12));
    r.sensor.gain_dn_per_e = 0.2;  // ~2000 DN: rounding below 0.05 %
    Frame flat;
    Frame vignetted;
    render(r, flat);
    r.sensor.vignetting = 0.3;
    render(r, vignetted);
    const std::int32_t xs[] = {0, kW - 1};
    const std::int32_t ys[] = {0, kH - 1};
    for (const std::int32_t x : xs) {
        for (const std::int32_t y : ys) {
            ASSERT_LT(flat.dn(x, y, 12), 4095.0);
            ASSERT_GT(flat.dn(x, y, 12), 500.0);
            EXPECT_NEAR(vignetted.dn(x, y, 12) / flat.dn(x, y, 12), 0.7, 2e-3) << x << "," << y;
        }
    }
    // Middle of the left edge: rho^2 = (47.5^2 + 0.5^2) / (47.5^2 + 31.5^2), quadratic in the radius.
    const double rho2 = (47.5 * 47.5 + 0.25) / (47.5 * 47.5 + 31.5 * 31.5);
    EXPECT_NEAR(vignetted.dn(0, kH / 2, 12) / flat.dn(0, kH / 2, 12), 1.0 - 0.3 * rho2, 2e-3);
    // Centre pixels ((kW-1)/2 +- 0.5): rho^2 = 0.5^2 * 2 / corner^2, i.e. ~1e-4 of the falloff.
    EXPECT_NEAR(vignetted.dn(kW / 2, kH / 2, 12) / flat.dn(kW / 2, kH / 2, 12), 1.0, 1e-3);
}

TEST(SimRender, NoiseMatchesShotPlusReadNoise) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    FrameRequest r = request(t, pinholeCamera(), groundView(p.base_elevation_m), noiselessSensor(12));
    r.sensor.gain_dn_per_e = 0.2;  // ~ 10000 e- (sigma_shot ~ 100 e-), ~ 2100 DN
    r.sensor.dark_offset_dn = 100.0;
    Frame clean;
    render(r, clean);
    r.sensor.shot_noise = true;
    r.sensor.read_noise_e = 40.0;
    Frame noisy;
    render(r, noisy);
    double sum_sq = 0.0;
    double predicted = 0.0;
    int n = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double c = clean.dn(x, y, 12);
            if (noisy.dn(x, y, 12) >= 4095.0 || c >= 4000.0) {
                continue;
            }
            const double electrons = (c - 100.0) / 0.2;
            const double diff = noisy.dn(x, y, 12) - c;
            sum_sq += diff * diff;
            // Shot + read noise in DN^2, plus the rounding of both images (1/12 DN^2 each).
            predicted += 0.2 * 0.2 * (electrons + 40.0 * 40.0) + 2.0 / 12.0;
            ++n;
        }
    }
    ASSERT_GT(n, kW * kH * 9 / 10);
    // sqrt(2n) relative spread of a variance estimate: ~1 %; 4 % is 4 sigma.
    EXPECT_NEAR(std::sqrt(sum_sq / n) / std::sqrt(predicted / n), 1.0, 0.04);
}

TEST(SimRender, SaturationClipsAtFullWellAndAtTheTopCode) {
    const TerrainParams p = planeParams();
    const Terrain& t = planeTerrain();
    FrameRequest r = request(t, pinholeCamera(), groundView(p.base_elevation_m), noiselessSensor(12));
    r.sensor.exposure_s = 1.0;  // ~ 1e6 e-: far over the full well
    r.sensor.full_well_e = 20000.0;
    r.sensor.gain_dn_per_e = 0.1;
    r.sensor.dark_offset_dn = 10.0;
    r.sensor.read_noise_e = 5.0;
    r.sensor.shot_noise = true;
    Frame f;
    render(r, f);
    double lo = 1e9;
    double hi = 0.0;
    for (const std::uint16_t v : f.image16) {
        lo = std::min(lo, static_cast<double>(v));
        hi = std::max(hi, static_cast<double>(v));
    }
    // Full well 20000 e- -> 2010 DN, plus read noise 0.5 DN (|n| < 8.6 sigma).
    EXPECT_GE(lo, 2010.0 - 5.0);
    EXPECT_LE(hi, 2010.0 + 5.0);
    EXPECT_EQ(f.stats.saturated_pixels, kW * kH);
    // Top code: a high gain drives every pixel to 4095, never beyond.
    r.sensor.gain_dn_per_e = 10.0;
    render(r, f);
    for (const std::uint16_t v : f.image16) {
        ASSERT_EQ(v, 4095U);
    }
}

TEST(SimRender, TwelveBitOutputStaysBelow4096And8BitUsesItsRange) {
    const Terrain& t = smallMarsTerrain();
    FrameRequest r = request(t, pinholeCamera(), groundView(t.elevationAt(0.0, 0.0)), SensorParams());
    r.sensor.bit_depth = 12;
    r.sensor.gain_dn_per_e = 0.3;
    r.lighting.shadows = true;
    Frame f;
    render(r, f);
    const std::uint16_t top = *std::max_element(f.image16.begin(), f.image16.end());
    EXPECT_LE(top, 4095U);
    EXPECT_GT(top, 1000U);  // not stuck in the low byte
    r.sensor = SensorParams();
    render(r, f);
    const std::uint8_t top8 = *std::max_element(f.image8.begin(), f.image8.end());
    const std::uint8_t low8 = *std::min_element(f.image8.begin(), f.image8.end());
    EXPECT_GT(top8 - low8, 40);  // a textured, shaded image, not a flat field
}

// Shadows: a dome lit from a low sun casts a shadow on the plane behind it; the shadowed
// pixels are darker than the lit plane next to them and exist only with shadows on.
TEST(SimRender, DomeCastsAShadowOnlyWhenShadowsAreOn) {
    const Terrain& t = domeTerrain();
    FrameRequest r = request(t, makePinhole(kW, kH, kHfovDeg), poseLookingAt(Vec3(0.0, 0.0, -2.5), Vec3(3.5, 0.0, 0.0)),
                             noiselessSensor(8));
    r.lighting.to_sun_site = Vec3(-0.1, -0.9, -0.35).normalized();  // low sun in the west: shadow to the east
    Frame lit;
    render(r, lit);
    EXPECT_EQ(lit.stats.shadowed_pixels, 0);
    r.lighting.shadows = true;
    Frame shadowed;
    render(r, shadowed);
    EXPECT_GT(shadowed.stats.shadowed_pixels, 20);
    int darker = 0;
    int changed = 0;
    int much_darker = 0;
    for (std::size_t i = 0; i < lit.image8.size(); ++i) {
        changed += lit.image8[i] != shadowed.image8[i] ? 1 : 0;
        darker += shadowed.image8[i] < lit.image8[i] ? 1 : 0;
        much_darker += shadowed.image8[i] + 20 < lit.image8[i] ? 1 : 0;
    }
    EXPECT_EQ(changed, darker);  // shadows only ever darken
    EXPECT_EQ(static_cast<std::int64_t>(changed), shadowed.stats.shadowed_pixels);
    // Only the sky term is left in a shadow: most shadowed pixels lose most of their light
    // (a few on the dome's terminator had little sunlight to lose).
    EXPECT_GT(much_darker, changed * 9 / 10);
}

// ---- determinism, bands, heap, errors -------------------------------------------------

std::uint64_t fnv(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t h = 0xCBF29CE484222325ULL;
    for (const std::uint8_t b : bytes) {
        h = (h ^ b) * 0x100000001B3ULL;
    }
    return h;
}

TEST(SimRender, SameInputsGiveSameBytesAndBandsMatchTheWholeFrame) {
    const Terrain& t = smallMarsTerrain();
    FrameRequest r = request(t, cahvorCamera(), groundView(t.elevationAt(0.0, 0.0)), SensorParams());
    r.lighting.shadows = true;
    r.frame_index = 3U;
    Frame a;
    Frame b;
    render(r, a);
    render(r, b);
    EXPECT_EQ(fnv(a.image8), fnv(b.image8));
    EXPECT_EQ(std::memcmp(a.range.data(), b.range.data(), a.range.size() * sizeof(float)), 0);
    // Bands, rendered bottom band first: same bytes as the whole frame.
    Frame bands;
    const std::int32_t splits[][2] = {{40, -1}, {17, 23}, {0, 17}};
    for (const auto& band : splits) {
        r.first_row = band[0];
        r.row_count = band[1];
        render(r, bands);
    }
    EXPECT_EQ(a.image8, bands.image8);
    // Another frame index gives other noise, the same truth.
    r.first_row = 0;
    r.row_count = -1;
    r.frame_index = 4U;
    render(r, b);
    EXPECT_NE(fnv(a.image8), fnv(b.image8));
    EXPECT_EQ(std::memcmp(a.range.data(), b.range.data(), a.range.size() * sizeof(float)), 0);
}

TEST(SimRender, RenderFrameTouchesNoHeap) {
    const Terrain& t = smallMarsTerrain();
    FrameRequest r = request(t, cahvorCamera(), groundView(t.elevationAt(0.0, 0.0)), SensorParams());
    r.lighting.shadows = true;
    static std::uint8_t image[kW * kH];
    static float range[kW * kH];
    static float disparity[kW * kH];
    FrameOutput out;
    out.image8 = ImageView<std::uint8_t>(image, kW, kH);
    out.truth.range_m = ImageView<float>(range, kW, kH);
    StereoTruthRequest sr;
    sr.terrain = &t;
    sr.left_model = makePinhole(kW, kH, kHfovDeg);
    sr.left_pose = r.pose;
    sr.baseline_m = 0.3;
    StereoTruthOutput so;
    so.disparity_px = ImageView<float>(disparity, kW, kH);
    test::NoHeapScope guard;
    EXPECT_TRUE(renderFrame(r, out, nullptr).isOk());
    EXPECT_TRUE(rectifiedDisparity(sr, so).isOk());
    EXPECT_EQ(guard.heapCalls(), 0U);
}

TEST(SimRender, BadRequestsAreRejectedWithAReason) {
    const Terrain& t = planeTerrain();
    Frame f;
    FrameRequest r = request(t, pinholeCamera(), groundView(0.3), noiselessSensor(8));
    FrameRequest bad = r;
    bad.terrain = nullptr;
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    bad = r;
    bad.sensor.bit_depth = 10;
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    bad = r;
    bad.lighting.to_sun_site = Vec3(0.0, 0.0, -2.0);
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    bad = r;
    bad.pose.R(0, 0) = 2.0;
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    bad = r;
    bad.first_row = 60;
    bad.row_count = 10;
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    bad = r;
    bad.model.width_px = 4000;
    EXPECT_EQ(renderFrame(bad, f.output(), nullptr).code(), StatusCode::kInvalidArgument);
    FrameOutput wrong = f.output();
    wrong.truth.depth_m = ImageView<float>(f.depth.data(), kW - 1, kH);
    EXPECT_EQ(renderFrame(r, wrong, nullptr).code(), StatusCode::kSizeMismatch);
    wrong = f.output();
    wrong.image8 = ImageView<std::uint8_t>();
    EXPECT_EQ(renderFrame(r, wrong, nullptr).code(), StatusCode::kSizeMismatch);
    StereoTruthRequest sr;
    sr.terrain = &t;
    sr.left_model = pinholeCamera();  // distorted: not a rectified model
    sr.baseline_m = 0.3;
    const StereoTruthOutput so{ImageView<float>(f.depth.data(), kW, kH), ImageView<std::uint8_t>(),
                               ImageView<float>()};
    EXPECT_EQ(rectifiedDisparity(sr, so).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vtm::sim
