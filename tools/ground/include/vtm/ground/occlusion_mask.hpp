// Non-occluded masks derived from ground-truth disparity (pixels; unknown = 0 or
// non-finite), for sets that ship without published occlusion masks
// (/work/shared/data/middlebury/README.md). Masks: 255 = evaluate (ground truth known
// and the point visible in the right image), 0 = occluded or unknown.
//
// Convention: left pixel (x, y) with disparity d sees the right pixel (x - d, y). Its
// right-image column is rounded to the nearest integer, halves up: floor(x - d + 0.5).
// A left pixel whose right column falls outside the image is occluded (nothing to match).
#pragma once

#include "vtm/ground/image.hpp"

namespace vtm::ground {

// Tolerance of both tests, pixels: ground truth is quantised (1/4 px for teddy and
// cones) and sloped surfaces change disparity between neighbours, so disparities within
// 1 px are taken as the same surface (Middlebury's own cross-check tolerance).
constexpr float kOcclusionTolerancePx = 1.0F;

// Left-right check (teddy, cones: ground truth for both views). Left pixel x with known
// d_L is visible when its right column xr = floor(x - d_L + 0.5) is inside the image,
// d_R(xr) is known, and |d_L - d_R(xr)| <= tolerance. Where d_R is unknown the point
// cannot be verified and is left out. Fails when the two maps differ in size.
Result<GreyImage> leftRightCheckMask(const FloatImage& gt_left_px, const FloatImage& gt_right_px,
                                     float tolerance_px = kOcclusionTolerancePx);

// Visibility along each row from the left ground truth alone (tsukuba, venus), the rule
// that reproduces the peer figures of shared/data/middlebury/README.md: left pixel x with
// known d, right position r = x - d, is evaluated when r >= 0 and
//   r <= min over known pixels x2 > x of (x2 - d2) + tolerance,
// i.e. no surface to its right reaches more than `tolerance` px further left in the
// right image (a nearer surface covering x's right position). Unknown pixels neither
// occlude nor are evaluated.
GreyImage visibilityMask(const FloatImage& gt_left_px, float tolerance_px = kOcclusionTolerancePx);

// Fraction of pixels (0..1) that a mask marks for evaluation.
double maskFraction(const GreyImage& mask);

}  // namespace vtm::ground
