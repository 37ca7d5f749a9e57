// The panorama kind (sim/panorama.hpp, docs/sim-scenarios.md "Panorama"): stations of a
// mast stereo pair on a pan/tilt head, the seeded pointing errors and their first-order
// prior covariance, the frames buildScenarioFrames renders.
#include "scenario_panorama.hpp"

#include "rotation.hpp"
#include "scenario_geometry.hpp"
#include "sim/panorama.hpp"
#include "vtm/core/random.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::sim {
namespace {

using detail::kRadPerDeg;

// Standard deviations of the 10 error parameters, in the order of the Jacobian's columns:
// rover roll, pitch, heading [rad]; mast tilt x, y [rad]; head offset x, y, z [m]; pan, tilt [rad].
constexpr int kErrorParams = 10;
using ErrorJacobian = Eigen::Matrix<double, 6, kErrorParams>;

void parameterSigmas(const PointingErrorModel& m, double (&sigma)[kErrorParams]) noexcept {
    sigma[0] = m.rover_roll_sigma_deg * kRadPerDeg;
    sigma[1] = m.rover_pitch_sigma_deg * kRadPerDeg;
    sigma[2] = m.rover_heading_sigma_deg * kRadPerDeg;
    sigma[3] = m.mast_tilt_sigma_deg * kRadPerDeg;
    sigma[4] = m.mast_tilt_sigma_deg * kRadPerDeg;
    sigma[5] = m.head_offset_sigma_m;
    sigma[6] = m.head_offset_sigma_m;
    sigma[7] = m.head_offset_sigma_m;
    sigma[8] = m.pan_sigma_deg * kRadPerDeg;
    sigma[9] = m.tilt_sigma_deg * kRadPerDeg;
}

// The commanded view of station k.
struct Pointing {
    std::int32_t tier = 0;
    std::int32_t column = 0;
    double pan_deg = 0.0;
    double tilt_deg = 0.0;
};

Pointing commanded(const Scenario& sc, std::int32_t k) noexcept {
    Pointing p;
    p.tier = k / sc.motion.columns;
    p.column = k % sc.motion.columns;
    p.pan_deg = 360.0 * static_cast<double>(p.column) / static_cast<double>(sc.motion.columns);
    p.tilt_deg = sc.motion.tiers.deg[p.tier];
    return p;
}

// R_vehicle_from_cam of the head at (pan, tilt): the mount rotation of the other kinds.
Mat3 headRotation(double pan_rad, double tilt_rad) noexcept {
    CameraMount mount;
    mount.pan_deg = pan_rad / kRadPerDeg;
    mount.tilt_deg = tilt_rad / kRadPerDeg;
    mount.roll_deg = 0.0;
    return detail::mountRotation(mount);
}

// Left-eye origin relative to the head, camera frame.
Vec3 leftEyeOffset(const Scenario& sc) noexcept { return Vec3(-0.5 * sc.motion.stereo_baseline_m, 0.0, 0.0); }

CameraPair rigOf(const Scenario& sc) noexcept {
    CameraPair rig;
    rig.model_a = sc.camera;
    rig.model_b = sc.camera;
    rig.b_from_a.R = Mat3::Identity();
    rig.b_from_a.t_m = Vec3(-sc.motion.stereo_baseline_m, 0.0, 0.0);  // X_b = X_a - (b, 0, 0)
    return rig;
}

// d(dtheta, dt) / d(error parameters) at the telemetry's pose (sim/panorama.hpp; the
// derivation is in docs/sim-scenarios.md "Panorama"). A = rover telemetry attitude,
// R = the eye's telemetry rotation, pan = the encoder pan from the rover's heading.
ErrorJacobian pointingJacobian(const Scenario& sc, const Mat3& A, const Mat3& R, double pan_rad) noexcept {
    const Vec3 head = sc.mount.position_vehicle_m;
    const Vec3 h_s = A * head;
    const Vec3 l_s = A * Vec3(0.0, 0.0, head.z());
    const Vec3 w = R * leftEyeOffset(sc);
    const Vec3 pan_axis = A * Vec3::UnitZ();
    const Vec3 tilt_axis = A * (detail::rotationZ(pan_rad) * Vec3::UnitY());
    const Mat3 wx = skew(w);
    ErrorJacobian J = ErrorJacobian::Zero();
    J.block<3, 3>(0, 0) = -A;                                             // rover attitude
    J.block<3, 3>(3, 0) = (skew(h_s) + wx) * A;
    J.block<3, 2>(0, 3) = A.leftCols<2>();                                // mast tilt
    J.block<3, 2>(3, 3) = -(skew(l_s) + wx) * A.leftCols<2>();
    J.block<3, 3>(3, 5) = A;                                              // head offset
    J.block<3, 1>(0, 8) = -pan_axis;                                      // pan encoder
    J.block<3, 1>(3, 8) = wx * pan_axis;
    J.block<3, 1>(0, 9) = -tilt_axis;                                     // tilt encoder
    J.block<3, 1>(3, 9) = wx * tilt_axis;
    return J;
}

// J_a diag(sigma^2) J_b^T over the first `params` parameters (all 10: one station's
// covariance; the 8 per-panorama ones: the covariance between two stations).
Mat6 propagate(const Scenario& sc, const ErrorJacobian& Ja, const ErrorJacobian& Jb, int params) noexcept {
    double sigma[kErrorParams];
    parameterSigmas(sc.pointing, sigma);
    ErrorJacobian JS = Ja;
    for (int c = 0; c < kErrorParams; ++c) {  // bound: 10 parameters
        JS.col(c) *= (c < params) ? sigma[c] * sigma[c] : 0.0;
    }
    return JS * Jb.transpose();
}

Mat6 priorCovariance(const Scenario& sc, const ErrorJacobian& J) noexcept {
    const Mat6 cov = propagate(sc, J, J, kErrorParams);
    return 0.5 * (cov + cov.transpose());
}

// The Jacobian of station k of a built panorama (at its telemetry pose and encoder pan).
ErrorJacobian stationJacobian(const Scenario& sc, const Panorama& p, std::int32_t k) noexcept {
    const double pan_rad = p.stations[k].pan_deg * kRadPerDeg + p.errors.pan_error_rad[k];
    return pointingJacobian(sc, p.rover.R_telemetry, p.stations[k].approx.site_from_a.R, pan_rad);
}

constexpr int kSharedParams = 8;  // rover attitude, mast tilt, head offset: drawn once per panorama

// Rays through the middle of the left/right (or top/bottom) image edges, camera frame.
Status edgeRays(const CameraModel& m, bool horizontal, Vec3& first, Vec3& second) noexcept {
    const double w = static_cast<double>(m.width_px);
    const double h = static_cast<double>(m.height_px);
    const Vec2 a = horizontal ? Vec2(-0.5, 0.5 * (h - 1.0)) : Vec2(0.5 * (w - 1.0), -0.5);
    const Vec2 b = horizontal ? Vec2(w - 0.5, 0.5 * (h - 1.0)) : Vec2(0.5 * (w - 1.0), h - 0.5);
    CameraRay ra;
    CameraRay rb;
    if (!backProjectPixel(m, a, ra).isOk() || !backProjectPixel(m, b, rb).isOk()) {
        return Status(StatusCode::kInvalidConfig, "scenario: camera model has no ray through an image edge (panorama)");
    }
    first = ra.direction;
    second = rb.direction;
    return Status::ok();
}

// Elevation (rad) of a vehicle-frame direction in the vertical plane of pan 0.
double elevationInViewPlane(const Vec3& d) noexcept { return math::atan2(-d.z(), d.x()); }

}  // namespace

