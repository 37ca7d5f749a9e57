// app::cameraPoseInSite: the camera's site_from_camera from the vehicle's pose (through
// hal::siteFromVehicle) and the camera mount, checked against a pose worked out by hand.
#include <gtest/gtest.h>

#include <limits>

#include "vtm/app/camera_mount.hpp"

namespace vtm::app {
namespace {

// The vehicle at (10, -4, -2) facing east: a 90 degree turn about the site's z (down) axis,
// so vehicle x -> site y, vehicle y -> site -x, vehicle z -> site z.
hal::PoseEstimate vehicleFacingEast() {
    hal::PoseEstimate v;
    v.position_m[0] = 10.0;
    v.position_m[1] = -4.0;
    v.position_m[2] = -2.0;
    v.attitude_wxyz[0] = 0.70710678118654752;
    v.attitude_wxyz[3] = 0.70710678118654752;
    return v;
}

// A camera 0.5 m ahead of the vehicle origin and 1.5 m above it, looking forward: its
// +z (view) along vehicle x, +x (image right) along vehicle y, +y (image down) along z.
CameraMount forwardCamera() {
    CameraMount m;
    m.R_vehicle_from_camera << 0.0, 0.0, 1.0,  //
        1.0, 0.0, 0.0,                         //
        0.0, 1.0, 0.0;
    m.position_vehicle_m = Vec3(0.5, 0.0, -1.5);
    return m;
}

TEST(CameraPoseInSite, ComposesTheVehiclePoseAndTheMount) {
    ASSERT_TRUE(validateMount(forwardCamera()).isOk());
    RigidPose site_from_camera;
    ASSERT_TRUE(cameraPoseInSite(vehicleFacingEast(), forwardCamera(), site_from_camera).isOk());
    // By hand: centre (10, -4, -2) + (0, 0.5, -1.5); the view along site y (east), image
    // right along site -x (south), image down along site z.
    EXPECT_NEAR((site_from_camera.t_m - Vec3(10.0, -3.5, -3.5)).norm(), 0.0, 1e-14);
    EXPECT_NEAR((site_from_camera.R * Vec3::UnitZ() - Vec3::UnitY()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((site_from_camera.R * Vec3::UnitX() + Vec3::UnitX()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((site_from_camera.R * Vec3::UnitY() - Vec3::UnitZ()).norm(), 0.0, 1e-15);
    // A point 2 m in front of the camera is 2 m east of it.
    EXPECT_NEAR((transformPoint(site_from_camera, Vec3(0.0, 0.0, 2.0)) - Vec3(10.0, -1.5, -3.5)).norm(), 0.0,
                1e-14);
}

TEST(CameraPoseInSite, RefusesAnInvalidVehiclePoseAndLeavesThePoseAlone) {
    hal::PoseEstimate v = vehicleFacingEast();
    v.attitude_wxyz[2] = std::numeric_limits<double>::quiet_NaN();
    RigidPose site_from_camera;
    site_from_camera.t_m = Vec3(7.0, 7.0, 7.0);
    const Status s = cameraPoseInSite(v, forwardCamera(), site_from_camera);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_STREQ(s.reason(), "pose: attitude_wxyz is not finite");
    EXPECT_EQ(site_from_camera.t_m, Vec3(7.0, 7.0, 7.0));
    EXPECT_EQ(site_from_camera.R, Mat3::Identity());
}

}  // namespace
}  // namespace vtm::app
