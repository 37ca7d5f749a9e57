// The shared geometric vocabulary of every module: one rigid pose and one camera pair
// (docs/core.md "Poses, frames and the camera pair"). Conventions, stated once:
//   - A RigidPose maps coordinates of one frame into another and is named by the two
//     frames, "to_from_from": X_to = R * X_from + t_m. So site_from_cam.t_m is the
//     camera's reference point (the origin of its CameraModel's frame) in the site frame,
//     and b_from_a maps camera A's reference frame into camera B's.
//   - Site frame: x north, y east, z down, metres (a local level frame at the site origin).
//   - A camera's reference frame is the one its CameraModel projects from (pinhole: +z
//     along the view, +x image right, +y image down; CAHV(OR): the frame of C, A, H, V).
//   - A CameraPair is two models and b_from_a: everything a two-view module needs to
//     predict, refine, rectify or triangulate, with no site frame in it.
#pragma once

#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

struct RigidPose {
    Mat3 R = Mat3::Identity();  // a rotation
    Vec3 t_m = Vec3::Zero();
};

struct CameraPair {
    CameraModel model_a{};
    CameraModel model_b{};
    RigidPose b_from_a{};  // X_b = R X_a + t_m
};

// X_to for X_from: R X + t.
[[nodiscard]] Vec3 transformPoint(const RigidPose& to_from_from, const Vec3& x_from) noexcept;

// b_from_a of two cameras known in one frame: R = R_b^T R_a, t = R_b^T (t_a - t_b).
[[nodiscard]] RigidPose relativePose(const RigidPose& site_from_a, const RigidPose& site_from_b) noexcept;

// site_from_b of camera B from camera A's pose and b_from_a (the inverse of relativePose):
// R_b = R_a R^T, t_b = t_a - R_b t.
[[nodiscard]] RigidPose poseOfB(const RigidPose& site_from_a, const RigidPose& b_from_a) noexcept;

// True when R is a rotation: finite, |R^T R - I| <= tolerance in every element, det > 0.
[[nodiscard]] bool isRotation(const Mat3& R, double tolerance) noexcept;

// kOk, or kInvalidArgument with `reason` (a static string naming the caller's field)
// when R is not a rotation within `tolerance` or t_m is not finite.
[[nodiscard]] Status checkRigidPose(const RigidPose& pose, double tolerance, const char* reason) noexcept;

}  // namespace vtm
