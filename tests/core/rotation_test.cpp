// vtm/core/rotation.hpp against Eigen's angle-axis as the peer.
#include <gtest/gtest.h>

#include "no_heap_guard.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm {
namespace {

Mat3 angleAxis(const Vec3& w) {
    return w.norm() == 0.0 ? Mat3::Identity() : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
}

TEST(Rotation, SkewIsTheCrossProduct) {
    const Vec3 w(0.3, -1.2, 2.5);
    const Vec3 v(-4.0, 0.5, 1.0);
    EXPECT_LT((skew(w) * v - w.cross(v)).norm(), 1e-15);
}

TEST(Rotation, ExpAgreesWithAngleAxisFromTinyToLargeAngles) {
    for (const Vec3& w : {Vec3(1e-10, -2e-10, 3e-10), Vec3(1e-5, 0.0, -2e-5), Vec3(0.2, -0.4, 0.1),
                          Vec3(Vec3(-1.0, 2.0, 0.5).normalized() * 3.0)}) {
        EXPECT_LT((rotationExp(w) - angleAxis(w)).cwiseAbs().maxCoeff(), 2e-15) << w.transpose();
    }
}

TEST(Rotation, LogInvertsExpAndAngleMeasuresTheRelativeRotation) {
    test::NoHeapScope guard;
    for (const Vec3& w : {Vec3(1e-10, -2e-10, 3e-10), Vec3(1e-5, 0.0, -2e-5), Vec3(0.2, -0.4, 0.1),
                          Vec3(Vec3(-1.0, 2.0, 0.5).normalized() * 3.0)}) {
        EXPECT_LT((rotationLog(rotationExp(w)) - w).norm(), 1e-15 + 1e-12 * w.norm()) << w.transpose();
        const Mat3 r0 = angleAxis(Vec3(0.4, 0.1, -0.3));
        EXPECT_NEAR(rotationAngleRad(r0, rotationExp(w) * r0), w.norm(), 1e-14 + 1e-12 * w.norm());
    }
    EXPECT_EQ(rotationLog(Mat3::Identity()), Vec3::Zero());
    EXPECT_EQ(guard.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm
