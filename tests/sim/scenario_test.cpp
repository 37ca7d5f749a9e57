// Scenarios (sim/scenario.hpp): the parser against every documented error class, the
// motion geometry against the requested baseline / convergence / altitudes computed from
// the produced poses, and the odometry error model's statistics over many seeds against
// the model's own parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A small analytic world: a tilted plane (so rovers stand at different heights), cheap to
// build on every target.
TerrainParams planeTerrain() {
    TerrainParams p = defaultMarsTerrainParams();
    p.kind = TerrainKind::kPlane;
    p.finest_cell_m = 1.0;
    p.samples_log2 = 5;
    p.levels = 8;
    p.plane_slope_north = 0.05;
    p.plane_slope_east = -0.03;
    p.base_elevation_m = 10.0;
    return p;
}

class PlaneWorld : public ::testing::Test {
protected:
    void SetUp() override {
        storage_.resize(Terrain::storageBytes(planeTerrain()) + 64U);
        arena_ = std::make_unique<Arena>(storage_.data(), storage_.size());
        ASSERT_TRUE(terrain_.build(planeTerrain(), *arena_).isOk());
    }
    std::vector<std::byte> storage_;
    std::unique_ptr<Arena> arena_;
    Terrain terrain_;
};

const char* kMinimal =
    "name t\nkind rover_pair\nseed 5\n[camera]\nmodel pinhole\nwidth_px 64\nheight_px 48\nhfov_deg 45\n";

Scenario parseOk(const std::string& text) {
    Scenario s;
    const Status st = parseScenario(text, s);
    EXPECT_TRUE(st.isOk()) << st.reason() << " line " << st.detail();
    return s;
}

Vec3 centreOf(const ScenarioFrame& f) { return f.camera_pose.t_m; }
Vec3 axisOf(const ScenarioFrame& f) { return f.camera_pose.R * Vec3::UnitZ(); }
Vec3 positionOf(const VehiclePose& p) { return Vec3(p.position_m[0], p.position_m[1], p.position_m[2]); }
Quat attitudeOf(const VehiclePose& p) {
    return Quat(p.attitude_wxyz[0], p.attitude_wxyz[1], p.attitude_wxyz[2], p.attitude_wxyz[3]);
}

// ---- parser -------------------------------------------------------------------------------

TEST(ScenarioParser, EveryShippedScenarioParses) {
    const char* files[] = {"rover_wide_baseline.scn", "descent.scn", "traverse.scn", "test_rover_small.scn",
                           "descent_orbital.scn"};
    const ScenarioKind kinds[] = {ScenarioKind::kRoverPair, ScenarioKind::kDescent, ScenarioKind::kTraverse,
                                  ScenarioKind::kRoverPair, ScenarioKind::kDescent};
    for (int i = 0; i < 5; ++i) {
        const std::string text = readFile(std::string(VTM_SCENARIO_DIR) + "/" + files[i]);
        ASSERT_FALSE(text.empty()) << files[i];
        Scenario s;
        const Status st = parseScenario(text, s);
        EXPECT_TRUE(st.isOk()) << files[i] << ": " << st.reason() << " line " << st.detail();
        EXPECT_EQ(s.kind, kinds[i]) << files[i];
    }
}

