// Colour-coded disparity as in the paper's Figure 3 (Olson et al.): the largest
// disparity (nearest terrain) red, then yellow, green, cyan, blue, down to purple for
// the smallest; black where there is no match.
//
// The ramp is a hue sweep at full saturation and value: hue = (1 - t) * 270 degrees
// with t = (d - d_lo) / (d_hi - d_lo) clamped to [0, 1]. So d_hi -> (255, 0, 0) red,
// d_lo -> (128, 0, 255) purple; values outside [d_lo, d_hi] take the end colours.
#pragma once

#include <array>
#include <cstdint>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

using Rgb = std::array<std::uint8_t, 3>;

// Colour of one disparity (pixels). Non-finite d (+inf, NaN: no match) -> black.
// If d_hi <= d_lo every finite d is red.
Rgb disparityColor(float d_px, float d_lo_px, float d_hi_px);

// RGB image (channels 3) of a one-channel disparity image (pixels).
GreyImage colorizeDisparity(const FloatImage& disparity_px, float d_lo_px, float d_hi_px);

}  // namespace vtm::ground
