// The panorama scenario kind (sim/panorama.hpp, docs/sim-scenarios.md "Panorama"): parser
// errors, the stereo rig and mast geometry, neighbour overlap checked on terrain truth, the
// pointing error statistics against the prior covariance (chi-square with 6 degrees of
// freedom), rendered range truth against the terrain, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "terrain_pool.hpp"
#include "vtm/core/rotation.hpp"

#include <Eigen/Eigenvalues>  // after vtm/core/eigen.hpp: the test's own eigen-decomposition

namespace vtm::sim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::string readScenarioFile(const char* name) {
    std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/" + name, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Scenario parseOk(const std::string& text) {
    Scenario s;
    const Status st = parseScenario(text, s);
    EXPECT_TRUE(st.isOk()) << st.reason() << " line " << st.detail();
    return s;
}

// The small test panorama and its terrain (built once per test binary into slot 0).
const Scenario& smallScenario() {
    static const Scenario s = parseOk(readScenarioFile("test_panorama_small.scn"));
    return s;
}
const Terrain& smallTerrain() { return terrainInPool(smallScenario().terrain, 0); }

// The test scenario text with the line starting with `key` replaced by `line` (or, when
// no such line exists, `line` added at the end of `section`).
std::string withLine(const std::string& key, const std::string& line, const std::string& section = "[motion]") {
    std::string text = readScenarioFile("test_panorama_small.scn");
    const std::size_t at = text.find("\n" + key + " ");
    if (at != std::string::npos) {
        const std::size_t end = text.find('\n', at + 1U);
        return text.replace(at + 1U, end - at - 1U, line);
    }
    const std::size_t sec = text.find(section + "\n");
    if (sec == std::string::npos) {
        return text + "\n" + section + "\n" + line + "\n";
    }
    return text.insert(sec + section.size() + 1U, line + "\n");
}

void expectError(const std::string& text, StatusCode code, const char* reason_part) {
    Scenario s;
    const Status st = parseScenario(text, s);
    EXPECT_EQ(st.code(), code) << st.reason();
    EXPECT_NE(std::strstr(st.reason(), reason_part), nullptr) << "got: " << st.reason();
}

// ---- parser -------------------------------------------------------------------------------

TEST(PanoramaParser, ShippedPanoramasParseWithTheirFields) {
    const Scenario big = parseOk(readScenarioFile("panorama.scn"));
    EXPECT_EQ(big.kind, ScenarioKind::kPanorama);
    EXPECT_EQ(big.motion.columns, 10);
    ASSERT_EQ(big.motion.tiers.count, 3);
    EXPECT_DOUBLE_EQ(big.motion.tiers.deg[2], -60.0);
    EXPECT_EQ(big.camera.width_px, 1024U);
    EXPECT_DOUBLE_EQ(big.motion.stereo_baseline_m, 0.42);
    EXPECT_EQ(scenarioFrameCount(big), 60);
    const Scenario& small = smallScenario();
    EXPECT_EQ(small.kind, ScenarioKind::kPanorama);
    EXPECT_EQ(small.motion.tiers.count, 2);
    EXPECT_DOUBLE_EQ(small.motion.tiers.deg[1], -45.0);
    EXPECT_DOUBLE_EQ(small.pointing.rover_heading_sigma_deg, 1.0);
    EXPECT_DOUBLE_EQ(small.pointing.head_offset_sigma_m, 0.005);
    EXPECT_EQ(scenarioFrameCount(small), 32);
}

