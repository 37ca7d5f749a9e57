// Placement of MlStereo's disparity window (setDisparityWindow) on disparities known
// before the dense search: e.g. the wide-baseline mapper's refined inlier features mapped
// into the rectified pair. The matcher searches a fixed number of disparities (its
// Config); where the scene's disparities lie depends on the pair (baseline, convergence),
// so the window is placed per pair where the known disparities are. docs/stereo.md.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::stereo {

// Largest |sample| placeDisparityWindow accepts, pixels.
constexpr double kMaxWindowSamplePx = 1.0e6;

struct DisparityWindow {
    std::int32_t d_min = 0;           // the window, pixels, inclusive: d_max = d_min + count - 1
    std::int32_t d_max = 0;
    std::int32_t samples_inside = 0;  // samples d with d_min <= d <= d_max
};

// The rule, over the samples sorted ascending (samples is sorted in place: insertion
// sort, O(n^2) for n samples):
//  1. the group: the run of consecutive sorted samples that holds the most samples with
//     last - first <= count - 5 (two pixels of margin on each side of the window for the
//     subpixel fit and kOutOfRange); among equally large runs the one of the lowest
//     disparities; a single sample when count < 5;
//  2. the window is centred on the group: d_min = floor(centre - (count - 1) / 2 + 0.5),
//     centre = (first + last) / 2 of the group;
//  3. when the bounds [bound_min, bound_max] (e.g. the rectifier's disparities of the
//     range interval, rectify::RectifiedPair::d_min/d_max) hold at least count
//     disparities, the window is moved inside them (a wider window than the bounds is left
//     where rule 2 put it).
// kInvalidArgument naming the input: no sample, a sample not finite or beyond
// kMaxWindowSamplePx, count outside 1..1024, bound_min > bound_max.
[[nodiscard]] Status placeDisparityWindow(Span<double> samples, std::int32_t count, std::int32_t bound_min,
                                          std::int32_t bound_max, DisparityWindow& window) noexcept;

// A plane in disparity space over the left rectified image, d(x, y) = a x + b y + c px: a
// 3D plane of the scene (a plane maps to one in disparity space). The search surface of a
// coarse-to-fine stereo (PyramidStereo) from disparities known before the dense search.
struct DisparityPlane {
    double a = 0.0;
    double b = 0.0;
    double c = 0.0;
    std::int32_t used = 0;       // samples of the second fit
    double residual_px = 0.0;    // their median absolute residual
};

// Least-squares fit of the plane to samples (x, y, d) (pixels), twice: the second fit
// keeps the samples within max(2 px, 3 x the first fit's median absolute residual).
// `scratch` holds the residuals (at least samples.size() doubles).
// kInvalidArgument naming the input: fewer than 3 samples, a sample not finite or beyond
// kMaxWindowSamplePx, scratch too small; kDegenerate when the samples (of either fit) lie
// on a line.
[[nodiscard]] Status fitDisparityPlane(Span<const Vec3> samples, Span<double> scratch, DisparityPlane& plane) noexcept;

// The plane's disparity per pixel, rounded to whole px and clamped to [bound_min,
// bound_max]. kInvalidArgument: an empty output, bound_min > bound_max, bounds outside
// -2047..2047.
[[nodiscard]] Status fillDisparityPlane(const DisparityPlane& plane, std::int32_t bound_min, std::int32_t bound_max,
                                        const ImageView<std::int16_t>& out) noexcept;

}  // namespace vtm::stereo
