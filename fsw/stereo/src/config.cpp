#include "vtm/core/config_check.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {
namespace {

bool isOdd(std::int32_t v) noexcept { return (v % 2) == 1; }

Status validateGeometry(const Config& c) noexcept {
    if (c.max_width < 8 || c.max_width > 8192) {
        return invalidConfig("max_width: must be 8..8192 px", c.max_width);
    }
    if (c.max_height < 8 || c.max_height > 8192) {
        return invalidConfig("max_height: must be 8..8192 px", c.max_height);
    }
    if (c.d_min < -4096 || c.d_min > 4096) {
        return invalidConfig("d_min: must be -4096..4096 px", c.d_min);
    }
    if (c.d_max < c.d_min) {
        return invalidConfig("d_max: must be >= d_min (the range is empty)", c.d_max);
    }
    if (c.d_max - c.d_min + 1 > 1024) {
        return invalidConfig("d_max: at most 1024 disparities (d_max - d_min + 1)", c.d_max - c.d_min + 1);
    }
    if (c.window < 3 || c.window > 31 || !isOdd(c.window)) {
        return invalidConfig("window: must be odd, 3..31 px", c.window);
    }
    if (c.prefilter_window < 3 || c.prefilter_window > 31 || !isOdd(c.prefilter_window)) {
        return invalidConfig("prefilter_window: must be odd, 3..31 px", c.prefilter_window);
    }
    if (c.prefilter != Prefilter::kNone && c.prefilter != Prefilter::kLocalMeanRemoved) {
        return invalidConfig("prefilter: unknown value", static_cast<std::int64_t>(c.prefilter));
    }
    return Status::ok();
}

Status validateModel(const Config& c) noexcept {
    if (c.beta_q10 < 1 || c.beta_q10 > 65535) {
        return invalidConfig("beta_q10: must be 1..65535 (1/1024 px per grey level)", c.beta_q10);
    }
    if (c.intensity_bins != 8 && c.intensity_bins != 16 && c.intensity_bins != 32 && c.intensity_bins != 64) {
        return invalidConfig("intensity_bins: must be 8, 16, 32 or 64", c.intensity_bins);
    }
    if (c.inlier_sigma_px16 < 4 || c.inlier_sigma_px16 > 128) {
        return invalidConfig("inlier_sigma_px16: must be 4..128 (1/16 px)", c.inlier_sigma_px16);
    }
    if (c.inlier_percent < 1 || c.inlier_percent > 99) {
        return invalidConfig("inlier_percent: must be 1..99", c.inlier_percent);
    }
    if (c.outlier_level_percent < 1 || c.outlier_level_percent > 99) {
        return invalidConfig("outlier_level_percent: must be 1..99", c.outlier_level_percent);
    }
    if (c.truncation_sigmas < 1 || c.truncation_sigmas > 6) {
        return invalidConfig("truncation_sigmas: must be 1..6", c.truncation_sigmas);
    }
    if (c.truncation_sigmas * c.inlier_sigma_px16 > 15 * 16) {
        return invalidConfig("truncation_sigmas: radius truncation_sigmas * sigma must be <= 15 px",
                       static_cast<std::int64_t>(c.truncation_sigmas) * c.inlier_sigma_px16);
    }
    return Status::ok();
}

Status validateIndicators(const Config& c) noexcept {
    if (c.uniqueness_percent < 0 || c.uniqueness_percent > 100) {
        return invalidConfig("uniqueness_percent: must be 0..100", c.uniqueness_percent);
    }
    if (c.lr_max_diff_px < -1 || c.lr_max_diff_px > 64) {
        return invalidConfig("lr_max_diff_px: must be -1 (off) or 0..64", c.lr_max_diff_px);
    }
    if (c.min_curvature < 0 || c.min_curvature > 65535) {
        return invalidConfig("min_curvature: must be 0..65535", c.min_curvature);
    }
    if (c.max_outlier_percent < 1 || c.max_outlier_percent > 100) {
        return invalidConfig("max_outlier_percent: must be 1..100", c.max_outlier_percent);
    }
    return Status::ok();
}

}  // namespace

Status Config::validate() const noexcept {
    VTM_RETURN_IF_ERROR(validateGeometry(*this));
    VTM_RETURN_IF_ERROR(validateModel(*this));
    return validateIndicators(*this);
}

}  // namespace vtm::stereo
