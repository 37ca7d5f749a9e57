// One row of image 2 warped onto image 1 by a plane's homography (private to
// fsw/descent; the sweep's warp, docs/descent.md "Warp").
#pragma once

#include <cstdint>

namespace vtm::descent::detail {

// Bilinear positions in 1/32 px (as OpenCV's INTER_BITS).
constexpr std::int32_t kSubpixelBits = 5;
constexpr std::int32_t kSubpixel = 1 << kSubpixelBits;

// out[x] for x in [x0, x1) (0 <= x0 <= x1 <= width): image 2 (width x height, levels x 16,
// followed by a padding row: prefilter()) at H (x, y) under the row-major homography h[9],
// bilinear with 1/32 px positions and weights, in levels x 16 rounded; 0 where the position
// is outside image 2 or behind camera 2. Columns certainly inside skip the per-pixel test
// and those certainly outside cost nothing (the same values as testing every pixel).
void warpRow(const double* h, std::int32_t y, std::int32_t x0, std::int32_t x1, const std::uint16_t* image2,
             std::int32_t width, std::int32_t height, float* out) noexcept;

// A superset of the x of row y (within [0, width - 1]) whose point (x + dx, y) the
// row-major homography h maps in front of camera 2 and inside image 2 (width x height):
// [lo, hi], lo > hi when there is none. Exact arithmetic would give an interval (the
// intersection of half-lines); it is widened by a margin far above the rounding.
void spanMappedInside(const double* h, double dx, double y, std::int32_t width, std::int32_t height, double& lo,
                      double& hi) noexcept;

}  // namespace vtm::descent::detail