TEST(PanoramaParser, ErrorsNameTheKey) {
    expectError(withLine("tier_tilts_deg", "tier_tilts_deg -10"), StatusCode::kCorruptData,
                "motion.tier_tilts_deg has a bad value");
    expectError(withLine("tier_tilts_deg", "tier_tilts_deg -10 -20 -30 -40"), StatusCode::kCorruptData,
                "motion.tier_tilts_deg has a bad value");
    expectError(withLine("tier_tilts_deg", "tier_tilts_deg -10 -95"), StatusCode::kInvalidConfig,
                "motion.tier_tilts_deg is out of range");
    expectError(withLine("columns", "columns 2"), StatusCode::kInvalidConfig, "motion.columns is out of range");
    expectError(withLine("columns", "columns 5"), StatusCode::kInvalidConfig,
                "motion.columns too few for the camera's field of view");
    expectError(withLine("tier_tilts_deg", "tier_tilts_deg -5 -70"), StatusCode::kInvalidConfig,
                "motion.tier_tilts_deg farther apart than the camera's vertical field of view");
}

TEST(PanoramaParser, MoreErrorsNameTheKey) {
    // 3 tiers x 11 columns = 33 stations = 66 frames.
    std::string text = withLine("tier_tilts_deg", "tier_tilts_deg -10 -35 -60");
    text = text.replace(text.find("columns 8"), 9, "columns 11");
    expectError(text, StatusCode::kInvalidConfig, "more frames than kMaxScenarioFrames");
    expectError(withLine("pan_sigma_deg", "pan_sigma_deg -1", "[pointing]"), StatusCode::kInvalidConfig,
                "pointing.pan_sigma_deg is out of range");
    expectError(withLine("bogus", "bogus 1", "[pointing]"), StatusCode::kCorruptData, "unknown key in [pointing]");
    expectError(withLine("mount_tilt_deg", "mount_tilt_deg -20", "[camera]"), StatusCode::kInvalidConfig,
                "camera.mount_tilt_deg does not belong to this kind");
    expectError(withLine("scale_error_percent", "scale_error_percent 1", "[odometry]"), StatusCode::kInvalidConfig,
                "odometry.scale_error_percent does not belong to this kind");
    // A scenario built in code is checked the same way.
    Scenario s = smallScenario();
    s.motion.tiers.count = 1;
    Status st = validateScenario(s);
    EXPECT_EQ(st.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::strstr(st.reason(), "motion.tier_tilts_deg is out of range"), nullptr) << st.reason();
    s = smallScenario();
    s.motion.columns = 5;
    st = validateScenario(s);
    EXPECT_NE(std::strstr(st.reason(), "motion.columns too few"), nullptr) << st.reason();
    static Panorama p;
    const Scenario rover_pair = parseOk(readScenarioFile("test_rover_small.scn"));
    st = buildPanorama(rover_pair, smallTerrain(), p);
    EXPECT_EQ(st.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::strstr(st.reason(), "not panorama"), nullptr) << st.reason();
    // [pointing] keys in another kind.
    std::string pair = readScenarioFile("test_rover_small.scn") + "\n[pointing]\npan_sigma_deg 0.1\n";
    expectError(pair, StatusCode::kInvalidConfig, "pointing.pan_sigma_deg does not belong to this kind");
}

// ---- geometry -----------------------------------------------------------------------------

TEST(PanoramaGeometry, OverlapMatchesThePinholeFormula) {
    const Scenario big = parseOk(readScenarioFile("panorama.scn"));
    PanoramaOverlap o;
    ASSERT_TRUE(panoramaOverlap(big, o).isOk());
    // A pinhole of field of view h tilted by t covers 2 atan(tan(h/2) / cos t) of pan on its
    // middle row; tiers 25 deg apart with a 45 deg vertical field overlap by 20 deg.
    const double tilts[] = {-10.0, -35.0, -60.0};
    for (int t = 0; t < 3; ++t) {
        const double width = 2.0 * std::atan(std::tan(22.5 * kDeg) / std::cos(tilts[t] * kDeg)) / kDeg;
        EXPECT_NEAR(o.horizontal_deg[t], width - 36.0, 1e-9) << t;
    }
    EXPECT_NEAR(o.vertical_deg[0], 20.0, 1e-9);
    EXPECT_NEAR(o.vertical_deg[1], 20.0, 1e-9);
}

