// The bilinear samplers of fsw/features (private): the template matcher's quantised one and
// the affine refinement's, each with a fast form for where it spends its time that gives
// the plain form's values bit for bit (tests/features/bilinear_test.cpp holds them to it).
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"

namespace vtm::features::detail {

// Local affine map of pixel offsets [a b; c d] (from-image offsets -> to-image offsets).
struct Affine2 {
    double a = 1.0, b = 0.0, c = 0.0, d = 1.0;
};

// Bilinear sample of `img` (at least 2 x 2) at (x, y) clamped to the image, in
// 1/kWeightOne grey levels (template_ncc.hpp). The weights are quantised first, so the
// result is an exact integer on every target.
[[nodiscard]] std::uint16_t sampleQuantised(const ImageView<const std::uint8_t>& img, double x, double y) noexcept;

// The (2 half + 1)^2 samples, row-major, of sampleQuantised at the points
// (cx + (m.a dx + m.b dy), cy + (m.c dx + m.d dy)), |dx|, |dy| <= half, into dst. When
// every point lies inside the image (the usual case, checked at the corners) the clamps
// are skipped and the cell's corner is a truncation: the same values.
void sampleQuantisedGrid(const ImageView<const std::uint8_t>& img, double cx, double cy, const Affine2& m,
                         std::int32_t half, std::uint16_t* dst) noexcept;

// Bilinear sample at (x, y) in doubles; the caller keeps (x, y) inside [0, w-1] x [0, h-1]
// and the image at least 2 x 2.
[[nodiscard]] double sampleLinear(const ImageView<const std::uint8_t>& img, double x, double y) noexcept;

// sampleLinear at (x, y) and its central differences at +-step:
// gx = sampleLinear(x + step, y) - sampleLinear(x - step, y), gy likewise in y, the same
// values; the five samples share the cells and row interpolations they have in common.
// The caller keeps every one of the five points inside as sampleLinear requires.
struct CrossSample {
    double value, gx, gy;
};
[[nodiscard]] CrossSample sampleCross(const ImageView<const std::uint8_t>& img, double x, double y,
                                      double step) noexcept;

}  // namespace vtm::features::detail
