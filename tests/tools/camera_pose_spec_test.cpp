// Camera poses named on the command line ("FILE" or "FILE:INDEX", docs/cli-poses.md): the
// right line is chosen, and every bad spec is refused with a message naming it.
#include <gtest/gtest.h>

#include <string>

#include "ground_test_files.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::ground {
namespace {

using test::TempDir;
using test::textBytes;
using test::writeBytes;

const char* kTwoPoses =
    "vtm-camera-poses 1\n"
    "0 mast 1000 1 2 -1.9 1 0 0 0\n"
    "7 mast 2000 4.5 -0.25 -2 0.70710678118654752 0 0 0.70710678118654752\n";

TEST(CameraPoseSpec, IndexPicksTheLineWithThatFrameIndex) {
    TempDir dir;
    const std::string path = dir.file("poses.txt");
    writeBytes(path, textBytes(kTwoPoses));
    auto p = readCameraPoseSpec(path + ":7");
    ASSERT_TRUE(p.ok) << p.error;
    EXPECT_EQ(p.value.frame_index, 7U);
    EXPECT_EQ(p.value.timestamp_ns, 2000U);
    EXPECT_DOUBLE_EQ(p.value.position_m[0], 4.5);
    EXPECT_DOUBLE_EQ(p.value.attitude_wxyz[3], 0.70710678118654752);
    p = readCameraPoseSpec(path + ":0");
    ASSERT_TRUE(p.ok) << p.error;
    EXPECT_DOUBLE_EQ(p.value.position_m[2], -1.9);
}

// The one conversion of the file record: the quaternion (cos 45, 0, 0, sin 45) turns the
// camera 90 degrees about the site's z axis (its x axis onto the site's y), the position is
// taken as it is; writing the pose back gives the same record.
TEST(CameraPoseRecord, SiteFromCamAndBack) {
    SimCameraPose p;
    p.position_m[0] = 4.5;
    p.position_m[1] = -0.25;
    p.position_m[2] = -2.0;
    p.attitude_wxyz[0] = 0.70710678118654752;
    p.attitude_wxyz[3] = 0.70710678118654752;
    const RigidPose site_from_cam = siteFromCam(p);
    EXPECT_NEAR((site_from_cam.R * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((site_from_cam.R * Vec3::UnitZ() - Vec3::UnitZ()).norm(), 0.0, 1e-15);
    EXPECT_EQ(site_from_cam.t_m, Vec3(4.5, -0.25, -2.0));

    SimCameraPose back;
    back.frame_index = 7U;
    back.camera = "mast";
    back.timestamp_ns = 2000U;
    setSiteFromCam(back, site_from_cam);
    EXPECT_EQ(back.frame_index, 7U);
    EXPECT_EQ(back.camera, "mast");
    EXPECT_EQ(back.timestamp_ns, 2000U);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(back.position_m[i], p.position_m[i]);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(back.attitude_wxyz[i], p.attitude_wxyz[i], 1e-15) << i;
}

TEST(CameraPoseSpec, APlainFileMustHoldExactlyOnePose) {
    TempDir dir;
    const std::string one = dir.file("one.txt");
    writeBytes(one, textBytes("vtm-camera-poses 1\n3 mast 5 0 0 0 1 0 0 0\n"));
    auto p = readCameraPoseSpec(one);
    ASSERT_TRUE(p.ok) << p.error;
    EXPECT_EQ(p.value.frame_index, 3U);
    const std::string two = dir.file("two.txt");
    writeBytes(two, textBytes(kTwoPoses));
    p = readCameraPoseSpec(two);
    ASSERT_FALSE(p.ok);
    EXPECT_NE(p.error.find("holds 2 poses"), std::string::npos) << p.error;
}

TEST(CameraPoseSpec, BadSpecsAreRefusedNamingTheProblem) {
    TempDir dir;
    const std::string path = dir.file("poses.txt");
    writeBytes(path, textBytes(kTwoPoses));
    auto p = readCameraPoseSpec(path + ":5");
    ASSERT_FALSE(p.ok);
    EXPECT_NE(p.error.find("no pose with frame index 5"), std::string::npos) << p.error;
    p = readCameraPoseSpec(dir.file("missing.txt"));
    ASSERT_FALSE(p.ok);
    EXPECT_NE(p.error.find("missing.txt"), std::string::npos) << p.error;
    const std::string bad_q = dir.file("q.txt");
    writeBytes(bad_q, textBytes("vtm-camera-poses 1\n0 mast 5 0 0 0 1 1 0 0\n"));
    p = readCameraPoseSpec(bad_q);
    ASSERT_FALSE(p.ok);
    EXPECT_NE(p.error.find("unit quaternion"), std::string::npos) << p.error;
    const std::string nan_p = dir.file("p.txt");
    writeBytes(nan_p, textBytes("vtm-camera-poses 1\n0 mast 5 nan 0 0 1 0 0 0\n"));
    p = readCameraPoseSpec(nan_p);
    ASSERT_FALSE(p.ok);
    EXPECT_NE(p.error.find("p.txt: line 2"), std::string::npos) << p.error;
}

}  // namespace
}  // namespace vtm::ground