TEST(PanoramaGeometry, RightEyeIsTheLeftThroughTheCalibratedBaseline) {
    static Panorama p;
    ASSERT_TRUE(buildPanorama(smallScenario(), smallTerrain(), p).isOk());
    static ScenarioFrames frames;
    ASSERT_TRUE(buildScenarioFrames(smallScenario(), smallTerrain(), frames).isOk());
    ASSERT_EQ(p.count, 16);
    ASSERT_EQ(frames.count, 32);
    // The frames carry the rover: true pose and the attitude telemetry with its covariance
    // (a level rover: the heading error is about the site's z axis, 1 deg sigma).
    const VehiclePose& odo = frames.frames[5].odometry_pose;
    const Mat3 R_odo = Quat(odo.attitude_wxyz[0], odo.attitude_wxyz[1], odo.attitude_wxyz[2], odo.attitude_wxyz[3])
                           .toRotationMatrix();
    EXPECT_LT((R_odo - p.rover.R_telemetry).norm(), 1e-12);
    EXPECT_GT(rotationAngleRad(R_odo, p.rover.R_site_from_vehicle), 1e-4);
    EXPECT_NEAR(odo.covariance[35], (1.0 * kDeg) * (1.0 * kDeg), 1e-15);
    EXPECT_NEAR(odo.covariance[21], (0.3 * kDeg) * (0.3 * kDeg), 1e-15);
    EXPECT_NEAR(odo.position_m[2], p.rover.position_site_m.z(), 0.0);
    for (int k = 0; k < p.count; ++k) {
        const NetworkStation& truth = p.stations[k].truth;
        ASSERT_TRUE(validateNetworkStation(truth).isOk());
        ASSERT_TRUE(validateNetworkStation(p.stations[k].approx).isOk());
        const RigidPose left = siteFromEye(truth, Eye::kLeft);
        const RigidPose right = siteFromEye(truth, Eye::kRight);
        // The rendered frames are the true eyes.
        EXPECT_EQ((frames.frames[2 * k].camera_pose.t_m - left.t_m).norm(), 0.0) << k;
        EXPECT_EQ((frames.frames[2 * k + 1].camera_pose.t_m - right.t_m).norm(), 0.0) << k;
        EXPECT_EQ(frames.frames[2 * k].role, FrameRole::kStereoLeft);
        EXPECT_EQ(frames.frames[2 * k + 1].role, FrameRole::kStereoRight);
        EXPECT_EQ(frames.frames[2 * k + 1].sequence, static_cast<std::uint32_t>(k));
        // Same orientation, right centre 0.42 m along the left's image-right axis.
        EXPECT_LT((right.R - left.R).norm(), 1e-15) << k;
        const Vec3 baseline = left.R.transpose() * (right.t_m - left.t_m);
        EXPECT_NEAR(baseline.x(), 0.42, 1e-12) << k;
        EXPECT_NEAR(baseline.y(), 0.0, 1e-12) << k;
        EXPECT_NEAR(baseline.z(), 0.0, 1e-12) << k;
        // The true view elevation is the tier's, up to the mast flex.
        const Vec3 axis = left.R * Vec3::UnitZ();
        const double elevation = std::asin(-axis.z()) / kDeg;
        EXPECT_NEAR(elevation, p.stations[k].tilt_deg, 1.0) << k;  // within the mast flex (true stations)
    }
}

