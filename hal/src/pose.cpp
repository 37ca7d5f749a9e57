#include <cmath>

#include "hal/odometry.hpp"
#include "vtm/core/eigen.hpp"

namespace vtm::hal {

Status validatePose(const PoseEstimate& pose) noexcept {
    for (const double p : pose.position_m) {
        if (!std::isfinite(p)) {
            return Status(StatusCode::kCorruptData, "pose: position_m is not finite");
        }
    }
    double norm2 = 0.0;
    for (const double q : pose.attitude_wxyz) {
        if (!std::isfinite(q)) {
            return Status(StatusCode::kCorruptData, "pose: attitude_wxyz is not finite");
        }
        norm2 += q * q;
    }
    // |q|^2 within 2e-6 of 1 <=> |q| within about 1e-6 of 1.
    if (norm2 < 1.0 - 2e-6 || norm2 > 1.0 + 2e-6) {
        return Status(StatusCode::kCorruptData, "pose: attitude_wxyz is not a unit quaternion");
    }
    for (std::size_t i = 0U; i < 36U; ++i) {
        if (!std::isfinite(pose.covariance[i])) {
            return Status(StatusCode::kCorruptData, "pose: covariance is not finite",
                          static_cast<std::int64_t>(i));
        }
    }
    for (std::size_t i = 0U; i < 6U; ++i) {
        if (pose.covariance[i * 7U] < 0.0) {
            return Status(StatusCode::kCorruptData, "pose: covariance diagonal is negative",
                          static_cast<std::int64_t>(i));
        }
    }
    return Status::ok();
}

RigidPose siteFromVehicle(const PoseEstimate& pose) noexcept {
    const Quat q(pose.attitude_wxyz[0], pose.attitude_wxyz[1], pose.attitude_wxyz[2], pose.attitude_wxyz[3]);
    RigidPose site_from_vehicle;
    site_from_vehicle.R = q.normalized().toRotationMatrix();
    site_from_vehicle.t_m = Vec3(pose.position_m[0], pose.position_m[1], pose.position_m[2]);
    return site_from_vehicle;
}

}  // namespace vtm::hal
