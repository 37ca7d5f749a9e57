// The frames of a scenario (sim/scenario.hpp buildScenarioFrames): vehicle paths of the
// moving kinds, camera poses from the mount, per-frame sensor settings and the odometry
// (the panorama's stations: scenario_panorama.cpp).
#include <cmath>
#include <cstring>

#include "rotation.hpp"
#include "scenario_geometry.hpp"
#include "scenario_panorama.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {
namespace {

using detail::kRadPerDeg;

using detail::mountRotation;
using detail::streamSeed;
using detail::toNanoseconds;

// Projection centre and optical axis of the model in its reference frame.
Vec3 modelCentre(const CameraModel& m) noexcept {
    return (m.kind == CameraModelKind::kPinholeBrown) ? Vec3::Zero() : Vec3(m.c[0], m.c[1], m.c[2]);
}
Vec3 modelAxis(const CameraModel& m) noexcept {
    return (m.kind == CameraModelKind::kPinholeBrown) ? Vec3::UnitZ() : Vec3(m.a[0], m.a[1], m.a[2]);
}

// A vehicle pose: where it stands, how it is turned, when.
struct Station {
    Vec3 position_site_m = Vec3::Zero();
    Mat3 R_site_from_vehicle = Mat3::Identity();
    double time_s = 0.0;
};

VehiclePose truePose(const Station& s) noexcept {
    return detail::vehiclePose(s.position_site_m, s.R_site_from_vehicle, s.time_s);
}

RigidPose mountedCamera(const Scenario& sc, const Station& s) noexcept {
    RigidPose site_from_cam;
    site_from_cam.R = s.R_site_from_vehicle * mountRotation(sc.mount);
    site_from_cam.t_m = s.position_site_m + s.R_site_from_vehicle * sc.mount.position_vehicle_m;
    return site_from_cam;
}

// Frame k of camera `role` seen from station s (odometry filled in later).
void setFrame(const Scenario& sc, const Station& s, FrameRole role, std::int32_t k, ScenarioFrame& f) noexcept {
    f.index = static_cast<std::uint32_t>(k);
    f.role = role;
    f.timestamp_ns = toNanoseconds(s.time_s);
    f.true_pose = truePose(s);
    f.model = sc.camera;
    f.camera_pose = mountedCamera(sc, s);
    f.sensor = sc.sensor;
    f.camera_id = kMainCameraId;
    f.sequence = (role == FrameRole::kMain) ? static_cast<std::uint32_t>(k) : 0U;
    f.stereo_baseline_m = 0.0;
}

// ---- rover pair -------------------------------------------------------------------------

struct PairGeometry {
    double yaw_a_rad = 0.0;
    double yaw_b_rad = 0.0;
    Vec3 centre_vehicle_m = Vec3::Zero();  // projection centre in the vehicle frame
};

// Yaws that give the requested angle between the two optical axes. With the axis at
// elevation t in the vehicle frame and a yaw difference dpsi between the two rovers:
// cos(convergence) = cos^2 t cos(dpsi) + sin^2 t.
Status pairGeometry(const Scenario& sc, PairGeometry& g) noexcept {
    const Mat3 R_vehicle_from_ref = mountRotation(sc.mount);
    const Vec3 axis = (R_vehicle_from_ref * modelAxis(sc.camera)).normalized();
    g.centre_vehicle_m = sc.mount.position_vehicle_m + R_vehicle_from_ref * modelCentre(sc.camera);
    const double sin2 = axis.z() * axis.z();
    const double cos2 = 1.0 - sin2;
    const double c = (math::cos(sc.motion.convergence_deg * kRadPerDeg) - sin2) / cos2;
    if (cos2 < 0.05 || c < -1.0) {
        return Status(StatusCode::kInvalidConfig,
                      "scenario: camera.mount_tilt_deg too steep for motion.convergence_deg (rover_pair)");
    }
    const double cc = (c > 1.0) ? 1.0 : c;
    const double dpsi = math::atan2(math::sqrt(1.0 - cc * cc), cc);
    const double view_yaw = sc.motion.heading_deg * kRadPerDeg - math::atan2(axis.y(), axis.x());
    g.yaw_a_rad = view_yaw + 0.5 * dpsi;  // the left rover turns right, towards the common point
    g.yaw_b_rad = view_yaw - 0.5 * dpsi;
    return Status::ok();
}

// Horizontal vehicle position whose camera centre lies at `centre_h` (north, east).
Vec2 vehicleAt(const Vec2& centre_h, const Mat3& R, const Vec3& centre_vehicle_m) noexcept {
    const Vec3 offset = R * centre_vehicle_m;
    return Vec2(centre_h.x() - offset.x(), centre_h.y() - offset.y());
}

// The two rover stations. The camera centres lie on the line through start_m
// perpendicular to the view heading, the 3-D distance between them is baseline_m: the
// rovers stand on the terrain at the positions of a horizontal baseline, then the
// horizontal separation is shortened so that the height step keeps the 3-D baseline.
Status roverPairStations(const Scenario& sc, const Terrain& terrain, const PairGeometry& g, Station& a,
                         Station& b) noexcept {
    const double h = sc.motion.heading_deg * kRadPerDeg;
    const Vec2 right(-math::sin(h), math::cos(h));
    const Vec2 mid = sc.motion.start_site_m;
    a.R_site_from_vehicle = detail::rotationZ(g.yaw_a_rad);
    b.R_site_from_vehicle = detail::rotationZ(g.yaw_b_rad);
    const double half = 0.5 * sc.motion.baseline_m;
    const Vec2 pa = vehicleAt(mid - half * right, a.R_site_from_vehicle, g.centre_vehicle_m);
    const Vec2 pb = vehicleAt(mid + half * right, b.R_site_from_vehicle, g.centre_vehicle_m);
    const double za = -terrain.elevationAt(pa.x(), pa.y());
    const double zb = -terrain.elevationAt(pb.x(), pb.y());
    const double dz = zb - za;  // the camera height offsets are equal (level rovers)
    if (!(math::sqrt(dz * dz) < 0.9 * sc.motion.baseline_m)) {
        return Status(StatusCode::kInvalidConfig,
                      "scenario: motion.baseline_m shorter than the terrain height step between the rovers");
    }
    const double half_h = 0.5 * math::sqrt(sc.motion.baseline_m * sc.motion.baseline_m - dz * dz);
    const Vec2 qa = vehicleAt(mid - half_h * right, a.R_site_from_vehicle, g.centre_vehicle_m);
    const Vec2 qb = vehicleAt(mid + half_h * right, b.R_site_from_vehicle, g.centre_vehicle_m);
    a.position_site_m = Vec3(qa.x(), qa.y(), za);
    b.position_site_m = Vec3(qb.x(), qb.y(), zb);
    a.time_s = sc.motion.start_time_s;
    const Vec3 drive = b.position_site_m - a.position_site_m;
    b.time_s = a.time_s + math::sqrt(drive.squaredNorm()) / sc.motion.speed_m_per_s;
    return Status::ok();
}

Status roverPairFrames(const Scenario& sc, const Terrain& terrain, ScenarioFrames& out) noexcept {
    PairGeometry g;
    VTM_RETURN_IF_ERROR(pairGeometry(sc, g));
    Station a;
    Station b;
    VTM_RETURN_IF_ERROR(roverPairStations(sc, terrain, g, a, b));
    setFrame(sc, a, FrameRole::kMain, 0, out.frames[0]);
    setFrame(sc, b, FrameRole::kMain, 1, out.frames[1]);
    // The fixed stereo pair: identical undistorted pinholes centred on the mast camera's
    // projection centre at the first position, parallel to its reference frame.
    const CameraModel stereo = makePinhole(sc.camera.width_px, sc.camera.height_px, sc.motion.stereo_hfov_deg);
    const RigidPose site_from_mast = mountedCamera(sc, a);
    RigidPose site_from_left;
    site_from_left.R = site_from_mast.R;
    const Vec3 centre = site_from_mast.t_m + site_from_mast.R * modelCentre(sc.camera);
    site_from_left.t_m = centre - site_from_mast.R * Vec3(0.5 * sc.motion.stereo_baseline_m, 0.0, 0.0);
    const FrameRole roles[2] = {FrameRole::kStereoLeft, FrameRole::kStereoRight};
    for (std::int32_t i = 0; i < 2; ++i) {  // bound: 2 cameras
        ScenarioFrame& f = out.frames[2 + i];
        setFrame(sc, a, roles[i], 2 + i, f);
        f.model = stereo;
        f.camera_id = (i == 0) ? kStereoLeftCameraId : kStereoRightCameraId;
        f.camera_pose =
            (i == 0) ? site_from_left : rightPoseOfRectifiedPair(site_from_left, sc.motion.stereo_baseline_m);
        f.stereo_baseline_m = sc.motion.stereo_baseline_m;
    }
    out.count = 4;
    return Status::ok();
}

// ---- descent ----------------------------------------------------------------------------

Status descentFrames(const Scenario& sc, const Terrain& terrain, ScenarioFrames& out) noexcept {
    const MotionParams& m = sc.motion;
    const Vec3 centre_vehicle_m = sc.mount.position_vehicle_m + mountRotation(sc.mount) * modelCentre(sc.camera);
    const double log_ratio = math::log(m.end_altitude_m / m.start_altitude_m);
    Random rng(streamSeed(sc.seed, detail::kAttitudeStream));
    const double sigma_rad = m.attitude_noise_deg * kRadPerDeg;
    for (std::int32_t k = 0; k < m.frames; ++k) {  // bound: frames <= kMaxDescentFrames
        const double fraction = static_cast<double>(k) / static_cast<double>(m.frames - 1);
        const double altitude_m =
            (k == m.frames - 1) ? m.end_altitude_m : m.start_altitude_m * math::exp(fraction * log_ratio);
        const double drift = (m.start_altitude_m - altitude_m) / (m.start_altitude_m - m.end_altitude_m);
        const Vec2 centre_h = m.start_site_m + drift * m.drift_site_m;
        const double noise_x = rng.normal(0.0, sigma_rad);
        const double noise_y = rng.normal(0.0, sigma_rad);
        const double noise_z = rng.normal(0.0, sigma_rad);
        Station s;
        s.R_site_from_vehicle = detail::rotationZ(m.heading_deg * kRadPerDeg) *
                                detail::rotationFromVector(Vec3(noise_x, noise_y, noise_z));
        const Vec3 centre(centre_h.x(), centre_h.y(), -(terrain.elevationAt(centre_h.x(), centre_h.y()) + altitude_m));
        s.position_site_m = centre - s.R_site_from_vehicle * centre_vehicle_m;
        s.time_s = m.start_time_s + (m.start_altitude_m - altitude_m) / m.speed_m_per_s;
        setFrame(sc, s, FrameRole::kMain, k, out.frames[k]);
    }
    out.count = m.frames;
    return Status::ok();
}

// ---- traverse ---------------------------------------------------------------------------

Status traverseFrames(const Scenario& sc, const Terrain& terrain, ScenarioFrames& out) noexcept {
    const MotionParams& m = sc.motion;
    Vec2 position = m.start_site_m;
    double yaw = m.heading_deg * kRadPerDeg;
    const double turn = m.turn_deg_per_stop * kRadPerDeg;
    for (std::int32_t k = 0; k < m.stops; ++k) {  // bound: stops <= kMaxTraverseStops
        if (k > 0) {
            // A constant-curvature drive: chord direction = mean of the two headings.
            const double chord = yaw + 0.5 * turn;
            position += m.step_m * Vec2(math::cos(chord), math::sin(chord));
            yaw += turn;
        }
        Station s;
        s.R_site_from_vehicle = detail::rotationZ(yaw);
        s.position_site_m = Vec3(position.x(), position.y(), -terrain.elevationAt(position.x(), position.y()));
        s.time_s = m.start_time_s + static_cast<double>(k) * m.step_m / m.speed_m_per_s;
        setFrame(sc, s, FrameRole::kMain, k, out.frames[k]);
    }
    out.count = m.stops;
    return Status::ok();
}

// ---- per-frame sensor and odometry ------------------------------------------------------

void varySensors(const Scenario& sc, ScenarioFrames& out) noexcept {
    Random rng(streamSeed(sc.seed, detail::kSensorStream));
    for (std::int32_t k = 1; k < out.count; ++k) {  // bound: count <= kMaxScenarioFrames
        const double u_exposure = 2.0 * rng.uniform01() - 1.0;
        const double u_gain = 2.0 * rng.uniform01() - 1.0;
        SensorParams& s = out.frames[k].sensor;
        s.exposure_s *= 1.0 + u_exposure * sc.variation.exposure_variation_percent / 100.0;
        s.gain_dn_per_e *= 1.0 + u_gain * sc.variation.gain_variation_percent / 100.0;
    }
}

// The odometry along the vehicle's path: one pose per distinct station, in time order
// (frames that share a station share its pose).
void addOdometry(const Scenario& sc, ScenarioFrames& out) noexcept {
    VehiclePose truth[kMaxScenarioFrames];
    VehiclePose odometry[kMaxScenarioFrames];
    std::int32_t station_of[kMaxScenarioFrames] = {};
    std::int32_t stations = 0;
    for (std::int32_t k = 0; k < out.count; ++k) {  // bound: count <= kMaxScenarioFrames
        std::int32_t s = 0;
        while (s < stations && truth[s].timestamp_ns != out.frames[k].timestamp_ns) {  // bound: stations <= count
            ++s;
        }
        if (s == stations) {
            truth[s] = out.frames[k].true_pose;
            ++stations;
        }
        station_of[k] = s;
    }
    applyOdometryErrors(sc.odometry, streamSeed(sc.seed, detail::kOdometryStream), truth, odometry, stations);
    for (std::int32_t k = 0; k < out.count; ++k) {  // bound: count
        out.frames[k].odometry_pose = odometry[station_of[k]];
    }
}

}  // namespace