TEST(PanoramaGeometry, WithoutErrorsEveryStationTurnsAboutTheMastHead) {
    Scenario s = smallScenario();
    s.pointing = PointingErrorModel{};
    static Panorama p;
    ASSERT_TRUE(buildPanorama(s, smallTerrain(), p).isOk());
    const Vec3 head = p.rover.position_site_m + p.rover.R_site_from_vehicle * s.mount.position_vehicle_m;
    // The rover stands on the terrain at start_m.
    EXPECT_NEAR(-p.rover.position_site_m.z(), smallTerrain().elevationAt(1.0, -2.0), 1e-12);
    for (int k = 0; k < p.count; ++k) {
        const RigidPose l = siteFromEye(p.stations[k].truth, Eye::kLeft);
        const RigidPose r = siteFromEye(p.stations[k].truth, Eye::kRight);
        EXPECT_LT((0.5 * (l.t_m + r.t_m) - head).norm(), 1e-12) << k;
        // Approximate = true without errors; zero prior.
        EXPECT_LT(rotationAngleRad(l.R, p.stations[k].approx.site_from_a.R), 1e-12) << k;
        EXPECT_LT((l.t_m - p.stations[k].approx.site_from_a.t_m).norm(), 1e-12) << k;
        EXPECT_EQ(p.stations[k].approx.prior_covariance.norm(), 0.0) << k;
        // Azimuth of the optical axis: heading 30 deg + column * 45 deg.
        const Vec3 axis = l.R * Vec3::UnitZ();
        const double azimuth = std::atan2(axis.y(), axis.x()) / kDeg;
        const double expected = 30.0 + 45.0 * p.stations[k].column;
        EXPECT_NEAR(std::remainder(azimuth - expected, 360.0), 0.0, 1e-9) << k;
        EXPECT_NEAR(std::asin(-axis.z()) / kDeg, p.stations[k].tilt_deg, 1e-9) << k;
    }
}

// Ground points of a grid of pixels of image a that image b also sees (projected inside b
// and b's own ray cast through that pixel lands on the same point: not occluded).
int sharedGroundPoints(const Terrain& terrain, const NetworkStation& a, Eye eye_a, const NetworkStation& b,
                       Eye eye_b) {
    const CameraModel& ma = modelOfEye(a, eye_a);
    const CameraModel& mb = modelOfEye(b, eye_b);
    const RigidPose pose_b = siteFromEye(b, eye_b);
    int shared = 0;
    for (int v = 2; v < ma.height_px; v += 6) {
        for (int u = 2; u < ma.width_px; u += 6) {
            Vec3 x;
            if (!panoramaGroundPoint(terrain, a, eye_a, Vec2(u, v), x).isOk()) {
                continue;
            }
            Vec2 pb;
            const Vec3 in_b = pose_b.R.transpose() * (x - pose_b.t_m);
            if (!projectPoint(mb, in_b, pb).isOk() || pb.x() < 0.0 || pb.y() < 0.0 ||
                pb.x() > mb.width_px - 1.0 || pb.y() > mb.height_px - 1.0) {
                continue;
            }
            Vec3 xb;
            if (panoramaGroundPoint(terrain, b, eye_b, pb, xb).isOk() && (xb - x).norm() < 0.01) {
                ++shared;
            }
        }
    }
    return shared;
}

TEST(PanoramaGeometry, NeighboursSeeCommonGroundPoints) {
    static Panorama p;
    ASSERT_TRUE(buildPanorama(smallScenario(), smallTerrain(), p).isOk());
    const int columns = p.columns;
    int weakest_horizontal = 1 << 30;
    for (int t = 0; t < p.tiers; ++t) {
        for (int c = 0; c < columns; ++c) {
            const NetworkStation& a = p.stations[panoramaStationIndex(t, c, columns)].truth;
            const NetworkStation& b = p.stations[panoramaStationIndex(t, (c + 1) % columns, columns)].truth;
            const int n = sharedGroundPoints(smallTerrain(), a, Eye::kLeft, b, Eye::kLeft);
            weakest_horizontal = std::min(weakest_horizontal, n);
            // Pan overlap 17-33 % of the width (docs), less the sky above the -15 deg tier.
            EXPECT_GE(n, 50) << "tier " << t << " column " << c;
        }
    }
    int weakest_vertical = 1 << 30;
    for (int c = 0; c < columns; ++c) {
        const NetworkStation& a = p.stations[panoramaStationIndex(0, c, columns)].truth;
        const NetworkStation& b = p.stations[panoramaStationIndex(1, c, columns)].truth;
        const int n = sharedGroundPoints(smallTerrain(), a, Eye::kLeft, b, Eye::kLeft);
        weakest_vertical = std::min(weakest_vertical, n);
        EXPECT_GE(n, 100) << "column " << c;  // tilt overlap 30 of 60 deg
    }
    // The two eyes of one station see mostly the same ground.
    const NetworkStation& s = p.stations[panoramaStationIndex(1, 0, columns)].truth;
    const int stereo = sharedGroundPoints(smallTerrain(), s, Eye::kLeft, s, Eye::kRight);
    EXPECT_GE(stereo, 300);
    RecordProperty("weakest_horizontal_shared_of_441", weakest_horizontal);
    RecordProperty("weakest_vertical_shared_of_441", weakest_vertical);
    RecordProperty("stereo_shared_of_441", stereo);
}