TEST(ScenarioParser, MinimalFileGetsTheDocumentedDefaultsAndDerivedSeeds) {
    const Scenario s = parseOk(kMinimal);
    EXPECT_STREQ(s.name, "t");
    EXPECT_EQ(s.seed, 5U);
    EXPECT_EQ(s.camera.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(s.camera.width_px, 64U);
    // 45 deg horizontal field of view: fx = (w / 2) / tan(22.5 deg).
    EXPECT_NEAR(s.camera.fx_px, 32.0 / std::tan(22.5 * kDeg), 1e-9);
    EXPECT_EQ(s.sensor.bit_depth, 8);
    EXPECT_DOUBLE_EQ(s.motion.baseline_m, 5.0);
    EXPECT_DOUBLE_EQ(s.motion.stereo_baseline_m, 0.42);
    // Seeds not given are derived from the scenario seed, differently per purpose.
    const Scenario other = parseOk(std::string(kMinimal).replace(std::string(kMinimal).find("seed 5"), 6, "seed 6"));
    EXPECT_NE(s.terrain.seed, other.terrain.seed);
    EXPECT_NE(s.sensor.noise_seed, other.sensor.noise_seed);
    EXPECT_NE(s.terrain.seed, s.sensor.noise_seed);
    // Sun: azimuth 135 deg (south-east), elevation 35 deg: z up is negative.
    EXPECT_NEAR(s.lighting.to_sun_site.z(), -std::sin(35.0 * kDeg), 1e-12);
    EXPECT_NEAR(s.lighting.to_sun_site.x(), std::cos(35.0 * kDeg) * std::cos(135.0 * kDeg), 1e-12);
}

TEST(ScenarioParser, EveryFieldIsSetFromTheFile) {
    const Scenario s = parseOk(std::string(kMinimal) +
                               "[terrain]\nrock_k 0.2\nseed 77\nkind dome\n"
                               "[camera]\nbit_depth 12\nmount_tilt_deg -30\nmount_position_m 0.1 0.2 -1.5\n"
                               "[sensor]\nexposure_s 0.02\nshot_noise false\nnoise_seed 9\n"
                               "[lighting]\nsun_azimuth_deg 90\nshadows false\n"
                               "[motion]\nstart_m 3 -4\nconvergence_deg 20\n"
                               "[odometry]\nrandom_walk_m_per_sqrt_m 0.5\n");
    EXPECT_DOUBLE_EQ(s.terrain.rock_k, 0.2);
    EXPECT_EQ(s.terrain.seed, 77U);
    EXPECT_EQ(s.terrain.kind, TerrainKind::kDome);
    EXPECT_EQ(s.sensor.bit_depth, 12);
    EXPECT_DOUBLE_EQ(s.mount.tilt_deg, -30.0);
    EXPECT_EQ(s.mount.position_vehicle_m, Vec3(0.1, 0.2, -1.5));
    EXPECT_DOUBLE_EQ(s.sensor.exposure_s, 0.02);
    EXPECT_FALSE(s.sensor.shot_noise);
    EXPECT_EQ(s.sensor.noise_seed, 9U);
    EXPECT_FALSE(s.lighting.shadows);
    EXPECT_NEAR(s.lighting.to_sun_site.y(), std::cos(35.0 * kDeg), 1e-12);  // east
    EXPECT_EQ(s.motion.start_site_m, Vec2(3.0, -4.0));
    EXPECT_DOUBLE_EQ(s.motion.convergence_deg, 20.0);
    EXPECT_DOUBLE_EQ(s.odometry.random_walk_m_per_sqrt_m, 0.5);
}

TEST(ScenarioParser, CahvorVectorsAndExplicitPinholeAreTakenAsGiven) {
    const Scenario s = parseOk(
        "name c\nkind traverse\nseed 1\n[camera]\nmodel cahvor\nwidth_px 100\nheight_px 80\n"
        "c 0 0 0\na 0 0 1\nh 400 0 50\nv 0 400 40\no 0 0 1\nr 0 -0.1 0.01\n");
    EXPECT_EQ(s.camera.kind, CameraModelKind::kCahvor);
    EXPECT_DOUBLE_EQ(s.camera.h[0], 400.0);
    EXPECT_DOUBLE_EQ(s.camera.r[1], -0.1);
    const Scenario p = parseOk(
        "name p\nkind traverse\nseed 1\n[camera]\nmodel pinhole\nwidth_px 100\nheight_px 80\n"
        "fx_px 90\nfy_px 91\ncx_px 49.5\ncy_px 39.5\nk1 -0.1\n");
    EXPECT_DOUBLE_EQ(p.camera.fy_px, 91.0);
    EXPECT_DOUBLE_EQ(p.camera.k1, -0.1);
}

struct BadCase {
    const char* appended;   // text appended to kMinimal
    StatusCode code;
    const char* reason_part;
    std::int64_t line;      // detail
};

TEST(ScenarioParser, EachErrorClassNamesTheKeyAndTheLine) {
    // kMinimal has 8 lines; an appended line is line 9, the next 10.
    const BadCase cases[] = {
        {"[terrain]\nrock_kk 0.1\n", StatusCode::kCorruptData, "unknown key in [terrain]", 10},
        {"colour red\n", StatusCode::kCorruptData, "unknown key in [camera]", 9},
        {"[weather]\n", StatusCode::kCorruptData, "unknown [section]", 9},
        {"width_px 64\n", StatusCode::kCorruptData, "camera.width_px given twice", 9},
        {"[terrain]\nrock_k abc\n", StatusCode::kCorruptData, "terrain.rock_k has a bad value", 10},
        {"[terrain]\nrock_k 0.1 0.2\n", StatusCode::kCorruptData, "terrain.rock_k has a bad value", 10},
        {"[terrain]\nrock_k nan\n", StatusCode::kCorruptData, "terrain.rock_k has a bad value", 10},
        {"[terrain]\nrock_k 0.9\n", StatusCode::kInvalidConfig, "terrain.rock_k is out of range 0 .. 0.5", 10},
        {"[motion]\nbaseline_m 500\n", StatusCode::kInvalidConfig, "motion.baseline_m is out of range", 10},
        {"[motion]\nframes 6\n", StatusCode::kInvalidConfig, "motion.frames does not belong", 10},
        {"k1 0.1\nmodel cahv\n", StatusCode::kCorruptData, "camera.model given twice", 10},
        {"fx_px 100\n", StatusCode::kInvalidConfig, "camera.hfov_deg and camera.fx_px", 8},
        {"bit_depth 10\n", StatusCode::kInvalidConfig, "camera.bit_depth must be 8 or 12", 10},
        {"[sensor]\nshot_noise maybe\n", StatusCode::kCorruptData, "sensor.shot_noise has a bad value", 10},
        {"[terrain]\nkind moon\n", StatusCode::kCorruptData, "terrain.kind has a bad value", 10},
        {"[terrain]\nseed -1\n", StatusCode::kCorruptData, "terrain.seed has a bad value", 10},
        {"[camera extra]\n", StatusCode::kCorruptData, "a section line must be [name] alone", 9},
    };
    for (const BadCase& c : cases) {
        Scenario s;
        const Status st = parseScenario(std::string(kMinimal) + c.appended, s);
        EXPECT_EQ(st.code(), c.code) << c.appended << " -> " << st.reason();
        EXPECT_NE(std::string(st.reason()).find(c.reason_part), std::string::npos)
            << c.appended << " -> " << st.reason();
        if (c.code != StatusCode::kInvalidConfig || std::string(c.reason_part) != "camera.bit_depth must be 8 or 12") {
            EXPECT_EQ(st.detail(), c.line) << c.appended;
        }
    }
}

TEST(ScenarioParser, MissingRequiredKeysAreNamed) {
    const struct {
        const char* text;
        const char* reason_part;
    } cases[] = {
        {"kind descent\nseed 1\n[camera]\nmodel pinhole\nwidth_px 8\nheight_px 8\nhfov_deg 40\n", "name missing"},
        {"name a\nkind descent\n[camera]\nmodel pinhole\nwidth_px 8\nheight_px 8\nhfov_deg 40\n", "seed missing"},
        {"name a\nkind descent\nseed 1\n[camera]\nmodel pinhole\nheight_px 8\nhfov_deg 40\n", "camera.width_px missing"},
        {"name a\nkind descent\nseed 1\n[camera]\nmodel pinhole\nwidth_px 8\nheight_px 8\n", "camera.fx_px missing"},
        {"name a\nkind descent\nseed 1\n[camera]\nmodel cahv\nwidth_px 8\nheight_px 8\nc 0 0 0\n", "camera.a missing"},
    };
    for (const auto& c : cases) {
        Scenario s;
        const Status st = parseScenario(c.text, s);
        EXPECT_EQ(st.code(), StatusCode::kInvalidConfig) << c.text;
        EXPECT_NE(std::string(st.reason()).find(c.reason_part), std::string::npos) << st.reason();
        EXPECT_EQ(st.detail(), 0);
    }
}

TEST(ScenarioParser, CommentsBlankLinesAndCrlfAreAccepted) {
    const Scenario s = parseOk("# header\r\n\r\nname  x   # trailing\r\nkind\ttraverse\nseed 1\n[camera]  # c\n"
                               "model pinhole\nwidth_px 8\nheight_px 8\nhfov_deg 40\n");
    EXPECT_STREQ(s.name, "x");
}

TEST(ScenarioParser, ParsingTouchesNoHeap) {
    const std::string text = std::string(kMinimal) + "[terrain]\nrock_k 0.1\n";
    static Scenario s;
    vtm::test::NoHeapScope scope;
    const Status st = parseScenario(text, s);
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_TRUE(st.isOk());
}

// ---- motion -------------------------------------------------------------------------------

TEST_F(PlaneWorld, RoverPairBaselineAndConvergenceAreTheRequestedOnes) {
    static ScenarioFrames frames;
    const double baselines[] = {1.0, 5.0, 20.0};
    const double convergences[] = {0.0, 10.0, 20.0};
    for (const double b : baselines) {
        for (const double c : convergences) {
            Scenario s = parseOk(kMinimal);
            s.terrain = planeTerrain();
            s.motion.baseline_m = b;
            s.motion.convergence_deg = c;
            s.motion.heading_deg = 30.0;
            s.mount.tilt_deg = -25.0;
            ASSERT_TRUE(buildScenarioFrames(s, terrain_, frames).isOk());
            ASSERT_EQ(frames.count, 4);
            const double baseline = (centreOf(frames.frames[1]) - centreOf(frames.frames[0])).norm();
            const double cos_angle = axisOf(frames.frames[0]).dot(axisOf(frames.frames[1]));
            const double angle_deg = std::atan2(axisOf(frames.frames[0]).cross(axisOf(frames.frames[1])).norm(),
                                                cos_angle) / kDeg;
            EXPECT_NEAR(baseline, b, 1e-9) << b << " " << c;
            EXPECT_NEAR(angle_deg, c, 1e-9) << b << " " << c;
            // Toed in: the axes converge in front of the cameras (their closest points
            // lie ahead of both), and the camera stands 1.9 m above its rover's ground.
            for (int k = 0; k < 2; ++k) {
                const ScenarioFrame& f = frames.frames[k];
                const double ground_z = -terrain_.elevationAt(f.true_pose.position_m[0], f.true_pose.position_m[1]);
                EXPECT_NEAR(f.true_pose.position_m[2], ground_z, 0.02 * b);
                EXPECT_NEAR(centreOf(f).z() - f.true_pose.position_m[2], -1.9, 1e-12);
            }
        }
    }
}

TEST_F(PlaneWorld, StereoPairIsParallelIdenticalAndHasTheRequestedBaseline) {
    static ScenarioFrames frames;
    Scenario s = parseOk(kMinimal);
    s.terrain = planeTerrain();
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, frames).isOk());
    const ScenarioFrame& l = frames.frames[2];
    const ScenarioFrame& r = frames.frames[3];
    EXPECT_EQ(l.role, FrameRole::kStereoLeft);
    EXPECT_EQ(r.role, FrameRole::kStereoRight);
    EXPECT_EQ(l.camera_pose.R, r.camera_pose.R);
    const Vec3 in_left = l.camera_pose.R.transpose() * (centreOf(r) - centreOf(l));
    EXPECT_NEAR(in_left.x(), 0.42, 1e-12);
    EXPECT_NEAR(in_left.tail<2>().norm(), 0.0, 1e-12);
    EXPECT_EQ(std::memcmp(&l.model, &r.model, sizeof(CameraModel)), 0);
    EXPECT_EQ(l.model.k1, 0.0);
    // Centred on the mast camera at the first position, taken at its time.
    EXPECT_NEAR((0.5 * (centreOf(l) + centreOf(r)) - centreOf(frames.frames[0])).norm(), 0.0, 1e-12);
    EXPECT_EQ(l.timestamp_ns, frames.frames[0].timestamp_ns);
}