PanoramaErrors drawPanoramaErrors(const Scenario& sc) noexcept {
    Random rng(detail::streamSeed(sc.seed, detail::kPointingStream));
    double sigma[kErrorParams];
    parameterSigmas(sc.pointing, sigma);
    PanoramaErrors e;
    // One draw per statement: argument evaluation order differs between targets.
    for (int i = 0; i < 3; ++i) {  // bound: 3 axes
        const double n = rng.normal();
        e.rover_attitude_rad[i] = sigma[i] * n;
    }
    for (int i = 0; i < 2; ++i) {  // bound: 2 axes
        const double n = rng.normal();
        e.mast_tilt_rad[i] = sigma[3 + i] * n;
    }
    for (int i = 0; i < 3; ++i) {  // bound: 3 axes
        const double n = rng.normal();
        e.head_offset_m[i] = sigma[5 + i] * n;
    }
    const std::int32_t count = sc.motion.tiers.count * sc.motion.columns;
    for (std::int32_t k = 0; k < count && k < kMaxPanoramaStations; ++k) {  // bound: kMaxPanoramaStations
        const double n_pan = rng.normal();
        const double n_tilt = rng.normal();
        e.pan_error_rad[k] = sigma[8] * n_pan;
        e.tilt_error_rad[k] = sigma[9] * n_tilt;
    }
    return e;
}

