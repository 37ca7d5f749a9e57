// Triangulation of a rectified pair's disparities (paper §6): every valid disparity becomes
// a 3-D point in the site frame with the 1-sigma uncertainty of its range.
//
// Rectified geometry (fsw/rectify's RectifiedPair as plain numbers, so that triangulation
// itself needs vtm_core only; rectified_geometry.hpp builds it from the pair): both rectified cameras are undistorted pinholes with
// the same fx, fy, cy and orientation; the right one's projection centre is baseline_m
// along the rectified +x (or -x: then disparities are negative). With the disparity
// convention of fsw/stereo (d = x_left - x_right):
//   depth Z = fx * b / (d - (cx_left - cx_right)),  b = signed baseline (+ when right is at +x)
//   point_rect = Z * ((x - cx_left) / fx, (y - cy) / fy, 1)
//   sigma_Z = Z^2 / (fx |b|) * sigma_d,  sigma_range = sigma_Z * |point| / Z
// Only + - * / and sqrt: the same bits on every target.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::terrain {

struct RectifiedGeometry {
    double fx_px = 0.0, fy_px = 0.0;
    double cx_left_px = 0.0, cx_right_px = 0.0, cy_px = 0.0;
    double baseline_m = 0.0;                  // signed: + when the right camera is at rectified +x
    Mat3 R_site_from_rect = Mat3::Identity();  // the left rectified optical frame in the site frame
    Vec3 left_centre_site_m = Vec3::Zero();    // the left projection centre in the site frame

    // kInvalidArgument naming the field: fx/fy not > 0, baseline 0, non-finite numbers,
    // R not a rotation (orthonormal within 1e-9, determinant +1).
    [[nodiscard]] Status validate() const noexcept;
};

// A triangulated point. Trivial (no member initialisers) so that point buffers can come
// from an Arena; `TerrainPoint p{};` is all zeros.
struct TerrainPoint {
    float x_m, y_m, z_m;   // site frame (z down)
    float sigma_range_m;   // 1-sigma along the left camera's ray
};

struct TriangulationLimits {
    double min_range_m = 0.5;       // nearer points are refused (disparity noise dominates)
    double max_range_m = 200.0;     // farther points are refused
    double max_sigma_ratio = 0.05;  // sigma_range / range above this: refused
    double default_sigma_px = 0.25; // sigma_d where the caller gives no uncertainty image
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

// The disparity convention of fsw/stereo: 1/16 pixel, INT16_MIN (stereo::kNoDisparity) = none.
constexpr std::int32_t kDisparityScale = 16;
constexpr std::int16_t kNoDisparity = INT16_MIN;

// One pixel: kOk and the point, or kNoData (no disparity, at or behind infinity, out of the
// range limits, too uncertain). sigma_d_px: the disparity's 1-sigma, pixels.
[[nodiscard]] Status triangulatePixel(const RectifiedGeometry& geometry, const TriangulationLimits& limits,
                                      double x_px, double y_px, double disparity_px, double sigma_d_px,
                                      TerrainPoint& point) noexcept;

struct TriangulationStats {
    std::int32_t points = 0;         // written
    std::int32_t no_disparity = 0;   // kNoDisparity pixels
    std::int32_t refused = 0;        // behind the cameras, out of range or too uncertain
    std::int32_t dropped = 0;        // valid points beyond the output's capacity
};

// A disparity image (left image size, 1/16 px) and optionally its sigma (pixels, may be
// empty) to points, in row-major order, at most out.size() of them (the rest counted as
// dropped). kInvalidArgument (geometry or limits), kSizeMismatch (sigma size).
[[nodiscard]] Status triangulate(const RectifiedGeometry& geometry, const TriangulationLimits& limits,
                                 const ImageView<const std::int16_t>& disparity_px16,
                                 const ImageView<const float>& sigma_px, Span<TerrainPoint> out,
                                 TriangulationStats& stats) noexcept;

}  // namespace vtm::terrain
