#include "vtm/core/pose.hpp"

#include "vtm/core/math.hpp"

namespace vtm {

Vec3 transformPoint(const RigidPose& to_from_from, const Vec3& x_from) noexcept {
    return to_from_from.R * x_from + to_from_from.t_m;
}

RigidPose relativePose(const RigidPose& site_from_a, const RigidPose& site_from_b) noexcept {
    RigidPose p;
    p.R = site_from_b.R.transpose() * site_from_a.R;
    p.t_m = site_from_b.R.transpose() * (site_from_a.t_m - site_from_b.t_m);
    return p;
}

RigidPose poseOfB(const RigidPose& site_from_a, const RigidPose& b_from_a) noexcept {
    RigidPose p;
    p.R = site_from_a.R * b_from_a.R.transpose();
    p.t_m = site_from_a.t_m - p.R * b_from_a.t_m;
    return p;
}

bool isRotation(const Mat3& R, double tolerance) noexcept {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            if (!math::isFinite(R(r, c))) {
                return false;
            }
        }
    }
    const Mat3 e = R.transpose() * R - Mat3::Identity();
    return e.cwiseAbs().maxCoeff() <= tolerance && R.determinant() > 0.0;
}

Status checkRigidPose(const RigidPose& pose, double tolerance, const char* reason) noexcept {
    const bool finite_t = math::isFinite(pose.t_m.x()) && math::isFinite(pose.t_m.y()) && math::isFinite(pose.t_m.z());
    if (!finite_t || !isRotation(pose.R, tolerance)) {
        return Status(StatusCode::kInvalidArgument, reason);
    }
    return Status::ok();
}

}  // namespace vtm
