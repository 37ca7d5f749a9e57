// `vtm refine` and `vtm rectify` as a user runs them on vtm-sim's files: a rover pair is
// rendered, camera 2's pose is spoiled the way odometry spoils it (2 deg of heading, 5 % of
// the baseline sideways), vtm refine must bring it back near the truth, and vtm rectify
// must write a rectified pair whose true correspondences share their rows. Bad inputs exit
// non-zero with one line naming the input.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ground_test_files.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::ground {
namespace {

using test::CommandRun;
using test::runCommand;
using test::slurp;

CommandRun runTool(const test::TempDir& dir, const char* exe, const std::string& args) {
    return runCommand(dir, exe, args);
}

double angleDeg(const Mat3& a, const Mat3& b) {
    const double c = std::fmax(-1.0, std::fmin(1.0, 0.5 * ((a.transpose() * b).trace() - 1.0)));
    return std::acos(c) * 57.29577951308232;
}

// Relative pose X_2 = R X_1 + t of two camera poses.
void relative(const SimCameraPose& p1, const SimCameraPose& p2, Mat3& R, Vec3& t) {
    const RigidPose cam2_from_cam1 = relativePose(siteFromCam(p1), siteFromCam(p2));
    R = cam2_from_cam1.R;
    t = cam2_from_cam1.t_m;
}

// A 512 x 512 rover pair 2 m apart (rover_wide_baseline's world), rendered once.
class WideBaselineCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        // The shipped rover scenario, smaller: 512 x 512, 2 m apart, 10 deg toed in, the mast
        // tilted so that both axes meet the ground where they converge (11.4 m).
        std::string scn = slurp(std::string(VTM_SCENARIO_DIR) + "/rover_wide_baseline.scn");
        const std::pair<const char*, const char*> edits[] = {{"width_px 1024", "width_px 512"},
                                                             {"height_px 1024", "height_px 512"},
                                                             {"\nbaseline_m 5", "\nbaseline_m 2"},
                                                             {"mount_tilt_deg -18", "mount_tilt_deg -9.5"}};
        for (const auto& [from, to] : edits) {
            const std::size_t at = scn.find(from);
            ASSERT_NE(at, std::string::npos) << from;
            scn.replace(at, std::string(from).size(), to);
        }
        std::ofstream(dir_->file("pair.scn")) << scn;
        const CommandRun r =
            runTool(*dir_, VTM_SIM_EXECUTABLE, "render '" + dir_->file("pair.scn") + "' '" + dir_->file("sim") + "' --frames 0,1");
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::string sim(const std::string& name) { return dir_->file("sim/" + name); }
    static test::TempDir* dir_;
};
test::TempDir* WideBaselineCli::dir_ = nullptr;

// Odometry-like error on camera 2 of the rendered pair: 2 deg of heading (about the site's
// vertical) and 5 % of the baseline sideways.
SimCameraPose spoiledPose2(const SimCameraPose& p1, const SimCameraPose& p2) {
    const Mat3 yaw = Eigen::AngleAxisd(2.0 / 57.29577951308232, Vec3::UnitZ()).toRotationMatrix();
    const RigidPose site_from_cam1 = siteFromCam(p1);
    RigidPose site_from_cam2 = siteFromCam(p2);
    const Vec3 base = site_from_cam2.t_m - site_from_cam1.t_m;
    site_from_cam2.R = yaw * site_from_cam2.R;
    site_from_cam2.t_m += base.cross(Vec3::UnitZ()).normalized() * (0.05 * base.norm());
    SimCameraPose spoiled = p2;
    setSiteFromCam(spoiled, site_from_cam2);
    return spoiled;
}

