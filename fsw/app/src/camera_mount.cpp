#include "vtm/app/camera_mount.hpp"

#include "vtm/core/math.hpp"

namespace vtm::app {
namespace {

bool finite(const Vec3& v) noexcept {
    return math::isFinite(v.x()) && math::isFinite(v.y()) && math::isFinite(v.z());
}

}  // namespace

Status validateMount(const CameraMount& mount) noexcept {
    const Mat3& R = mount.R_vehicle_from_camera;
    for (int c = 0; c < 3; ++c) {
        if (!finite(R.col(c))) {
            return Status(StatusCode::kInvalidConfig, "mount.R_vehicle_from_camera: not finite");
        }
    }
    const double orthogonality = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
    if (!(orthogonality <= 1e-9) || !(R.determinant() > 0.0)) {
        return Status(StatusCode::kInvalidConfig, "mount.R_vehicle_from_camera: not a rotation (within 1e-9)");
    }
    if (!finite(mount.position_vehicle_m) || !(mount.position_vehicle_m.norm() <= 100.0)) {
        return Status(StatusCode::kInvalidConfig, "mount.position_vehicle_m: must be finite, within 100 m");
    }
    return Status::ok();
}

Status cameraPoseInSite(const hal::PoseEstimate& vehicle, const CameraMount& mount,
                        RigidPose& site_from_camera) noexcept {
    VTM_RETURN_IF_ERROR(hal::validatePose(vehicle));
    const RigidPose site_from_vehicle = hal::siteFromVehicle(vehicle);
    site_from_camera.R = site_from_vehicle.R * mount.R_vehicle_from_camera;
    site_from_camera.t_m = site_from_vehicle.R * mount.position_vehicle_m + site_from_vehicle.t_m;
    return Status::ok();
}

}  // namespace vtm::app
