// Camera models: the parameters of a camera (plain data, as the HAL delivers them with
// every frame) and their geometry: projection of a 3D point to a pixel and
// back-projection of a pixel to a ray. Shared by the simulator's renderer (sim/), the
// HAL drivers and fsw/rectify, so that every part of VTM agrees on one definition.
//
// Conventions (docs/camera-models.md):
//  - Pixel coordinates: x = column, y = row, (0, 0) is the CENTRE of the top-left pixel.
//  - Every model works in its own reference frame ("camera reference frame"):
//      * kPinholeBrown: the optical frame, origin at the projection centre, +z along the
//        optical axis, +x towards growing columns, +y towards growing rows (metres);
//      * kCahv / kCahvor: the frame in which C, A, H, V (O, R) are expressed (e.g. the
//        rover's mast head frame); C is the projection centre in metres.
//    A caller places the camera in the world with a pose T_world_from_reference.
//  - CAHV(OR) as Yakimovsky & Cunningham 1978 and Gennery 2001:
//      x = (P - C).H / (P - C).A,  y = (P - C).V / (P - C).A;
//    CAHVOR moves P radially about the axis O before that projection:
//      zeta = (P - C).O, lambda = (P - C) - zeta O, tau = |lambda|^2 / zeta^2,
//      mu = r0 + r1 tau + r2 tau^2, P' = P + mu lambda.
//    O is used as O / |O| (validation allows |O| within 1e-6 of 1), so that projection
//    and back-projection are exact inverses whatever the last digits of a stored O.
//  - Pinhole + Brown (OpenCV's ordering of k1 k2 p1 p2 k3): normalised (a, b) = (X/Z, Y/Z),
//    r2 = a^2 + b^2, radial = 1 + k1 r2 + k2 r2^2 + k3 r2^3,
//    a' = a radial + 2 p1 a b + p2 (r2 + 2 a^2), b' = b radial + p1 (r2 + 2 b^2) + 2 p2 a b,
//    x = fx a' + cx, y = fy b' + cy.
#pragma once

#include <cstdint>
#include <string_view>

#include "vtm/core/eigen.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

enum class CameraModelKind : std::uint8_t {
    kNone = 0,
    kPinholeBrown = 1,  // fx, fy, cx, cy, k1..k3 radial, p1 p2 tangential
    kCahv = 2,          // C, A, H, V
    kCahvor = 3,        // C, A, H, V, O, R
};

struct CameraModel {
    CameraModelKind kind = CameraModelKind::kNone;
    std::uint16_t width_px = 0U;
    std::uint16_t height_px = 0U;
    // Pinhole + Brown distortion (kPinholeBrown), pixels.
    double fx_px = 0.0, fy_px = 0.0, cx_px = 0.0, cy_px = 0.0;
    double k1 = 0.0, k2 = 0.0, k3 = 0.0, p1 = 0.0, p2 = 0.0;
    // CAHV / CAHVOR vectors in the camera reference frame (C in metres).
    double c[3] = {0.0, 0.0, 0.0};
    double a[3] = {0.0, 0.0, 0.0};
    double h[3] = {0.0, 0.0, 0.0};
    double v[3] = {0.0, 0.0, 0.0};
    double o[3] = {0.0, 0.0, 0.0};
    double r[3] = {0.0, 0.0, 0.0};
};

// A ray in the camera reference frame: origin (the projection centre) and unit direction.
struct CameraRay {
    Vec3 origin_m = Vec3::Zero();
    Vec3 direction = Vec3::UnitZ();
};

// Checks every field the kind uses: kind known, width_px and height_px > 0, finite
// numbers, fx_px/fy_px > 0, A (and O) unit vectors within 1e-6, H and V not parallel to A
// nor coplanar with it, O within 90 degrees of every corner's ray, and the radial
// distortion (k1 k2 k3, or R) monotonic out to beyond the image corners, so that every
// pixel of the image has exactly one ray. kInvalidArgument; the reason names the field
// ("camera model: A is not a unit vector"); detail 0. Fields of other kinds are ignored.
[[nodiscard]] Status validateCameraModel(const CameraModel& model) noexcept;

// Pixel of a point given in the camera reference frame. kDegenerate when the point is
// at or behind the projection centre's plane (Z <= 0, or (P - C).A <= 0; CAHVOR also
// (P - C).O <= 0), or lies beyond the radius where the radial distortion folds back
// (its pixel would not back-project to it). The model must pass validateCameraModel
// (VTM_ASSERT on kind only; other fields are the caller's responsibility).
// Uses only + - * / and sqrt: the same bits on every target.
[[nodiscard]] Status projectPoint(const CameraModel& model, const Vec3& point_m, Vec2& pixel) noexcept;

// Ray through a pixel (any real position, also outside the image). Distortion is
// inverted by Newton's method (at most kMaxUndistortIterations steps, converged when the
// re-distorted point is within 1e-15 (relative) of the pixel's; accepted up to 1e-12);
// kDegenerate if that fails, or if the pixel's ray points 90 degrees or more away from
// A (CAHV) / O (CAHVOR). The direction is a unit vector with direction.A > 0 (CAHV(OR))
// or z > 0 (pinhole).
[[nodiscard]] Status backProjectPixel(const CameraModel& model, const Vec2& pixel, CameraRay& ray) noexcept;
constexpr int kMaxUndistortIterations = 40;

// Constructors for the models a scenario names by field of view.
// Pinhole with square pixels, principal point at the image centre ((w-1)/2, (h-1)/2),
// the horizontal field of view in degrees measured between the outer edges of the
// first and last columns (fx = (w/2) / tan(hfov/2)), no distortion. 0 < hfov < 180.
[[nodiscard]] CameraModel makePinhole(std::uint16_t width_px, std::uint16_t height_px, double hfov_deg) noexcept;
// The CAHV model that projects exactly like an undistorted pinhole (C = 0, A = +z).
[[nodiscard]] CameraModel cahvFromPinhole(const CameraModel& pinhole) noexcept;

// Text form (docs/camera-models.md has the full grammar): ASCII lines "key values...",
// fields separated by blanks or tabs, '\r' ignored, blank lines and lines whose first
// field starts with '#' ignored; numbers as std::strtod reads them ("C" locale).
//   vtm_camera_model 1          exactly, on the first line
//   kind cahvor                 pinhole | cahv | cahvor
//   width_px 1024               1..65535
//   height_px 1024
//   pinhole: fx_px fy_px cx_px cy_px k1 k2 k3 p1 p2      (one number each)
//   cahv:    C A H V     cahvor: C A H V O R             (three numbers each)
// Every field of the kind exactly once, in any order; no field of another kind.
// parseCameraModel: kCorruptData on any problem, the reason naming the field
// ("camera model text: fx_px must be one finite number"), detail = the 1-based line
// number (0 when the problem is a missing field); a model that parses but fails
// validateCameraModel() is kCorruptData with validateCameraModel's reason. `out` is
// written only on success.
[[nodiscard]] Status parseCameraModel(std::string_view text, CameraModel& out) noexcept;
// (Writing the text form is ground-side: vtm::ground::formatCameraModel in tools/ground.)

}  // namespace vtm
