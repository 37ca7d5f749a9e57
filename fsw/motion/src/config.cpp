// Config::validate: every field range-checked before a refinement starts.
#include "vtm/core/math.hpp"
#include "vtm/core/config_check.hpp"
#include "vtm/motion/motion_refiner.hpp"

namespace vtm::motion {
namespace {

// (0, 1000], NaN refused.
bool inScale(double v) noexcept { return math::isFinite(v) && v > 0.0 && v <= 1000.0; }

}  // namespace

Status Config::validate() const noexcept {
    if (max_iterations < 1 || max_iterations > kMaxMotionIterations) {
        return invalidConfig("max_iterations: must be 1..200", max_iterations);
    }
    if (kernel != RobustKernel::kNone && kernel != RobustKernel::kHuber && kernel != RobustKernel::kCauchy) {
        return invalidConfig("kernel: must be none, huber or cauchy", static_cast<std::int64_t>(kernel));
    }
    if (!inScale(robust_scale_px)) {
        return invalidConfig("robust_scale_px: must be in (0, 1000] px", 0);
    }
    if (!inScale(outlier_threshold_px)) {
        return invalidConfig("outlier_threshold_px: must be in (0, 1000] px", 0);
    }
    if (max_passes < 1 || max_passes > kMaxMotionPasses) {
        return invalidConfig("max_passes: must be 1..10", max_passes);
    }
    if (min_inliers < 6 || min_inliers > kMaxMotionMatches) {
        return invalidConfig("min_inliers: must be 6..1024 (5 motion parameters plus redundancy)", min_inliers);
    }
    if (!math::isFinite(rotation_prior_sigma_rad) || rotation_prior_sigma_rad < 0.0 ||
        rotation_prior_sigma_rad > math::kPi) {
        return invalidConfig("rotation_prior_sigma_rad: must be 0 (none) or in (0, pi] rad", 0);
    }
    if (!math::isFinite(range_min_m) || range_min_m <= 0.0) {
        return invalidConfig("range_min_m: must be finite and > 0 m", 0);
    }
    if (!math::isFinite(range_max_m) || range_max_m <= range_min_m || range_max_m > 1e7) {
        return invalidConfig("range_max_m: must be > range_min_m and <= 1e7 m", 0);
    }
    return Status::ok();
}

}  // namespace vtm::motion