TEST_F(PlaneWorld, DescentAltitudesSpanTheRequestedRangeGeometrically) {
    static ScenarioFrames frames;
    Scenario s = parseOk(std::string(kMinimal).replace(std::string(kMinimal).find("rover_pair"), 10, "descent") +
                         "mount_tilt_deg -90\nmount_position_m 0 0 0\n[motion]\nframes 7\nattitude_noise_deg 1\n"
                         "drift_m 30 -40\nstart_altitude_m 2000\nend_altitude_m 20\n");
    s.terrain = planeTerrain();
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, frames).isOk());
    ASSERT_EQ(frames.count, 7);
    double previous = 0.0;
    for (int k = 0; k < 7; ++k) {
        const Vec3 c = centreOf(frames.frames[k]);
        const double altitude = -c.z() - terrain_.elevationAt(c.x(), c.y());
        const double expected = 2000.0 * std::pow(20.0 / 2000.0, k / 6.0);
        EXPECT_NEAR(altitude, expected, 1e-9 * expected) << k;
        if (k > 0) {
            EXPECT_GT(frames.frames[k].timestamp_ns, frames.frames[k - 1].timestamp_ns);
            EXPECT_NEAR(previous / altitude, std::pow(100.0, 1.0 / 6.0), 1e-9);
        }
        previous = altitude;
        // Looking down within a few sigma of the attitude noise.
        EXPECT_GT(axisOf(frames.frames[k]).z(), std::cos(5.0 * kDeg));
    }
    const Vec3 drift = centreOf(frames.frames[6]) - centreOf(frames.frames[0]);
    EXPECT_NEAR(drift.x(), 30.0, 1e-9);
    EXPECT_NEAR(drift.y(), -40.0, 1e-9);
}

