// The panorama's image network (paper §3; docs/core.md "The image network"): the
// vocabulary shared by the simulator's panorama, the tie points (fsw/tiepoints) and the
// bundle adjustment (fsw/bundle).
//  - A station is one exposure of the stereo rig: a CameraPair (model_a = left eye,
//    model_b = right eye, b_from_a fixed by calibration) and the left camera's pose
//    site_from_a in the site frame (x north, y east, z down).
//  - An image is one eye of one station (ImageRef); a station's two images are
//    StationImages.
//  - A tie point is one ground point seen in two or more images; each sighting is a
//    TieObservation naming the image and the pixel.
//  - A station's pointing prior is the 6x6 covariance of the perturbation (dtheta, dt)
//    that maps the approximate pose to the true one:
//        R_true = rotationExp(dtheta) * R_approx,  t_true = t_approx + dt,
//    dtheta in radians about the site axes, dt in metres in the site frame. The
//    off-diagonal blocks carry the correlation between attitude and position (a mast head
//    turned about a wrong axis is both rotated and displaced).
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

enum class Eye : std::uint8_t { kLeft = 0, kRight = 1 };

struct ImageRef {
    std::uint16_t station = 0U;
    Eye eye = Eye::kLeft;
};

struct NetworkStation {
    CameraPair rig{};               // left = model_a, right = model_b, calibrated b_from_a
    RigidPose site_from_a{};        // the left camera's pose (approximate or adjusted)
    Mat6 prior_covariance = Mat6::Zero();  // of (dtheta [rad], dt [m]); see above
};

struct TieObservation {
    ImageRef image{};
    std::uint32_t point = 0U;       // tie point id, 0 .. points - 1
    Vec2 pixel_px = Vec2::Zero();   // conventions of vtm/core/camera_model.hpp
};

// The 8-bit images of one station's two eyes; an empty view (data null) for an eye
// without an image.
struct StationImages {
    ImageView<const std::uint8_t> left{};
    ImageView<const std::uint8_t> right{};
};

// The image of one eye.
[[nodiscard]] inline const ImageView<const std::uint8_t>& imageOfEye(const StationImages& images, Eye eye) noexcept {
    return eye == Eye::kLeft ? images.left : images.right;
}

// site_from_cam of one eye of a station: the left pose itself, or poseOfB for the right.
[[nodiscard]] RigidPose siteFromEye(const NetworkStation& station, Eye eye) noexcept;

// The camera model of one eye.
[[nodiscard]] const CameraModel& modelOfEye(const NetworkStation& station, Eye eye) noexcept;

// kOk, or kInvalidArgument naming the field: both models valid, b_from_a and site_from_a
// rigid (rotation within 1e-9), the prior covariance finite, symmetric within 1e-12
// (relative) and with a non-negative diagonal.
[[nodiscard]] Status validateNetworkStation(const NetworkStation& station) noexcept;

}  // namespace vtm
