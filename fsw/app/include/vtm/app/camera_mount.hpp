// Where a camera sits on its vehicle, and its pose in the site frame from an odometry
// pose. Frames: site x north, y east, z down (metres); the camera's reference frame is
// the one its CameraModel projects from (pinhole: +z along the view, +x right, +y down).
#pragma once

#include "hal/odometry.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"

namespace vtm::app {

struct CameraMount {
    Mat3 R_vehicle_from_camera = Mat3::Identity();  // a rotation
    Vec3 position_vehicle_m = Vec3::Zero();         // camera centre in the vehicle frame
};

// kOk, or kInvalidConfig naming the field: R not a rotation within 1e-9, position not
// finite or farther than 100 m from the vehicle origin.
[[nodiscard]] Status validateMount(const CameraMount& mount) noexcept;

// site_from_camera = site_from_vehicle (the pose, hal::siteFromVehicle) * vehicle_from_camera
// (the mount): R = R_sv R_vc, t_m = R_sv p_vc + t_sv. kCorruptData when the pose fails
// hal::validatePose (its reason); site_from_camera is then left as it was.
[[nodiscard]] Status cameraPoseInSite(const hal::PoseEstimate& vehicle, const CameraMount& mount,
                                      RigidPose& site_from_camera) noexcept;

}  // namespace vtm::app
