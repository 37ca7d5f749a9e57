#include <gtest/gtest.h>

#include <limits>

#include "hal/odometry.hpp"

namespace vtm::hal {
namespace {

PoseEstimate goodPose() {
    PoseEstimate p;
    p.position_m[0] = 3.0;
    p.attitude_wxyz[0] = 0.6;
    p.attitude_wxyz[3] = 0.8;
    for (int i = 0; i < 6; ++i) {
        p.covariance[i * 7] = 0.01;
    }
    return p;
}

TEST(ValidatePose, AcceptsAFinitePoseWithUnitQuaternion) { EXPECT_TRUE(validatePose(goodPose()).isOk()); }

TEST(ValidatePose, RejectsNaNAnywhere) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    PoseEstimate p = goodPose();
    p.position_m[1] = nan;
    EXPECT_EQ(validatePose(p).code(), StatusCode::kCorruptData);
    EXPECT_STREQ(validatePose(p).reason(), "pose: position_m is not finite");
    p = goodPose();
    p.attitude_wxyz[2] = nan;
    EXPECT_EQ(validatePose(p).code(), StatusCode::kCorruptData);
    p = goodPose();
    p.covariance[13] = std::numeric_limits<double>::infinity();
    EXPECT_EQ(validatePose(p).detail(), 13);
}

// goodPose's attitude (0.6, 0, 0, 0.8) is a turn about the site's z axis; by hand its
// matrix is [[1 - 2 z^2, -2 w z, 0], [2 w z, 1 - 2 z^2, 0], [0, 0, 1]], so the vehicle's x
// axis goes to (-0.28, 0.96, 0) in the site frame.
TEST(SiteFromVehicle, RotatesAsTheQuaternionAndKeepsThePosition) {
    const RigidPose site_from_vehicle = siteFromVehicle(goodPose());
    EXPECT_TRUE(isRotation(site_from_vehicle.R, 1e-12));
    const Vec3 x = site_from_vehicle.R * Vec3::UnitX();
    EXPECT_NEAR(x.x(), -0.28, 1e-15);
    EXPECT_NEAR(x.y(), 0.96, 1e-15);
    EXPECT_NEAR(x.z(), 0.0, 1e-15);
    EXPECT_NEAR((site_from_vehicle.R * Vec3::UnitZ() - Vec3::UnitZ()).norm(), 0.0, 1e-15);
    EXPECT_EQ(site_from_vehicle.t_m, Vec3(3.0, 0.0, 0.0));
}

TEST(SiteFromVehicle, NormalisesAQuaternionThatPassedValidation) {
    PoseEstimate p = goodPose();
    p.attitude_wxyz[0] *= 1.0 + 8e-7;  // |q|^2 within validatePose's 2e-6
    p.attitude_wxyz[3] *= 1.0 + 8e-7;
    ASSERT_TRUE(validatePose(p).isOk());
    const RigidPose site_from_vehicle = siteFromVehicle(p);
    EXPECT_TRUE(isRotation(site_from_vehicle.R, 1e-12));
    EXPECT_NEAR((site_from_vehicle.R - siteFromVehicle(goodPose()).R).norm(), 0.0, 1e-12);
}

TEST(ValidatePose, RejectsNonUnitQuaternionAndNegativeVariance) {
    PoseEstimate p = goodPose();
    p.attitude_wxyz[0] = 0.61;
    EXPECT_STREQ(validatePose(p).reason(), "pose: attitude_wxyz is not a unit quaternion");
    p = goodPose();
    p.covariance[2 * 7] = -1e-9;
    EXPECT_EQ(validatePose(p).code(), StatusCode::kCorruptData);
    EXPECT_EQ(validatePose(p).detail(), 2);
}

}  // namespace
}  // namespace vtm::hal
