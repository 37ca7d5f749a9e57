// vtm/core/pose.hpp: the rigid-pose conventions every module relies on, checked against
// points moved through the frames by hand.
#include <gtest/gtest.h>

#include <limits>

#include "no_heap_guard.hpp"
#include "vtm/core/pose.hpp"

namespace vtm {
namespace {

Mat3 rotation(double ax, double ay, double az) {
    return (Eigen::AngleAxisd(az, Vec3::UnitZ()) * Eigen::AngleAxisd(ay, Vec3::UnitY()) *
            Eigen::AngleAxisd(ax, Vec3::UnitX()))
        .toRotationMatrix();
}

RigidPose pose(double ax, double ay, double az, const Vec3& t) {
    RigidPose p;
    p.R = rotation(ax, ay, az);
    p.t_m = t;
    return p;
}

TEST(RigidPose, TranslationIsTheOriginOfTheSourceFrame) {
    const RigidPose site_from_cam = pose(0.1, -0.2, 0.7, Vec3(3.0, -4.0, -1.5));
    const Vec3 centre = transformPoint(site_from_cam, Vec3::Zero());
    EXPECT_LT((centre - Vec3(3.0, -4.0, -1.5)).norm(), 1e-15);
    // A point 2 m along the camera's +z lies 2 m along the third column of R.
    const Vec3 ahead = transformPoint(site_from_cam, Vec3(0.0, 0.0, 2.0));
    EXPECT_LT((ahead - centre - 2.0 * site_from_cam.R.col(2)).norm(), 1e-14);
}

TEST(RigidPose, RelativePoseMapsAPointSeenByAIntoB) {
    const RigidPose site_from_a = pose(0.05, 0.3, -0.4, Vec3(1.0, 2.0, -1.8));
    const RigidPose site_from_b = pose(-0.02, 0.25, 0.2, Vec3(-3.0, 6.5, -1.7));
    const RigidPose b_from_a = relativePose(site_from_a, site_from_b);
    const Vec3 x_site(25.0, -7.0, 0.4);
    // By hand: into A, then the relative pose; against: straight into B.
    const Vec3 x_a = site_from_a.R.transpose() * (x_site - site_from_a.t_m);
    const Vec3 x_b = site_from_b.R.transpose() * (x_site - site_from_b.t_m);
    EXPECT_LT((transformPoint(b_from_a, x_a) - x_b).norm(), 1e-12);
    EXPECT_TRUE(isRotation(b_from_a.R, 1e-12));
}

TEST(RigidPose, PoseOfBInvertsRelativePose) {
    const RigidPose site_from_a = pose(0.3, -0.1, 2.0, Vec3(10.0, -2.0, -1.9));
    const RigidPose site_from_b = pose(0.28, -0.05, 1.7, Vec3(12.0, 3.0, -1.85));
    const RigidPose back = poseOfB(site_from_a, relativePose(site_from_a, site_from_b));
    EXPECT_LT((back.R - site_from_b.R).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((back.t_m - site_from_b.t_m).norm(), 1e-13);
}

TEST(RigidPose, IsRotationRejectsReflectionsScaleAndNaN) {
    EXPECT_TRUE(isRotation(rotation(0.4, 0.5, 0.6), 1e-12));
    Mat3 mirror = Mat3::Identity();
    mirror(0, 0) = -1.0;
    EXPECT_FALSE(isRotation(mirror, 1e-6));
    EXPECT_FALSE(isRotation(1.001 * Mat3::Identity(), 1e-6));
    EXPECT_TRUE(isRotation(1.0000001 * Mat3::Identity(), 1e-6));
    Mat3 nan = Mat3::Identity();
    nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(isRotation(nan, 1e-6));
}

TEST(RigidPose, CheckNamesTheFieldAndRejectsNonFiniteTranslation) {
    RigidPose p = pose(0.0, 0.0, 0.1, Vec3(1.0, 0.0, 0.0));
    EXPECT_TRUE(checkRigidPose(p, 1e-9, "pose: bad").isOk());
    p.t_m.y() = std::numeric_limits<double>::infinity();
    const Status s = checkRigidPose(p, 1e-9, "prior.b_from_a: not a rigid pose");
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_STREQ(s.reason(), "prior.b_from_a: not a rigid pose");
}

TEST(RigidPose, OperationsTouchNoHeap) {
    const RigidPose a = pose(0.1, 0.2, 0.3, Vec3(1.0, 2.0, 3.0));
    const RigidPose b = pose(0.2, 0.1, 0.0, Vec3(0.0, 1.0, 0.0));
    test::NoHeapScope guard;
    const RigidPose r = poseOfB(a, relativePose(a, b));
    EXPECT_TRUE(isRotation(r.R, 1e-9));
    EXPECT_EQ(guard.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm
