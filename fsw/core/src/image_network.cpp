#include "vtm/core/image_network.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm {

RigidPose siteFromEye(const NetworkStation& station, Eye eye) noexcept {
    return eye == Eye::kLeft ? station.site_from_a : poseOfB(station.site_from_a, station.rig.b_from_a);
}

const CameraModel& modelOfEye(const NetworkStation& station, Eye eye) noexcept {
    return eye == Eye::kLeft ? station.rig.model_a : station.rig.model_b;
}

Status validateNetworkStation(const NetworkStation& station) noexcept {
    if (!validateCameraModel(station.rig.model_a).isOk()) {
        return Status(StatusCode::kInvalidArgument, "network station: the left camera model is invalid");
    }
    if (!validateCameraModel(station.rig.model_b).isOk()) {
        return Status(StatusCode::kInvalidArgument, "network station: the right camera model is invalid");
    }
    VTM_RETURN_IF_ERROR(checkRigidPose(station.rig.b_from_a, 1e-9, "network station: b_from_a is not rigid"));
    VTM_RETURN_IF_ERROR(checkRigidPose(station.site_from_a, 1e-9, "network station: site_from_a is not rigid"));
    const Mat6& c = station.prior_covariance;
    for (int r = 0; r < 6; ++r) {
        if (!math::isFinite(c(r, r)) || c(r, r) < 0.0) {
            return Status(StatusCode::kInvalidArgument, "network station: prior covariance has a negative or non-finite variance");
        }
        for (int k = 0; k < 6; ++k) {
            const double scale = std::fabs(c(r, k)) + std::fabs(c(k, r));
            if (!math::isFinite(c(r, k)) || std::fabs(c(r, k) - c(k, r)) > 1e-12 * scale) {
                return Status(StatusCode::kInvalidArgument, "network station: prior covariance is not symmetric");
            }
        }
    }
    return Status::ok();
}

}  // namespace vtm
