// Geometry shared by the sweep and the depth-to-height-map step (internal to fsw/descent).
#pragma once

#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent::detail {

// kOk for an undistorted pinhole, else kUnsupported naming the camera.
[[nodiscard]] Status checkPinhole(const CameraModel& camera) noexcept;
// kOk for a finite pose whose rotation is orthonormal (within 1e-6) and proper;
// kInvalidArgument with `reason` otherwise (vtm::checkRigidPose).
[[nodiscard]] Status checkPose(const RigidPose& pose, const char* reason) noexcept;
// K and K^-1 of an undistorted pinhole.
[[nodiscard]] Mat3 intrinsics(const CameraModel& camera) noexcept;
[[nodiscard]] Mat3 inverseIntrinsics(const CameraModel& camera) noexcept;

// Image-2 position of image-1 pixel (x, y) under the row-major homography h[9]. false
// when the point maps to or behind camera 2's principal plane (w <= 0).
[[nodiscard]] inline bool mapPixel(const double* h, double x, double y, double& u, double& v) noexcept {
    // Same operation order as the sweep's row loop (row terms first): same bits.
    const double X = h[0] * x + (h[1] * y + h[2]);
    const double Y = h[3] * x + (h[4] * y + h[5]);
    const double W = h[6] * x + (h[7] * y + h[8]);
    if (!(W > 0.0)) {
        return false;
    }
    const double inv = 1.0 / W;
    u = X * inv;
    v = Y * inv;
    return true;
}

}  // namespace vtm::descent::detail