PanoramaRover panoramaRover(const Scenario& sc, const Terrain& terrain, const PanoramaErrors& e) noexcept {
    PanoramaRover r;
    const Vec2 at = sc.motion.start_site_m;
    r.position_site_m = Vec3(at.x(), at.y(), -terrain.elevationAt(at.x(), at.y()));
    r.R_site_from_vehicle = detail::rotationZ(sc.motion.heading_deg * kRadPerDeg);
    r.R_telemetry = r.R_site_from_vehicle * rotationExp(e.rover_attitude_rad);
    return r;
}

PanoramaStation panoramaStation(const Scenario& sc, const PanoramaRover& rover, const PanoramaErrors& e,
                                std::int32_t k) noexcept {
    VTM_ASSERT(k >= 0 && k < kMaxPanoramaStations, k);
    const Pointing p = commanded(sc, k);
    PanoramaStation s;
    s.tier = p.tier;
    s.column = p.column;
    s.pan_deg = p.pan_deg;
    s.tilt_deg = p.tilt_deg;
    s.time_s = sc.motion.start_time_s + static_cast<double>(k) * sc.motion.station_interval_s;
    const CameraPair rig = rigOf(sc);
    const Vec3 head = sc.mount.position_vehicle_m;
    const Vec3 lever(0.0, 0.0, head.z());
    const Vec3 eye = leftEyeOffset(sc);
    // Truth: the commanded angles on the flexed mast.
    const Mat3 flex = rotationExp(Vec3(e.mast_tilt_rad.x(), e.mast_tilt_rad.y(), 0.0));
    const Mat3& Rv = rover.R_site_from_vehicle;
    const Mat3 R_true = Rv * flex * headRotation(p.pan_deg * kRadPerDeg, p.tilt_deg * kRadPerDeg);
    const Vec3 head_true = head + (flex * lever - lever) + e.head_offset_m;
    s.truth.rig = rig;
    s.truth.site_from_a.R = R_true;
    s.truth.site_from_a.t_m = rover.position_site_m + Rv * head_true + R_true * eye;
    // Telemetry: the rover's reported attitude, a rigid mast, the encoder readings.
    const double pan_rad = p.pan_deg * kRadPerDeg + e.pan_error_rad[k];
    const double tilt_rad = p.tilt_deg * kRadPerDeg + e.tilt_error_rad[k];
    const Mat3& A = rover.R_telemetry;
    const Mat3 R_approx = A * headRotation(pan_rad, tilt_rad);
    s.approx.rig = rig;
    s.approx.site_from_a.R = R_approx;
    s.approx.site_from_a.t_m = rover.position_site_m + A * head + R_approx * eye;
    s.approx.prior_covariance = priorCovariance(sc, pointingJacobian(sc, A, R_approx, pan_rad));
    return s;
}