TEST_F(PlaneWorld, TraverseStopsAreAStepApartOnTheGround) {
    static ScenarioFrames frames;
    Scenario s = parseOk(std::string(kMinimal).replace(std::string(kMinimal).find("rover_pair"), 10, "traverse") +
                         "[motion]\nstops 5\nstep_m 1.5\nturn_deg_per_stop 10\nspeed_m_per_s 0.05\n");
    s.terrain = planeTerrain();
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, frames).isOk());
    ASSERT_EQ(frames.count, 5);
    for (int k = 1; k < 5; ++k) {
        const Vec3 a = positionOf(frames.frames[k - 1].true_pose);
        const Vec3 b = positionOf(frames.frames[k].true_pose);
        EXPECT_NEAR((b - a).head<2>().norm(), 1.5, 1e-12);
        EXPECT_NEAR(b.z(), -terrain_.elevationAt(b.x(), b.y()), 1e-12);
        // 10 deg more heading per stop.
        const double turned = attitudeOf(frames.frames[k - 1].true_pose).angularDistance(
            attitudeOf(frames.frames[k].true_pose));
        EXPECT_NEAR(turned, 10.0 * kDeg, 1e-12);
        EXPECT_EQ(frames.frames[k].timestamp_ns - frames.frames[k - 1].timestamp_ns, 30'000'000'000ULL);
    }
}