namespace detail {

std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream) noexcept {
    std::uint64_t state = seed ^ stream;
    return splitMix64(state);
}

Mat3 mountRotation(const CameraMount& mount) noexcept {
    Mat3 base;  // reference +z = vehicle +x, +x = vehicle +y, +y = vehicle +z
    base << 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;
    return rotationZ(mount.pan_deg * kRadPerDeg) * rotationY(mount.tilt_deg * kRadPerDeg) * base *
           rotationZ(mount.roll_deg * kRadPerDeg);
}

std::uint64_t toNanoseconds(double t_s) noexcept { return static_cast<std::uint64_t>(std::floor(t_s * 1e9 + 0.5)); }

VehiclePose vehiclePose(const Vec3& position_site_m, const Mat3& R_site_from_vehicle, double time_s) noexcept {
    VehiclePose p;
    const Quat q = quaternionOf(R_site_from_vehicle);
    p.timestamp_ns = toNanoseconds(time_s);
    for (int i = 0; i < 3; ++i) {  // bound: 3 axes
        p.position_m[i] = position_site_m[i];
    }
    p.attitude_wxyz[0] = q.w();
    p.attitude_wxyz[1] = q.x();
    p.attitude_wxyz[2] = q.y();
    p.attitude_wxyz[3] = q.z();
    return p;
}

}  // namespace detail

