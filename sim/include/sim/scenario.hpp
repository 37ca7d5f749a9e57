// Scenarios of the simulated world (docs/sim-scenarios.md): a text file names the terrain,
// the camera and its mount on the vehicle, the sensor, the sun, the vehicle's motion and
// the odometry error model. This header parses that text into a fixed-size Scenario (no
// heap) and turns a Scenario into the frames to render: for frame k its time, the true
// vehicle pose, the odometry's pose (true pose plus the seeded error model), the camera
// model, the camera's pose in the site frame and the sensor settings of that frame.
//
// Frames (hal/odometry.hpp, sim/render.hpp):
//  - site: x north, y east, z DOWN (metres); elevation = -z.
//  - vehicle: x forward, y right, z down; the vehicle's origin is its ground contact point
//    (rover) or its reference point (lander). Attitude: T_site_from_vehicle.
//  - camera reference frame: the CameraModel's frame (the optical frame of a pinhole:
//    +z forward, +x image right, +y image down; the frame C/A/H/V are given in for
//    CAHV(OR)). Mounted with pan/tilt/roll: at pan = tilt = roll = 0 its +z is the
//    vehicle's +x, its +x the vehicle's +y and its +y the vehicle's +z.
//
// Determinism: vtm::math only, one random draw per statement, one generator per purpose
// seeded from the scenario seed, so the same text gives the same frames on every target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sim/orbital.hpp"
#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/status.hpp"