// ---- pointing errors ----------------------------------------------------------------------

struct StationError {
    Vec6 e = Vec6::Zero();
    double chi2 = 0.0;
};

StationError stationError(const PanoramaStation& s) {
    StationError out;
    out.e.head<3>() = rotationLog(s.truth.site_from_a.R * s.approx.site_from_a.R.transpose());
    out.e.tail<3>() = s.truth.site_from_a.t_m - s.approx.site_from_a.t_m;
    out.chi2 = out.e.dot(s.approx.prior_covariance.ldlt().solve(out.e));
    return out;
}

TEST(PanoramaErrors, NormalisedErrorsFollowChiSquareWithSixDegreesOfFreedom) {
    Scenario s = smallScenario();
    static Panorama p;
    constexpr int kSeeds = 400;
    std::vector<double> chi2;
    std::vector<double> heading0;
    std::vector<double> heading1;
    std::vector<double> z_theta;
    std::vector<double> z_t;
    for (int seed = 1; seed <= kSeeds; ++seed) {
        s.seed = static_cast<std::uint64_t>(seed) * 7919U;
        ASSERT_TRUE(buildPanorama(s, smallTerrain(), p).isOk());
        // One station per seed: stations of one panorama share the per-panorama errors.
        const int k = seed % p.count;
        const StationError e = stationError(p.stations[k]);
        chi2.push_back(e.chi2);
        const Mat6& c = p.stations[k].approx.prior_covariance;
        z_theta.push_back(e.e(2) / std::sqrt(c(2, 2)));
        z_t.push_back(e.e(3) / std::sqrt(c(3, 3)));
        heading0.push_back(stationError(p.stations[0]).e(2));
        heading1.push_back(stationError(p.stations[5]).e(2));
    }
    double mean = 0.0;
    int above_95 = 0;
    for (const double x : chi2) {
        mean += x;
        above_95 += (x > 12.5916) ? 1 : 0;  // chi-square(6) 95th percentile
    }
    mean /= kSeeds;
    double var = 0.0;
    for (const double x : chi2) {
        var += (x - mean) * (x - mean);
    }
    var /= (kSeeds - 1);
    // chi-square(6): mean 6, variance 12. Sampling sd of the mean sqrt(12/400) = 0.17; of the
    // variance about 12 * sqrt(2/400) * 2 ~ 2.4 (heavier tail: 4 sd allowed below).
    EXPECT_NEAR(mean, 6.0, 0.7);
    RecordProperty("chi2_mean_x1000", static_cast<int>(mean * 1000.0));
    RecordProperty("chi2_var_x1000", static_cast<int>(var * 1000.0));
    RecordProperty("chi2_above_95_of_400", above_95);
    EXPECT_NEAR(var, 12.0, 5.0);
    // 5 % above the 95th percentile, binomial sd 1.1 %.
    EXPECT_NEAR(above_95 / static_cast<double>(kSeeds), 0.05, 0.035);
    // Single components: unit variance.
    double v_theta = 0.0;
    double v_t = 0.0;
    for (int i = 0; i < kSeeds; ++i) {
        v_theta += z_theta[i] * z_theta[i];
        v_t += z_t[i] * z_t[i];
    }
    EXPECT_NEAR(v_theta / kSeeds, 1.0, 0.3);
    EXPECT_NEAR(v_t / kSeeds, 1.0, 0.3);
    // The rover's heading error is shared: the stations' azimuth errors are correlated.
    double sxy = 0.0;
    double sxx = 0.0;
    double syy = 0.0;
    for (int i = 0; i < kSeeds; ++i) {
        sxy += heading0[i] * heading1[i];
        sxx += heading0[i] * heading0[i];
        syy += heading1[i] * heading1[i];
    }
    EXPECT_GT(sxy / std::sqrt(sxx * syy), 0.8);
}

