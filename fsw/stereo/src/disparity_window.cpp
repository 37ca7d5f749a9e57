// placeDisparityWindow (vtm/stereo/disparity_window.hpp).
#include "vtm/stereo/disparity_window.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm::stereo {

Status placeDisparityWindow(Span<double> samples, std::int32_t count, std::int32_t bound_min, std::int32_t bound_max,
                            DisparityWindow& window) noexcept {
    if (samples.empty()) {
        return Status(StatusCode::kInvalidArgument, "placeDisparityWindow: samples: no disparity to place the window on");
    }
    if (count < 1 || count > 1024) {
        return Status(StatusCode::kInvalidArgument, "placeDisparityWindow: count must be 1..1024", count);
    }
    if (bound_min > bound_max) {
        return Status(StatusCode::kInvalidArgument, "placeDisparityWindow: bound_min is above bound_max", bound_min);
    }
    const auto n = static_cast<std::int32_t>(samples.size() > 0x7FFFFFFFU ? 0x7FFFFFFFU : samples.size());
    double* d = samples.data();
    for (std::int32_t i = 0; i < n; ++i) {
        if (!math::isFinite(d[i]) || std::fabs(d[i]) > kMaxWindowSamplePx) {
            return Status(StatusCode::kInvalidArgument, "placeDisparityWindow: samples: not finite or beyond 1e6 px", i);
        }
    }
    // Insertion sort (ascending).
    for (std::int32_t i = 1; i < n; ++i) {
        const double v = d[i];
        std::int32_t k = i;
        for (; k > 0 && d[k - 1] > v; --k) {
            d[k] = d[k - 1];
        }
        d[k] = v;
    }
    // Two pixels of margin on each side for the subpixel fit and kOutOfRange.
    const double span = static_cast<double>(count - 1) - 4.0;
    std::int32_t best_lo = 0;
    std::int32_t best_hi = 1;  // exclusive; n >= 1: the first sample alone is a group
    std::int32_t hi = 0;
    for (std::int32_t lo = 0; lo < n; ++lo) {
        hi = hi > lo ? hi : lo;
        for (; hi < n && d[hi] - d[lo] <= span; ++hi) {
        }
        if (hi - lo > best_hi - best_lo) {
            best_lo = lo;
            best_hi = hi;
        }
    }
    const double centre = 0.5 * (d[best_lo] + d[best_hi - 1]);
    std::int32_t start = static_cast<std::int32_t>(std::floor(centre - 0.5 * static_cast<double>(count - 1) + 0.5));
    // Inside the bounds, when they are at least as wide as the window.
    if (static_cast<std::int64_t>(bound_max) - bound_min + 1 >= count) {
        start = start < bound_min ? bound_min : start;
        start = start > bound_max - (count - 1) ? bound_max - (count - 1) : start;
    }
    window.d_min = start;
    window.d_max = start + count - 1;
    window.samples_inside = 0;
    for (std::int32_t i = 0; i < n; ++i) {
        window.samples_inside += (d[i] >= window.d_min && d[i] <= window.d_max) ? 1 : 0;
    }
    return Status::ok();
}

}  // namespace vtm::stereo