namespace vtm::sim {

enum class ScenarioKind : std::uint8_t {
    kRoverPair = 1,  // mast camera at two rover positions + a fixed-baseline stereo pair
    kDescent = 2,    // nadir camera of a descending lander
    kTraverse = 3,   // a short rover drive, one frame per stop
    kPanorama = 4,   // a mast stereo pair turned through 360 deg in tiers (sim/panorama.hpp)
};

// Capacities of a Scenario.
constexpr std::size_t kMaxScenarioNameChars = 63U;  // name: [A-Za-z0-9_-], 1..63 characters
constexpr std::int32_t kMaxScenarioFrames = 64;     // frames of one scenario (all cameras)
constexpr std::int32_t kMaxTraverseStops = 60;
constexpr std::int32_t kMinDescentFrames = 2;
constexpr std::int32_t kMaxDescentFrames = 32;
constexpr std::int32_t kMinPanoramaTiers = 2;
constexpr std::int32_t kMaxPanoramaTiers = 3;
constexpr std::int32_t kMaxPanoramaStations = kMaxScenarioFrames / 2;  // two frames (eyes) per station
constexpr std::size_t kMaxScenarioTextBytes = 65536U;

// Where the camera's reference frame sits on the vehicle.
struct CameraMount {
    Vec3 position_vehicle_m = Vec3(0.0, 0.0, -1.9);  // vehicle frame (z down: -1.9 = 1.9 m up)
    double pan_deg = 0.0;    // about the vehicle's z axis, positive towards the vehicle's right
    double tilt_deg = -25.0; // elevation of the view direction, negative = looking down
    double roll_deg = 0.0;   // about the view direction (reference +z), turning its +x towards its +y
};

// The seeded odometry (navigation) error model. Per run (per seed) the scale error, the
// heading drift rate and the pitch and roll drift rates are drawn once from
// N(mean, sigma); along the path, with d the distance travelled (metres):
//   measured displacement = (1 + scale error) * true displacement, rotated by the
//   attitude error accumulated so far (heading = rate * d, pitch/roll = their rate * d),
//   plus a position random walk N(0, random_walk^2 * step length) per axis;
//   odometry attitude = attitude error (applied on the left, site frame) * true attitude.
// The reported covariance is diagonal: the model's second moments at distance d
// (docs/sim-scenarios.md "Odometry").
struct OdometryErrorModel {
    double scale_error_percent = 0.0;           // mean distance scale error
    double scale_error_sigma_percent = 0.0;     // its spread between runs (>= 0)
    double heading_drift_deg_per_m = 0.0;       // mean heading drift rate
    double heading_drift_sigma_deg_per_m = 0.0; // its spread between runs (>= 0)
    double tilt_drift_sigma_deg_per_m = 0.0;    // spread of the pitch and roll drift rates (mean 0)
    double random_walk_m_per_sqrt_m = 0.0;      // position random walk (>= 0)
};

// A panorama's tiers: the elevation of each tier's view direction (negative = down),
// count = kMinPanoramaTiers .. kMaxPanoramaTiers; entries past count are unused.
struct TierTilts {
    std::int32_t count = 2;
    double deg[kMaxPanoramaTiers] = {-10.0, -35.0, -60.0};
};

// [motion]: the fields of the scenario's kind (the others stay at their defaults).
struct MotionParams {
    Vec2 start_site_m = Vec2::Zero();  // north, east: pair midpoint / first stop / first nadir point
    double heading_deg = 0.0;          // view (pair) or drive (traverse, descent) direction, from north towards east
    double start_time_s = 1000.0;      // timestamp of the first frame
    double speed_m_per_s = 0.05;       // rover drive speed (pair, traverse) or descent speed
    // rover_pair
    double baseline_m = 5.0;           // distance between the mast camera's two projection centres
    double convergence_deg = 10.0;     // angle between the two optical axes (toed in)
    double stereo_baseline_m = 0.42;   // fixed stereo pair at the first position
    double stereo_hfov_deg = 45.0;
    // descent
    double start_altitude_m = 2000.0;  // camera height above the terrain below it
    double end_altitude_m = 20.0;
    std::int32_t frames = 8;           // descent frames (geometric altitude spacing)
    Vec2 drift_site_m = Vec2::Zero();  // lateral drift (north, east) from the first to the last frame
    double attitude_noise_deg = 0.0;   // sigma per axis, per frame
    // traverse
    std::int32_t stops = 6;
    double step_m = 2.0;               // drive between consecutive stops
    double turn_deg_per_stop = 0.0;    // heading change per step, positive to the right
    // panorama (also stereo_baseline_m; the eyes are [camera]'s model, the pan/tilt head
    // sits at camera.mount_position_m: its z is minus the mast height)
    std::int32_t columns = 10;         // exposures per tier, evenly spaced through 360 deg of pan
    TierTilts tiers{};                 // the tiers' view elevations, top tier first
    double station_interval_s = 5.0;   // time between consecutive exposures
};

// [pointing] (panorama only): the seeded error model of what the rover's telemetry says
// about each exposure's pose (docs/sim-scenarios.md "Panorama"). Every error is zero-mean
// normal with the given sigma, drawn per exposure (encoders) or once per panorama (mast,
// rover attitude, so shared by all stations).
struct PointingErrorModel {
    double pan_sigma_deg = 0.0;          // pan encoder, per exposure
    double tilt_sigma_deg = 0.0;         // tilt encoder, per exposure
    double mast_tilt_sigma_deg = 0.0;    // mast axis tilt about each horizontal vehicle axis, per panorama
    double head_offset_sigma_m = 0.0;    // head position offset per vehicle axis, per panorama
    double rover_roll_sigma_deg = 0.0;   // rover attitude telemetry, per panorama
    double rover_pitch_sigma_deg = 0.0;
    double rover_heading_sigma_deg = 0.0;
};

// Per-frame differences of the sensor: frame k > 0 gets exposure and gain factors
// 1 + u / 100, u uniform in [-variation, +variation] (seeded); frame 0 is nominal.
struct SensorVariation {
    double exposure_variation_percent = 0.0;
    double gain_variation_percent = 0.0;
};

// [orbital] (descent only): an orbital image of the same world in a second modality
// (sim/orbital.hpp), for descent-to-orbital registration with truth. Its centre is
// motion.start_m + centre_offset_m; the sun and the modality are its own.
struct OrbitalScenario {
    bool enabled = false;                  // an [orbital] section was given
    Vec2 centre_offset_m = Vec2::Zero();   // north, east from motion.start_m
    double cell_m = 1.0;                   // metres per pixel
    std::int32_t width_px = 512;
    std::int32_t height_px = 512;
    std::int32_t subsamples = 2;           // per pixel axis
    double sun_azimuth_deg = 250.0;        // from north towards east
    double sun_elevation_deg = 50.0;
    OrbitalModality modality = OrbitalModality::kThermal;
    std::int32_t bit_depth = 8;            // 8 or 16
    bool shadows = true;
    double noise_fs = 0.004;               // noise sigma, fraction of full scale
    double ambient = 0.125;                // kVisible: sky light / direct sun
    double thermal_floor_k = 180.0;        // kThermal: ThermalParams::floor_k
    double thermal_subsolar_k = 300.0;     // kThermal: ThermalParams::subsolar_k
    std::uint64_t noise_seed = 1U;         // derived from seed if not given
};

struct Scenario {
    char name[kMaxScenarioNameChars + 1U] = {};
    ScenarioKind kind = ScenarioKind::kRoverPair;
    std::uint64_t seed = 0U;
    TerrainParams terrain{};
    CameraModel camera{};        // the main camera (mast / nadir); width/height = frame size
    double camera_hfov_deg = 0.0;  // when given by hfov (else 0)
    CameraMount mount{};
    SensorParams sensor{};       // bit_depth from [camera]; noise_seed derived from seed if not given
    SensorVariation variation{};
    Lighting lighting{};           // to_sun_site from the two angles below (sunDirection)
    double sun_azimuth_deg = 135.0;   // from north towards east
    double sun_elevation_deg = 35.0;  // above the horizon
    MotionParams motion{};
    OdometryErrorModel odometry{};
    OrbitalScenario orbital{};
    PointingErrorModel pointing{};  // panorama only
};

// Parses a scenario text (docs/sim-scenarios.md). Every problem is a Status whose reason
// names the key as section.key (or the section) and whose detail is the 1-based line
// number (0 for a key that is missing altogether):
//   kCorruptData   unknown section or key, key given twice, wrong number of values,
//                  a value that is not a number / not one of the allowed words;
//   kInvalidConfig required key missing, value out of its range, a key that does not
//                  belong to the scenario's kind, fields that contradict each other.
// `out` is fully written on success only.
[[nodiscard]] Status parseScenario(std::string_view text, Scenario& out) noexcept;

// Checks a Scenario built in code the way parseScenario checks a file (detail 0).
[[nodiscard]] Status validateScenario(const Scenario& scenario) noexcept;

// Unit vector towards the sun in the site frame (z down) from azimuth (from north towards
// east) and elevation above the horizon, degrees.
[[nodiscard]] Vec3 sunDirection(double azimuth_deg, double elevation_deg) noexcept;

// ---- Frames -----------------------------------------------------------------------

// hal::PoseEstimate's layout (sim/ does not include hal/): T_site_from_vehicle with a
// 6x6 row-major covariance over (x, y, z [m], rx, ry, rz [rad]), rotation on the left.
struct VehiclePose {
    std::uint64_t timestamp_ns = 0U;
    double position_m[3] = {0.0, 0.0, 0.0};
    double attitude_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
    double covariance[36] = {};
};

enum class FrameRole : std::uint8_t {
    kMain = 0,         // the scenario's camera (mast / nadir)
    kStereoLeft = 1,   // rover_pair: fixed stereo pair at the first position
    kStereoRight = 2,  // (panorama: every frame is one eye of a station, sequence = station)
};

// Camera ids in frames and manifests.
constexpr std::uint8_t kMainCameraId = 0U;
constexpr std::uint8_t kStereoLeftCameraId = 1U;
constexpr std::uint8_t kStereoRightCameraId = 2U;

struct ScenarioFrame {
    std::uint32_t index = 0U;        // 0..count-1, also the renderer's frame_index (noise)
    FrameRole role = FrameRole::kMain;
    std::uint8_t camera_id = kMainCameraId;
    std::uint32_t sequence = 0U;     // per camera, 0, 1, ...
    std::uint64_t timestamp_ns = 0U;
    VehiclePose true_pose;           // covariance zero
    VehiclePose odometry_pose;       // what the vehicle believes, with its covariance
    CameraModel model{};
    RigidPose camera_pose{};         // true site_from_cam of the camera
    SensorParams sensor{};           // this frame's exposure, gain and noise seed
    double stereo_baseline_m = 0.0;  // kStereoLeft: the pair's baseline (right = left + R (b, 0, 0))
};

// All frames of a scenario: about 70 KiB, declare it static or on the heap of a ground tool.
// Rover pair order: 0 mast camera at the first position, 1 mast camera at the second,
// 2 and 3 the fixed stereo pair (left, right) at the first position.
struct ScenarioFrames {
    ScenarioFrame frames[kMaxScenarioFrames];
    std::int32_t count = 0;
};

// Number of frames the scenario produces (rover_pair: 4, descent: frames, traverse: stops,
// panorama: 2 * tiers * columns, left eye of station k at 2k, right eye at 2k + 1).
[[nodiscard]] std::int32_t scenarioFrameCount(const Scenario& scenario) noexcept;

// The frames of a valid scenario over its built terrain (rovers stand on it, the lander's
// altitude is measured from it). kInvalidConfig (naming the field) when the geometry
// cannot be built, e.g. a rover_pair height step between the two positions as large as
// the baseline.
[[nodiscard]] Status buildScenarioFrames(const Scenario& scenario, const Terrain& terrain,
                                         ScenarioFrames& out) noexcept;

// The frame's camera pose in its vehicle's frame at the true pose (vehicle_from_camera:
// X_vehicle = R X_camera + t_m): the mount calibration a mapper is configured with.
[[nodiscard]] RigidPose vehicleFromCamera(const ScenarioFrame& frame) noexcept;

// The odometry error model applied to a sequence of true poses (timestamps copied): the
// maths of buildScenarioFrames, for any path. count >= 1.
void applyOdometryErrors(const OdometryErrorModel& model, std::uint64_t seed, const VehiclePose* truth,
                         VehiclePose* odometry, std::int32_t count) noexcept;

// The render request of one scenario frame (whole frame, default range): what every
// consumer of a scenario (vtm-sim, hal/sim, the HIL receiver, tests) renders, so that they
// all produce the same bits for the same frame.
[[nodiscard]] FrameRequest scenarioFrameRequest(const Scenario& scenario, const Terrain& terrain,
                                                const ScenarioFrame& frame) noexcept;

// The orbital image of a scenario with an [orbital] section (the whole image; the
// thermal scale and the sensor offset at their OrbitalParams defaults).
[[nodiscard]] OrbitalParams scenarioOrbitalParams(const Scenario& scenario) noexcept;

// ---- Terrain ----------------------------------------------------------------------

// Bytes an Arena needs to build the scenario's terrain (alignment included).
[[nodiscard]] std::size_t scenarioTerrainBytes(const Scenario& scenario) noexcept;
// Builds the scenario's terrain into `arena` (Terrain::build with the scenario's params).
[[nodiscard]] Status buildScenarioTerrain(const Scenario& scenario, Arena& arena, Terrain& terrain) noexcept;

}  // namespace vtm::sim