TEST(PanoramaErrors, JointErrorsOfTwoStationsFollowChiSquareOfTheJointRank) {
    Scenario s = smallScenario();
    static Panorama p;
    constexpr int kSeeds = 400;
    double sum = 0.0;
    double sum2 = 0.0;
    double cross_sum = 0.0;  // the heading (dtheta z) errors of the two stations, normalised
    double dof_sum = 0.0;
    // Second-order size of an error of 4 sigma of the largest angle (the 1 deg heading): theta^2 / 2.
    const double kSecondOrder = 0.5 * (4.0 * kDeg) * (4.0 * kDeg);
    for (int seed = 1; seed <= kSeeds; ++seed) {
        s.seed = static_cast<std::uint64_t>(seed) * 104729U;
        ASSERT_TRUE(buildPanorama(s, smallTerrain(), p).isOk());
        const int k = seed % p.count;
        const int l = (k + 5 + (seed % 3) * p.columns) % p.count;  // same tier or the other one
        Eigen::Matrix<double, 12, 12> joint;
        joint.block<6, 6>(0, 0) = panoramaCrossCovariance(s, p, k, k);
        joint.block<6, 6>(6, 6) = panoramaCrossCovariance(s, p, l, l);
        joint.block<6, 6>(0, 6) = panoramaCrossCovariance(s, p, k, l);
        joint.block<6, 6>(6, 0) = panoramaCrossCovariance(s, p, l, k);
        EXPECT_LT((joint.block<6, 6>(0, 6) - joint.block<6, 6>(6, 0).transpose()).norm(),
                  1e-12 * joint.norm());
        Eigen::Matrix<double, 12, 1> e;
        e.head<6>() = stationError(p.stations[k]).e;
        e.tail<6>() = stationError(p.stations[l]).e;
        // The joint is singular, rank 9 of 12: to first order three combinations of the 12
        // parameters change neither station: a mast tilt about the vehicle x axis with the same
        // rover roll; a mast tilt about y with the same rover pitch and the head offset that
        // undoes the head's move; a rover heading error with pan encoder errors undoing it at
        // both stations and the head offset. Chi-square over the eigenvectors whose eigenvalue
        // is not zero; along the others the errors are second-order small.
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> eig(joint);
        const double largest = eig.eigenvalues()(11);
        double chi2 = 0.0;
        int rank = 0;
        for (int i = 0; i < 12; ++i) {
            const double lambda = eig.eigenvalues()(i);
            const double along = eig.eigenvectors().col(i).dot(e);
            if (lambda > 1e-12 * largest) {
                chi2 += along * along / lambda;
                ++rank;
            } else {
                EXPECT_LT(std::abs(along), kSecondOrder) << seed;
            }
        }
        dof_sum += rank;
        sum += chi2;
        sum2 += chi2 * chi2;
        cross_sum += e(2) * e(8) / joint(2, 8);
    }
    const double mean = sum / kSeeds;
    const double var = sum2 / kSeeds - mean * mean;
    const double dof = dof_sum / kSeeds;
    // chi-square(dof): mean dof (sampling sd ~0.24), variance 2 dof.
    EXPECT_EQ(dof, 9.0);
    EXPECT_NEAR(mean, dof, 1.0);
    EXPECT_NEAR(var, 2.0 * dof, 10.0);
    RecordProperty("joint_rank_x1000", static_cast<int>(dof * 1000.0));
    // The predicted cross-covariance of the heading errors is the sampled one (ratio ~1).
    EXPECT_NEAR(cross_sum / kSeeds, 1.0, 0.25);
    RecordProperty("heading_cross_ratio_x1000", static_cast<int>(cross_sum / kSeeds * 1000.0));
    RecordProperty("joint_chi2_mean_x1000", static_cast<int>(mean * 1000.0));
    RecordProperty("joint_chi2_var_x1000", static_cast<int>(var * 1000.0));
}

TEST(PanoramaErrors, PerPanoramaErrorsAreSharedAndEncoderErrorsAreNot) {
    Scenario s = smallScenario();
    s.pointing = PointingErrorModel{};
    s.pointing.pan_sigma_deg = 0.5;
    static Panorama p;
    ASSERT_TRUE(buildPanorama(s, smallTerrain(), p).isOk());
    // Only the pan encoder: each station's error is a turn about the mast (site z) axis by
    // minus its own pan error, and the prior's rotation block is sigma^2 on z alone.
    const double sigma = 0.5 * kDeg;
    double previous = 0.0;
    for (int k = 0; k < p.count; ++k) {
        const StationError e = stationError(p.stations[k]);
        EXPECT_NEAR(e.e(2), -p.errors.pan_error_rad[k], 1e-9) << k;
        EXPECT_NEAR(e.e(0), 0.0, 1e-9);
        EXPECT_NEAR(p.stations[k].approx.prior_covariance(2, 2), sigma * sigma, 1e-12 * sigma * sigma);
        EXPECT_NEAR(p.stations[k].approx.prior_covariance(0, 0), 0.0, 1e-20);
        EXPECT_NE(e.e(2), previous);
        previous = e.e(2);
    }
}

// ---- rendering ----------------------------------------------------------------------------