TEST_F(WideBaselineCli, RefineBringsASpoiledOdometryPoseBackToTheTruth) {
    auto p1 = readCameraPoseSpec(sim("camera_poses.txt:0"));
    auto p2 = readCameraPoseSpec(sim("camera_poses.txt:1"));
    ASSERT_TRUE(p1.ok && p2.ok) << p1.error << p2.error;
    const SimCameraPose spoiled = spoiledPose2(p1.value, p2.value);
    std::ofstream(dir_->file("odometry2.txt")) << formatCameraPoses({spoiled});

    const CommandRun r = runTool(*dir_, VTM_EXECUTABLE,
                                 "refine '" + sim("mast_000.png") + "' '" + sim("mast_001.png") + "' --camera '" +
                                     sim("mast.cmod") + "' --pose1 '" + sim("camera_poses.txt") + ":0' --pose2 '" +
                                     dir_->file("odometry2.txt") + "' --range 1:1000 --out '" +
                                     dir_->file("refined.txt") + "' --report '" + dir_->file("refine.md") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(slurp(dir_->file("refine.md")).find("inliers"), std::string::npos);
    auto q1 = readCameraPoseSpec(dir_->file("refined.txt") + ":0");
    auto q2 = readCameraPoseSpec(dir_->file("refined.txt") + ":1");
    ASSERT_TRUE(q1.ok && q2.ok) << q1.error << q2.error;
    Mat3 R_true, R_odo, R_ref;
    Vec3 t_true, t_odo, t_ref;
    relative(p1.value, p2.value, R_true, t_true);
    relative(p1.value, spoiled, R_odo, t_odo);
    relative(q1.value, q2.value, R_ref, t_ref);
    const double rot_before = angleDeg(R_true, R_odo);
    const double rot_after = angleDeg(R_true, R_ref);
    const double dir_before = std::acos(t_true.normalized().dot(t_odo.normalized())) * 57.29577951308232;
    const double dir_after = std::acos(std::fmin(1.0, t_true.normalized().dot(t_ref.normalized()))) * 57.29577951308232;
    std::printf("rotation error %.3f -> %.3f deg, direction error %.3f -> %.3f deg\n", rot_before, rot_after,
                dir_before, dir_after);
    EXPECT_GT(rot_before, 1.9);
    EXPECT_LT(rot_after, 0.1);
    EXPECT_LT(dir_after, 0.25 * dir_before);
    // The baseline length is the odometry's (not observable from images).
    EXPECT_NEAR(t_ref.norm(), t_odo.norm(), 1e-9);
}

// The report's range of the inliers (where the refined motion was measured; rows of nearer
// or farther points are extrapolated) against the renderer's true range at the same pixels.
TEST_F(WideBaselineCli, RefineReportsTheRangeOfItsInliersAsTheRendererHasIt) {
    auto p1 = readCameraPoseSpec(sim("camera_poses.txt:0"));
    auto p2 = readCameraPoseSpec(sim("camera_poses.txt:1"));
    auto range = readPfm(sim("mast_000_range.pfm"));
    ASSERT_TRUE(p1.ok && p2.ok && range.ok) << p1.error << p2.error << range.error;
    std::ofstream(dir_->file("odometry2b.txt")) << formatCameraPoses({spoiledPose2(p1.value, p2.value)});
    const CommandRun r = runTool(*dir_, VTM_EXECUTABLE,
                                 "refine '" + sim("mast_000.png") + "' '" + sim("mast_001.png") + "' --camera '" +
                                     sim("mast.cmod") + "' --pose1 '" + sim("camera_poses.txt") + ":0' --pose2 '" +
                                     dir_->file("odometry2b.txt") + "' --out '" + dir_->file("refined_b.txt") +
                                     "' --matches '" + dir_->file("matches_b.txt") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::size_t at = r.out.find("| inliers' range along camera 1's rays");
    ASSERT_NE(at, std::string::npos) << r.out;
    double reported[5] = {};
    ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find(") | ", at) + 4, "%lf / %lf / %lf / %lf / %lf", &reported[0],
                          &reported[1], &reported[2], &reported[3], &reported[4]),
              5)
        << r.out.substr(at, 200);
    // True range at the inliers' pixels in image 1 (nearest pixel; (0,0) is the centre of the
    // top-left pixel in both files).
    std::ifstream matches(dir_->file("matches_b.txt"));
    std::vector<double> truth;
    std::string line;
    while (std::getline(matches, line)) {
        double x1, y1, x2, y2, ncc;
        int inlier = 0;
        if (line.empty() || line[0] == '#' ||
            std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %d", &x1, &y1, &x2, &y2, &ncc, &inlier) != 6 || inlier != 1) {
            continue;
        }
        const float t = range.value.at(static_cast<int>(std::lround(x1)), static_cast<int>(std::lround(y1)));
        if (std::isfinite(t)) truth.push_back(t);
    }
    ASSERT_GE(truth.size(), 12U);
    std::sort(truth.begin(), truth.end());
    const auto pct = [&truth](double q) {
        return truth[static_cast<std::size_t>(q * static_cast<double>(truth.size() - 1U) + 0.5)];
    };
    std::printf("inliers' range, reported / true: 10th %.2f / %.2f m, median %.2f / %.2f m, 90th %.2f / %.2f m\n",
                reported[1], pct(0.1), reported[2], pct(0.5), reported[3], pct(0.9));
    // Allowed: 5 % plus the range error of half a pixel of disparity at that range
    // (z^2 * 0.5 px / (fx * baseline)): a 2 m baseline resolves 200 m points to about 8 %.
    CameraModel cam{};
    ASSERT_TRUE(readCameraModelFile(sim("mast.cmod"), cam).ok);
    const double baseline_m = (siteFromCam(p2.value).t_m - siteFromCam(p1.value).t_m).norm();
    const auto tolerance = [&](double z) { return 0.05 * z + z * z * 0.5 / (cam.fx_px * baseline_m); };
    const std::pair<int, double> columns[] = {{1, 0.1}, {2, 0.5}, {3, 0.9}};  // report column, percentile
    for (const auto& [k, q] : columns) {
        EXPECT_NEAR(reported[k], pct(q), tolerance(pct(q))) << "percentile " << q;
    }
    EXPECT_LE(reported[0], reported[1]);
    EXPECT_LE(reported[3], reported[4]);
}