TEST_F(PlaneWorld, SameScenarioGivesTheSameFramesAndAnotherSeedOtherOdometry) {
    static ScenarioFrames a;
    static ScenarioFrames b;
    Scenario s = parseOk(std::string(kMinimal) + "[odometry]\nrandom_walk_m_per_sqrt_m 0.1\n");
    s.terrain = planeTerrain();
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, a).isOk());
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, b).isOk());
    EXPECT_EQ(std::memcmp(&a.frames[1].odometry_pose, &b.frames[1].odometry_pose, sizeof(VehiclePose)), 0);
    s.seed = 6U;
    ASSERT_TRUE(buildScenarioFrames(s, terrain_, b).isOk());
    EXPECT_NE(a.frames[1].odometry_pose.position_m[0], b.frames[1].odometry_pose.position_m[0]);
    EXPECT_EQ(std::memcmp(&a.frames[1].true_pose, &b.frames[1].true_pose, sizeof(VehiclePose)), 0);
}

TEST_F(PlaneWorld, BuildingFramesTouchesNoHeap) {
    static ScenarioFrames frames;
    Scenario s = parseOk(kMinimal);
    s.terrain = planeTerrain();
    vtm::test::NoHeapScope scope;
    const Status st = buildScenarioFrames(s, terrain_, frames);
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_TRUE(st.isOk());
}

