// vtm/core/image_network.hpp: the eyes of a station are placed as the calibration says,
// and a malformed station is refused with the field named.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "vtm/core/image_network.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm {
namespace {

NetworkStation navcamLikeStation() {
    NetworkStation s;
    s.rig.model_a = makePinhole(1024U, 1024U, 45.0);
    s.rig.model_b = s.rig.model_a;
    s.rig.b_from_a.t_m = Vec3(-0.42, 0.0, 0.0);  // right eye 0.42 m to the left eye's +x
    s.site_from_a.R = rotationExp(Vec3(0.3, -0.2, 1.1));
    s.site_from_a.t_m = Vec3(2.0, -1.0, -1.5);
    s.prior_covariance.diagonal() << 1e-6, 1e-6, 4e-6, 1e-4, 1e-4, 1e-4;
    return s;
}

TEST(ImageNetwork, TheRightEyeSeesAPointWhereTheCalibratedRigSaysItDoes) {
    const NetworkStation s = navcamLikeStation();
    const Vec3 x_site(9.0, 4.0, 0.5);
    const RigidPose site_from_b = siteFromEye(s, Eye::kRight);
    // By hand: into the left eye, then through the calibration; against: straight into B.
    const Vec3 x_a = s.site_from_a.R.transpose() * (x_site - s.site_from_a.t_m);
    const Vec3 x_b_by_rig = transformPoint(s.rig.b_from_a, x_a);
    const Vec3 x_b_direct = site_from_b.R.transpose() * (x_site - site_from_b.t_m);
    EXPECT_LT((x_b_by_rig - x_b_direct).norm(), 1e-13);
    // The right eye's centre is 0.42 m along the left eye's +x axis.
    EXPECT_LT((site_from_b.t_m - (s.site_from_a.t_m + 0.42 * s.site_from_a.R.col(0))).norm(), 1e-14);
    EXPECT_EQ(&modelOfEye(s, Eye::kRight), &s.rig.model_b);
    EXPECT_EQ(std::memcmp(siteFromEye(s, Eye::kLeft).R.data(), s.site_from_a.R.data(), sizeof(double) * 9U), 0);
}

TEST(ImageNetwork, ValidationNamesTheBadField) {
    EXPECT_TRUE(validateNetworkStation(navcamLikeStation()).isOk());
    NetworkStation s = navcamLikeStation();
    s.rig.model_b.fx_px = -1.0;
    EXPECT_STREQ(validateNetworkStation(s).reason(), "network station: the right camera model is invalid");
    s = navcamLikeStation();
    s.site_from_a.R(0, 0) += 1e-3;
    EXPECT_STREQ(validateNetworkStation(s).reason(), "network station: site_from_a is not rigid");
    s = navcamLikeStation();
    s.prior_covariance(0, 4) = 1e-6;
    EXPECT_STREQ(validateNetworkStation(s).reason(), "network station: prior covariance is not symmetric");
    s = navcamLikeStation();
    s.prior_covariance(2, 2) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(validateNetworkStation(s).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vtm