Status buildPanorama(const Scenario& sc, const Terrain& terrain, Panorama& out) noexcept {
    VTM_RETURN_IF_ERROR(validateScenario(sc));
    if (sc.kind != ScenarioKind::kPanorama) {
        return Status(StatusCode::kInvalidConfig, "buildPanorama: scenario kind is not panorama");
    }
    if (!terrain.built()) {
        return Status(StatusCode::kInvalidArgument, "buildPanorama: terrain not built");
    }
    out.tiers = sc.motion.tiers.count;
    out.columns = sc.motion.columns;
    out.count = out.tiers * out.columns;
    out.errors = drawPanoramaErrors(sc);
    out.rover = panoramaRover(sc, terrain, out.errors);
    for (std::int32_t k = 0; k < out.count; ++k) {  // bound: count <= kMaxPanoramaStations (validated)
        out.stations[k] = panoramaStation(sc, out.rover, out.errors, k);
    }
    return Status::ok();
}

Mat6 panoramaCrossCovariance(const Scenario& sc, const Panorama& p, std::int32_t k, std::int32_t l) noexcept {
    VTM_ASSERT(k >= 0 && k < p.count && l >= 0 && l < p.count, k);
    if (k == l) {
        return p.stations[k].approx.prior_covariance;
    }
    return propagate(sc, stationJacobian(sc, p, k), stationJacobian(sc, p, l), kSharedParams);
}

Status panoramaOverlap(const Scenario& sc, PanoramaOverlap& out) noexcept {
    out = PanoramaOverlap{};
    Vec3 left;
    Vec3 right;
    Vec3 top;
    Vec3 bottom;
    VTM_RETURN_IF_ERROR(edgeRays(sc.camera, true, left, right));
    VTM_RETURN_IF_ERROR(edgeRays(sc.camera, false, top, bottom));
    const double spacing_deg = 360.0 / static_cast<double>(sc.motion.columns);
    double top_deg[kMaxPanoramaTiers] = {};
    double bottom_deg[kMaxPanoramaTiers] = {};
    for (std::int32_t t = 0; t < sc.motion.tiers.count; ++t) {  // bound: <= kMaxPanoramaTiers
        const Mat3 M = headRotation(0.0, sc.motion.tiers.deg[t] * kRadPerDeg);
        const Vec3 l = M * left;
        const Vec3 r = M * right;
        const double width_rad = math::atan2(r.y(), r.x()) - math::atan2(l.y(), l.x());
        out.horizontal_deg[t] = width_rad / kRadPerDeg - spacing_deg;
        top_deg[t] = elevationInViewPlane(M * top) / kRadPerDeg;
        bottom_deg[t] = elevationInViewPlane(M * bottom) / kRadPerDeg;
    }
    for (std::int32_t t = 0; t + 1 < sc.motion.tiers.count; ++t) {  // bound: <= kMaxPanoramaTiers - 1
        const bool upper_first = sc.motion.tiers.deg[t] >= sc.motion.tiers.deg[t + 1];
        const std::int32_t upper = upper_first ? t : t + 1;
        const std::int32_t lower = upper_first ? t + 1 : t;
        out.vertical_deg[t] = top_deg[lower] - bottom_deg[upper];
    }
    return Status::ok();
}

Status panoramaGroundPoint(const Terrain& terrain, const NetworkStation& station, Eye eye, const Vec2& pixel_px,
                           Vec3& point_site_m, double max_range_m) noexcept {
    CameraRay ray;
    VTM_RETURN_IF_ERROR(backProjectPixel(modelOfEye(station, eye), pixel_px, ray));
    const RigidPose pose = siteFromEye(station, eye);
    const TerrainHit hit = terrain.intersect(transformPoint(pose, ray.origin_m), pose.R * ray.direction, max_range_m);
    if (!hit.hit) {
        return Status(StatusCode::kNoData, "panoramaGroundPoint: the pixel sees no terrain (sky)");
    }
    point_site_m = hit.point_site_m;
    return Status::ok();
}