TEST_F(WideBaselineCli, RectifyWritesAPairWhoseTrueCorrespondencesShareTheirRows) {
    const CommandRun r = runTool(*dir_, VTM_EXECUTABLE,
                                 "rectify '" + sim("mast_000.png") + "' '" + sim("mast_001.png") + "' --camera '" +
                                     sim("mast.cmod") + "' --pose1 '" + sim("camera_poses.txt") + ":0' --pose2 '" +
                                     sim("camera_poses.txt") + ":1' --range 1:100000 --out-dir '" + dir_->file("rect") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto img1 = loadGrey8(dir_->file("rect/rectified1.png"));
    auto img2 = loadGrey8(dir_->file("rect/rectified2.png"));
    ASSERT_TRUE(img1.ok && img2.ok) << img1.error << img2.error;
    CameraModel m1{};
    CameraModel m2{};
    ASSERT_TRUE(readCameraModelFile(dir_->file("rect/rectified1.cmod"), m1).ok);
    ASSERT_TRUE(readCameraModelFile(dir_->file("rect/rectified2.cmod"), m2).ok);
    auto r1 = readCameraPoseSpec(dir_->file("rect/rectified_poses.txt:0"));
    auto r2 = readCameraPoseSpec(dir_->file("rect/rectified_poses.txt:1"));
    ASSERT_TRUE(r1.ok && r2.ok);
    // True 3-D points (from the renderer's depth of image 1) land on the same row of both
    // rectified images, and their disparity lies in the reported range.
    auto p1 = readCameraPoseSpec(sim("camera_poses.txt:0"));
    auto depth = readPfm(sim("mast_000_depth.pfm"));
    CameraModel raw{};
    ASSERT_TRUE(p1.ok && depth.ok && readCameraModelFile(sim("mast.cmod"), raw).ok);
    const std::string report = slurp(dir_->file("rect/report.md"));
    int d_min = 0, d_max = 0;
    const std::size_t at = report.find("| disparity range");
    ASSERT_NE(at, std::string::npos) << report;
    ASSERT_EQ(std::sscanf(report.c_str() + report.find("| ", at + 3) + 2, "%d:%d", &d_min, &d_max), 2) << report;
    const RigidPose site_from_cam1 = siteFromCam(p1.value);
    const RigidPose site_from_rect1 = siteFromCam(r1.value);
    const RigidPose site_from_rect2 = siteFromCam(r2.value);
    double sum2 = 0.0;
    int n = 0;
    int in_range = 0;
    for (int y = 20; y < raw.height_px; y += 20) {
        for (int x = 20; x < raw.width_px; x += 20) {
            const float z = depth.value.at(x, y);
            if (!std::isfinite(z)) continue;
            CameraRay ray;
            ASSERT_TRUE(backProjectPixel(raw, Vec2(x, y), ray).isOk());
            const Vec3 p_site =
                transformPoint(site_from_cam1, ray.origin_m + ray.direction * (static_cast<double>(z) / ray.direction.z()));
            Vec2 a, b;
            const Vec3 pa = site_from_rect1.R.transpose() * (p_site - site_from_rect1.t_m);
            const Vec3 pb = site_from_rect2.R.transpose() * (p_site - site_from_rect2.t_m);
            if (!projectPoint(m1, pa, a).isOk() || !projectPoint(m2, pb, b).isOk()) continue;
            sum2 += (a.y() - b.y()) * (a.y() - b.y());
            ++n;
            const double d = a.x() - b.x();
            in_range += (d >= d_min && d <= d_max) ? 1 : 0;
        }
    }
    ASSERT_GT(n, 100);
    EXPECT_LT(std::sqrt(sum2 / n), 1e-6) << "vertical disparity of true points, px";
    EXPECT_EQ(in_range, n) << "disparities outside the reported range " << d_min << ":" << d_max;
}

TEST_F(WideBaselineCli, BadInputsExitNonZeroWithOneLineNamingTheInput) {
    const std::string pair = "'" + sim("mast_000.png") + "' '" + sim("mast_001.png") + "' ";
    const std::string cam = "--camera '" + sim("mast.cmod") + "' ";
    const std::string poses = "--pose1 '" + sim("camera_poses.txt") + ":0' --pose2 '" + sim("camera_poses.txt") + ":1' ";
    struct Case {
        std::string args;
        int code;
        std::string says;
    };
    const Case cases[] = {
        {"refine " + pair + cam + poses + "--range 5:1 --out x.txt", 2, "--range '5:1'"},
        {"refine " + pair + cam + poses + "--max-rotation-sigma 0.001 --out x.txt", 2, "--max-rotation-sigma"},
        {"refine " + pair + cam + "--pose1 '" + sim("camera_poses.txt") + ":9' --pose2 '" + sim("camera_poses.txt") +
             ":1' --out x.txt",
         1, "no pose with frame index 9"},
        {"rectify " + pair + "--camera '" + dir_->file("missing.cmod") + "' " + poses + "--out-dir o", 1, "missing.cmod"},
        {"rectify " + pair + cam + "--pose1 '" + sim("camera_poses.txt") + ":0' --pose2 '" + sim("camera_poses.txt") +
             ":0' --out-dir o",
         1, "no baseline"},
        {"refine '" + sim("mast_000_depth.pfm") + "' '" + sim("mast_001.png") + "' " + cam + poses + "--out x.txt", 1,
         "mast_000_depth.pfm"},
    };
    for (const Case& c : cases) {
        const CommandRun r = runTool(*dir_, VTM_EXECUTABLE, c.args);
        EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
}

}  // namespace
}  // namespace vtm::ground