// ---- odometry error model ------------------------------------------------------------------

// A straight drive north, 1 m steps, level.
std::vector<VehiclePose> straightDrive(int poses) {
    std::vector<VehiclePose> truth(static_cast<std::size_t>(poses));
    for (int k = 0; k < poses; ++k) {
        truth[static_cast<std::size_t>(k)].timestamp_ns = 1000U + static_cast<std::uint64_t>(k);
        truth[static_cast<std::size_t>(k)].position_m[0] = 0.1 + k;
        truth[static_cast<std::size_t>(k)].position_m[1] = 0.3;
        truth[static_cast<std::size_t>(k)].position_m[2] = -0.7;
    }
    return truth;
}

TEST(OdometryModel, ZeroModelGivesTheTruthBitForBitOtherwiseNot) {
    std::vector<VehiclePose> truth = straightDrive(10);
    for (std::size_t k = 0; k < truth.size(); ++k) {  // a turning path: yaw 7 deg per step
        const Quat q(Eigen::AngleAxisd(7.0 * kDeg * static_cast<double>(k), Vec3::UnitZ()));
        truth[k].attitude_wxyz[0] = q.w();
        truth[k].attitude_wxyz[3] = q.z();
    }
    std::vector<VehiclePose> odo(truth.size());
    applyOdometryErrors(OdometryErrorModel{}, 42U, truth.data(), odo.data(), 10);
    for (std::size_t k = 0; k < truth.size(); ++k) {
        EXPECT_EQ(std::memcmp(&truth[k], &odo[k], sizeof(VehiclePose)), 0) << k;
    }
    OdometryErrorModel m;
    m.scale_error_percent = 1.0;
    applyOdometryErrors(m, 42U, truth.data(), odo.data(), 10);
    EXPECT_NE(odo[9].position_m[0], truth[9].position_m[0]);
    EXPECT_EQ(odo[9].timestamp_ns, truth[9].timestamp_ns);
}

struct Moments {
    double mean = 0.0;
    double sd = 0.0;
};
Moments moments(const std::vector<double>& v) {
    Moments m;
    for (const double x : v) m.mean += x;
    m.mean /= static_cast<double>(v.size());
    for (const double x : v) m.sd += (x - m.mean) * (x - m.mean);
    m.sd = std::sqrt(m.sd / static_cast<double>(v.size() - 1));
    return m;
}