RigidPose vehicleFromCamera(const ScenarioFrame& f) noexcept {
    const VehiclePose& v = f.true_pose;
    const Mat3 R_site_from_vehicle =
        Quat(v.attitude_wxyz[0], v.attitude_wxyz[1], v.attitude_wxyz[2], v.attitude_wxyz[3]).normalized().toRotationMatrix();
    const Vec3 vehicle(v.position_m[0], v.position_m[1], v.position_m[2]);
    RigidPose vehicle_from_camera;
    vehicle_from_camera.R = R_site_from_vehicle.transpose() * f.camera_pose.R;
    vehicle_from_camera.t_m = R_site_from_vehicle.transpose() * (f.camera_pose.t_m - vehicle);
    return vehicle_from_camera;
}

std::int32_t scenarioFrameCount(const Scenario& scenario) noexcept {
    switch (scenario.kind) {
        case ScenarioKind::kRoverPair: return 4;
        case ScenarioKind::kDescent: return scenario.motion.frames;
        case ScenarioKind::kPanorama: return 2 * scenario.motion.tiers.count * scenario.motion.columns;
        default: return scenario.motion.stops;
    }
}

Status buildScenarioFrames(const Scenario& scenario, const Terrain& terrain, ScenarioFrames& out) noexcept {
    VTM_RETURN_IF_ERROR(validateScenario(scenario));
    if (!terrain.built()) {
        return Status(StatusCode::kInvalidArgument, "buildScenarioFrames: terrain not built");
    }
    out.count = 0;
    Status status;
    switch (scenario.kind) {
        case ScenarioKind::kRoverPair: status = roverPairFrames(scenario, terrain, out); break;
        case ScenarioKind::kDescent: status = descentFrames(scenario, terrain, out); break;
        case ScenarioKind::kPanorama: status = detail::panoramaFrames(scenario, terrain, out); break;
        default: status = traverseFrames(scenario, terrain, out); break;
    }
    VTM_RETURN_IF_ERROR(status);
    varySensors(scenario, out);
    if (scenario.kind != ScenarioKind::kPanorama) {  // the panorama's rover stands still: its telemetry is set
        addOdometry(scenario, out);
    }
    return Status::ok();
}

std::size_t scenarioTerrainBytes(const Scenario& scenario) noexcept {
    return Terrain::storageBytes(scenario.terrain);
}

Status buildScenarioTerrain(const Scenario& scenario, Arena& arena, Terrain& terrain) noexcept {
    return terrain.build(scenario.terrain, arena);
}

FrameRequest scenarioFrameRequest(const Scenario& scenario, const Terrain& terrain,
                                  const ScenarioFrame& frame) noexcept {
    FrameRequest request;
    request.terrain = &terrain;
    request.model = frame.model;
    request.pose = frame.camera_pose;
    request.lighting = scenario.lighting;
    request.sensor = frame.sensor;
    request.frame_index = frame.index;
    return request;
}

}  // namespace vtm::sim
