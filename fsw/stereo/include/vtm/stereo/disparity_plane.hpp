// Disparities known before the dense search (e.g. the wide-baseline mapper's refined inlier
// features mapped into the rectified pair) as a plane in disparity space: the surface the
// coarse level of stereo::PyramidStereo follows. docs/stereo.md.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::stereo {

// Largest |coordinate| of a sample fitDisparityPlane accepts, pixels.
constexpr double kMaxPlaneSamplePx = 1.0e6;

// A plane in disparity space over the left rectified image, d(x, y) = a x + b y + c px: a
// 3D plane of the scene (a plane maps to one in disparity space). The search surface of a
// coarse-to-fine stereo (PyramidStereo) from disparities known before the dense search.
struct DisparityPlane {
    double a = 0.0;
    double b = 0.0;
    double c = 0.0;
    std::int32_t used = 0;       // samples of the last fit
    double residual_px = 0.0;    // their median absolute residual
};

// Least-squares fit of the plane to samples (x, y, d) (pixels), then refits (at most 8,
// until the count kept stops changing), each over the samples within max(2 px, 3 x the
// median absolute residual of all samples to the last fit).
// `scratch` holds the residuals (at least samples.size() doubles).
// kInvalidArgument naming the input: fewer than 3 samples, a sample not finite or beyond
// kMaxPlaneSamplePx, scratch too small; kDegenerate when the samples (of any fit) lie on
// a line.
[[nodiscard]] Status fitDisparityPlane(Span<const Vec3> samples, Span<double> scratch, DisparityPlane& plane) noexcept;

// The plane's disparity per pixel, rounded to whole px and clamped to [bound_min,
// bound_max]. kInvalidArgument: an empty output, bound_min > bound_max, bounds outside
// -2047..2047.
[[nodiscard]] Status fillDisparityPlane(const DisparityPlane& plane, std::int32_t bound_min, std::int32_t bound_max,
                                        const ImageView<std::int16_t>& out) noexcept;

}  // namespace vtm::stereo
