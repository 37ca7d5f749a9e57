// Reduction of a camera model (vtm/core/camera_model.hpp) to a linear camera, the input
// of Fusiello's rectification. The non-linear part (Brown distortion, CAHVOR's O and R)
// is not lost: the rectifier's remap tables go through the FULL model, so it is removed
// when the images are resampled. docs/rectify.md.
#pragma once

#include <cstdint>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/status.hpp"

namespace vtm::rectify {

// A linear (undistorted pinhole) camera in the model's reference frame:
//   pixel ~ K (R_cam_from_ref (X_ref - centre_ref_m)),  K upper triangular, K(2,2) = 1,
// K(0,0) = fx > 0, K(1,1) = fy > 0, K(0,1) = skew (CAHV only; 0 for a pinhole).
struct LinearCamera {
    Mat3 K = Mat3::Identity();
    Mat3 R_cam_from_ref = Mat3::Identity();
    Vec3 centre_ref_m = Vec3::Zero();
    std::int32_t width_px = 0, height_px = 0;
};

// kPinholeBrown -> K = [fx 0 cx; 0 fy cy; 0 0 1], R = I, centre 0 (distortion dropped).
// kCahv -> the exact Yakimovsky-Cunningham decomposition of [H; V; A] / |A| = K R:
//   R's rows (r1, r2, A^), A^ = A/|A|, r2 = (V - vc A^)/vs, r1 = r2 x A^;
//   vc = V.A^, vs = |V - vc A^|, hc = H.A^, hs = H.r1, skew = H.r2; centre = C.
//   A model with H.r1 <= 0 images a mirror world (H x V against A): kInvalidArgument.
// kCahvor -> the decomposition of its CAHV part (JPL's practice; O and R are removed by
// the remap).
// kInvalidArgument when validateCameraModel() rejects the model (its reason); `out` is
// written only on success.
[[nodiscard]] Status linearizeCamera(const CameraModel& model, LinearCamera& out) noexcept;

}  // namespace vtm::rectify