TEST(PanoramaRender, RangeTruthLiesOnTheTerrain) {
    static ScenarioFrames frames;
    ASSERT_TRUE(buildScenarioFrames(smallScenario(), smallTerrain(), frames).isOk());
    const int w = 128;
    std::vector<std::uint8_t> image(static_cast<std::size_t>(w * w));
    std::vector<float> range(static_cast<std::size_t>(w * w));
    int checked = 0;
    double worst = 0.0;
    for (const int f : {1, 18}) {  // right eye of station 0 (tier -15 deg), left eye of station 9 (tier -45 deg)
        const ScenarioFrame& frame = frames.frames[f];
        FrameOutput out;
        out.image8 = ImageView<std::uint8_t>(image.data(), w, w, w);
        out.truth.range_m = ImageView<float>(range.data(), w, w, w);
        RenderStats stats;
        ASSERT_TRUE(renderFrame(scenarioFrameRequest(smallScenario(), smallTerrain(), frame), out, &stats).isOk());
        EXPECT_GT(stats.hit_pixels, w * w / 4) << f;
        for (int v = 0; v < w; v += 3) {
            for (int u = 0; u < w; u += 3) {
                const float r = range[static_cast<std::size_t>(v * w + u)];
                if (!std::isfinite(r)) {
                    continue;
                }
                CameraRay ray;
                ASSERT_TRUE(backProjectPixel(frame.model, Vec2(u, v), ray).isOk());
                const Vec3 origin = transformPoint(frame.camera_pose, ray.origin_m);
                const Vec3 x = origin + static_cast<double>(r) * (frame.camera_pose.R * ray.direction);
                const double height_error = std::abs(smallTerrain().elevationAt(x.x(), x.y()) + x.z());
                // float range: ~6e-8 relative; steep rock flanks turn it into height.
                const double tolerance = 2e-6 + 2e-7 * r;
                worst = std::max(worst, height_error / tolerance);
                EXPECT_LE(height_error, tolerance) << "frame " << f << " pixel " << u << "," << v;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 500);
    RecordProperty("worst_height_error_over_tolerance_x1000", static_cast<int>(worst * 1000.0));
}

TEST(PanoramaRender, GroundPointOfAPixelMatchesTheRenderedRange) {
    static Panorama p;
    ASSERT_TRUE(buildPanorama(smallScenario(), smallTerrain(), p).isOk());
    static ScenarioFrames frames;
    ASSERT_TRUE(buildScenarioFrames(smallScenario(), smallTerrain(), frames).isOk());
    const int w = 128;
    std::vector<std::uint8_t> image(static_cast<std::size_t>(w * w));
    std::vector<float> range(static_cast<std::size_t>(w * w));
    const int k = panoramaStationIndex(1, 3, p.columns);
    FrameOutput out;
    out.image8 = ImageView<std::uint8_t>(image.data(), w, w, w);
    out.truth.range_m = ImageView<float>(range.data(), w, w, w);
    ASSERT_TRUE(renderFrame(scenarioFrameRequest(smallScenario(), smallTerrain(), frames.frames[2 * k + 1]), out,
                            nullptr)
                    .isOk());
    const RigidPose right = siteFromEye(p.stations[k].truth, Eye::kRight);
    int compared = 0;
    for (int v = 1; v < w; v += 9) {
        for (int u = 1; u < w; u += 9) {
            Vec3 x;
            const float r = range[static_cast<std::size_t>(v * w + u)];
            const Status st = panoramaGroundPoint(smallTerrain(), p.stations[k].truth, Eye::kRight, Vec2(u, v), x);
            ASSERT_EQ(st.isOk(), std::isfinite(r)) << u << "," << v;
            if (st.isOk()) {
                EXPECT_NEAR((x - right.t_m).norm(), r, 1e-5 * r + 1e-5) << u << "," << v;
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 100);
}

// ---- determinism and heap -----------------------------------------------------------------

TEST(PanoramaDeterminism, SameSeedSameBitsOtherSeedOtherErrors) {
    static Panorama a;
    static Panorama b;
    ASSERT_TRUE(buildPanorama(smallScenario(), smallTerrain(), a).isOk());
    ASSERT_TRUE(buildPanorama(smallScenario(), smallTerrain(), b).isOk());
    EXPECT_EQ(std::memcmp(&a.errors, &b.errors, sizeof(a.errors)), 0);
    for (int k = 0; k < a.count; ++k) {
        EXPECT_EQ(std::memcmp(&a.stations[k].truth.site_from_a, &b.stations[k].truth.site_from_a,
                              sizeof(RigidPose)), 0);
        EXPECT_EQ(std::memcmp(&a.stations[k].approx.site_from_a, &b.stations[k].approx.site_from_a,
                              sizeof(RigidPose)), 0);
        EXPECT_EQ(std::memcmp(a.stations[k].approx.prior_covariance.data(),
                              b.stations[k].approx.prior_covariance.data(), sizeof(Mat6)), 0);
    }
    Scenario other = smallScenario();
    other.seed += 1U;
    ASSERT_TRUE(buildPanorama(other, smallTerrain(), b).isOk());
    EXPECT_NE(a.errors.rover_attitude_rad.x(), b.errors.rover_attitude_rad.x());
    EXPECT_NE(a.stations[3].approx.site_from_a.t_m.x(), b.stations[3].approx.site_from_a.t_m.x());
}

TEST(PanoramaDeterminism, BuildingThePanoramaTouchesNoHeap) {
    static Panorama p;
    static ScenarioFrames frames;
    const Terrain& terrain = smallTerrain();
    vtm::test::NoHeapScope scope;
    const Status a = buildPanorama(smallScenario(), terrain, p);
    const Status b = buildScenarioFrames(smallScenario(), terrain, frames);
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_TRUE(a.isOk());
    EXPECT_TRUE(b.isOk());
}

}  // namespace
}  // namespace vtm::sim
