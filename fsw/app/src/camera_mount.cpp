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

Status cameraPoseInSite(const hal::PoseEstimate& vehicle, const CameraMount& mount, Mat3& R_site_from_camera,
                        Vec3& position_site_m) noexcept {
    VTM_RETURN_IF_ERROR(hal::validatePose(vehicle));
    const Quat q(vehicle.attitude_wxyz[0], vehicle.attitude_wxyz[1], vehicle.attitude_wxyz[2],
                 vehicle.attitude_wxyz[3]);
    const Mat3 R_site_from_vehicle = q.normalized().toRotationMatrix();
    const Vec3 t(vehicle.position_m[0], vehicle.position_m[1], vehicle.position_m[2]);
    R_site_from_camera = R_site_from_vehicle * mount.R_vehicle_from_camera;
    position_site_m = R_site_from_vehicle * mount.position_vehicle_m + t;
    return Status::ok();
}

}  // namespace vtm::app