namespace detail {

Status panoramaFrames(const Scenario& sc, const Terrain& terrain, ScenarioFrames& out) noexcept {
    const PanoramaErrors errors = drawPanoramaErrors(sc);
    const PanoramaRover rover = panoramaRover(sc, terrain, errors);
    const std::int32_t count = sc.motion.tiers.count * sc.motion.columns;
    // The telemetry's attitude covariance: the rover errors about the vehicle axes, in site axes.
    double sigma[kErrorParams];
    parameterSigmas(sc.pointing, sigma);
    Mat3 attitude_cov = Mat3::Zero();
    for (int i = 0; i < 3; ++i) {  // bound: roll, pitch, heading
        attitude_cov(i, i) = sigma[i] * sigma[i];
    }
    attitude_cov = rover.R_site_from_vehicle * attitude_cov * rover.R_site_from_vehicle.transpose();
    for (std::int32_t k = 0; k < count; ++k) {  // bound: count <= kMaxPanoramaStations (validated)
        const PanoramaStation s = panoramaStation(sc, rover, errors, k);
        for (std::int32_t e = 0; e < 2; ++e) {  // bound: 2 eyes
            ScenarioFrame& f = out.frames[2 * k + e];
            f.index = static_cast<std::uint32_t>(2 * k + e);
            f.role = (e == 0) ? FrameRole::kStereoLeft : FrameRole::kStereoRight;
            f.camera_id = (e == 0) ? kStereoLeftCameraId : kStereoRightCameraId;
            f.sequence = static_cast<std::uint32_t>(k);
            f.timestamp_ns = detail::toNanoseconds(s.time_s);
            f.true_pose = detail::vehiclePose(rover.position_site_m, rover.R_site_from_vehicle, s.time_s);
            f.odometry_pose = detail::vehiclePose(rover.position_site_m, rover.R_telemetry, s.time_s);
            for (int r = 0; r < 3; ++r) {  // bound: 3x3 attitude block of (x, y, z, rx, ry, rz)
                for (int c = 0; c < 3; ++c) {  // bound: 3
                    f.odometry_pose.covariance[(3 + r) * 6 + 3 + c] = attitude_cov(r, c);
                }
            }
            f.model = sc.camera;
            f.camera_pose = siteFromEye(s.truth, (e == 0) ? Eye::kLeft : Eye::kRight);
            f.sensor = sc.sensor;
            f.stereo_baseline_m = (e == 0) ? sc.motion.stereo_baseline_m : 0.0;
        }
    }
    out.count = 2 * count;
    return Status::ok();
}

Status validatePanoramaCoverage(const Scenario& sc) noexcept {
    if (sc.kind != ScenarioKind::kPanorama) {
        return Status::ok();
    }
    PanoramaOverlap overlap;
    VTM_RETURN_IF_ERROR(panoramaOverlap(sc, overlap));
    for (std::int32_t t = 0; t < sc.motion.tiers.count; ++t) {  // bound: <= kMaxPanoramaTiers
        if (!(overlap.horizontal_deg[t] > 0.0)) {
            return Status(StatusCode::kInvalidConfig,
                          "scenario: motion.columns too few for the camera's field of view (no overlap in pan)", t);
        }
        if (t + 1 < sc.motion.tiers.count && !(overlap.vertical_deg[t] > 0.0)) {
            return Status(StatusCode::kInvalidConfig,
                          "scenario: motion.tier_tilts_deg farther apart than the camera's vertical field of view", t);
        }
    }
    return Status::ok();
}

}  // namespace detail
}  // namespace vtm::sim