TEST(OdometryModel, ScaleAndHeadingStatisticsOverSeedsMatchTheModel) {
    constexpr int kSeeds = 400;
    constexpr int kPoses = 21;  // 20 m
    const std::vector<VehiclePose> truth = straightDrive(kPoses);
    OdometryErrorModel m;
    m.scale_error_percent = 2.0;
    m.scale_error_sigma_percent = 0.5;
    m.heading_drift_deg_per_m = 0.3;
    m.heading_drift_sigma_deg_per_m = 0.1;
    std::vector<VehiclePose> odo(kPoses);
    std::vector<double> scale_percent;
    std::vector<double> heading_deg_per_m;
    double sum_yaw2 = 0.0;
    for (int seed = 0; seed < kSeeds; ++seed) {
        applyOdometryErrors(m, static_cast<std::uint64_t>(seed) * 7919U + 1U, truth.data(), odo.data(), kPoses);
        double travelled = 0.0;
        for (int k = 1; k < kPoses; ++k) {
            travelled += (positionOf(odo[static_cast<std::size_t>(k)]) - positionOf(odo[static_cast<std::size_t>(k - 1)])).norm();
        }
        scale_percent.push_back((travelled / 20.0 - 1.0) * 100.0);
        const Quat q = attitudeOf(odo.back());
        const double yaw = std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
        heading_deg_per_m.push_back(yaw / kDeg / 20.0);
        sum_yaw2 += yaw * yaw;
    }
    const Moments s = moments(scale_percent);
    const Moments h = moments(heading_deg_per_m);
    // Means within 4 standard errors; spreads within 20 % (sd of a sample sd ~ 3.5 % here).
    EXPECT_NEAR(s.mean, 2.0, 4.0 * 0.5 / std::sqrt(kSeeds));
    EXPECT_NEAR(s.sd, 0.5, 0.1);
    EXPECT_NEAR(h.mean, 0.3, 4.0 * 0.1 / std::sqrt(kSeeds));
    EXPECT_NEAR(h.sd, 0.1, 0.02);
    // The reported yaw variance is the model's second moment: mean of yaw^2 over seeds.
    const double yaw_var = odo.back().covariance[35];
    EXPECT_NEAR(sum_yaw2 / kSeeds, yaw_var, 0.2 * yaw_var);
    EXPECT_NEAR(yaw_var, (0.3 * 0.3 + 0.1 * 0.1) * (20.0 * kDeg) * (20.0 * kDeg), 1e-12);
}

TEST(OdometryModel, RandomWalkAndTiltMatchTheirCovariance) {
    constexpr int kSeeds = 400;
    constexpr int kPoses = 17;  // 16 m
    const std::vector<VehiclePose> truth = straightDrive(kPoses);
    OdometryErrorModel m;
    m.random_walk_m_per_sqrt_m = 0.05;
    m.tilt_drift_sigma_deg_per_m = 0.2;
    std::vector<VehiclePose> odo(kPoses);
    double sum_east2 = 0.0;
    double sum_roll2 = 0.0;
    for (int seed = 0; seed < kSeeds; ++seed) {
        applyOdometryErrors(m, static_cast<std::uint64_t>(seed) + 100U, truth.data(), odo.data(), kPoses);
        const double east = odo.back().position_m[1] - truth.back().position_m[1];
        sum_east2 += east * east;
        const Quat q = attitudeOf(odo.back());
        const double roll = std::atan2(2.0 * (q.w() * q.x() + q.y() * q.z()), 1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y()));
        sum_roll2 += roll * roll;
    }
    // East error on a northward drive: only the random walk (roll and pitch do not move
    // a level northward step sideways to first order): variance = walk^2 * d.
    const double var_east = 0.05 * 0.05 * 16.0;
    EXPECT_NEAR(sum_east2 / kSeeds, var_east, 0.25 * var_east);
    EXPECT_NEAR(sum_roll2 / kSeeds, odo.back().covariance[21], 0.25 * odo.back().covariance[21]);
    EXPECT_GE(odo.back().covariance[7], var_east);
}

}  // namespace
}  // namespace vtm::sim
