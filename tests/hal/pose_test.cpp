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
