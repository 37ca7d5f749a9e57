// Where a camera sits on its vehicle, and its pose in the site frame from an odometry
// pose. Frames: site x north, y east, z down (metres); the camera's reference frame is
// the one its CameraModel projects from (pinhole: +z along the view, +x right, +y down).
#pragma once

#include "hal/odometry.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/status.hpp"

namespace vtm::app {

struct CameraMount {
    Mat3 R_vehicle_from_camera = Mat3::Identity();  // a rotation
    Vec3 position_vehicle_m = Vec3::Zero();         // camera centre in the vehicle frame
};

// kOk, or kInvalidConfig naming the field: R not a rotation within 1e-9, position not
// finite or farther than 100 m from the vehicle origin.
[[nodiscard]] Status validateMount(const CameraMount& mount) noexcept;

// T_site_from_camera = T_site_from_vehicle (the pose) * T_vehicle_from_camera (the mount).
// kCorruptData when the pose fails hal::validatePose (its reason).
[[nodiscard]] Status cameraPoseInSite(const hal::PoseEstimate& vehicle, const CameraMount& mount,
                                      Mat3& R_site_from_camera, Vec3& position_site_m) noexcept;

}  // namespace vtm::app
