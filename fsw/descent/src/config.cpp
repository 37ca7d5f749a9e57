// Configuration checks, the workspace formula and init() of the plane sweep.
#include "vtm/core/config_check.hpp"
#include "vtm/descent/plane_sweep.hpp"

#include <cmath>

namespace vtm::descent {
namespace {

bool finite(double v) noexcept { return std::isfinite(v); }

// Element counts of every workspace buffer, in the order init() carves them.
struct Sizes {
    std::size_t planes;   // homographies: 9 doubles each; inverse depths: 1 double each
    std::size_t image;    // prefiltered image 2
    std::size_t width;    // one row
    std::size_t warped;   // (band_rows + window - 1) rows
    std::size_t band;     // band_rows rows
};

Sizes sizesOf(const Config& c) noexcept {
    const auto w = static_cast<std::size_t>(c.max_width);
    Sizes s{};
    s.planes = static_cast<std::size_t>(c.planes);
    s.image = w * static_cast<std::size_t>(c.max_height) + w + 1U;  // + a padding row and a pixel
    s.width = w;
    s.warped = w * static_cast<std::size_t>(c.band_rows + c.window - 1);
    s.band = w * static_cast<std::size_t>(c.band_rows);
    return s;
}

}  // namespace

Status Config::validate() const noexcept {
    if (max_width < 16 || max_width > 4096) {
        return invalidConfig("max_width: must be 16..4096 px", max_width);
    }
    if (max_height < 16 || max_height > 4096) {
        return invalidConfig("max_height: must be 16..4096 px", max_height);
    }
    if (planes < 3 || planes > kMaxPlanes) {
        return invalidConfig("planes: must be 3..256", planes);
    }
    if (!finite(depth_min_m) || !(depth_min_m > 0.0) || depth_min_m > 1.0e7) {
        return invalidConfig("depth_min_m: must be a finite number > 0 (metres, at most 1e7)", 0);
    }
    if (!finite(depth_max_m) || !(depth_max_m > depth_min_m) || depth_max_m > 1.0e7) {
        return invalidConfig("depth_max_m: must be finite and > depth_min_m (metres, at most 1e7)", 0);
    }
    if (window < 3 || window > 31 || (window % 2) != 1) {
        return invalidConfig("window: must be odd, 3..31 px", window);
    }
    if (window > max_width || window > max_height) {
        return invalidConfig("window: larger than max_width or max_height", window);
    }
    if (score != Score::kSad && score != Score::kNcc) {
        return invalidConfig("score: unknown value (kSad or kNcc)", static_cast<std::int64_t>(score));
    }
    if (!finite(max_plane_step_px) || max_plane_step_px < 0.0 || max_plane_step_px > 1000.0) {
        return invalidConfig("max_plane_step_px: must be 0..1000 (image-2 pixels; 0: every plane)", 0);
    }
    if (!finite(min_parallax_px) || min_parallax_px < 0.0 || min_parallax_px > 1000.0) {
        return invalidConfig("min_parallax_px: must be 0..1000 (image-2 pixels)", 0);
    }
    if (band_rows < 1 || band_rows > max_height) {
        return invalidConfig("band_rows: must be 1..max_height", band_rows);
    }
    return Status::ok();
}

std::size_t PlaneSweep::workspaceBytes(const Config& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const Sizes s = sizesOf(config);
    // Term by term, in the order init() carves them; Arena::arrayBytes adds worst-case padding.
    return Arena::arrayBytes<double>(9U * s.planes) + Arena::arrayBytes<double>(s.planes)    // homographies, 1/z
           + Arena::arrayBytes<std::uint16_t>(s.image)                              // prefiltered image 2
           + Arena::arrayBytes<std::int32_t>(s.width)                               // prefilter row
           + 2U * Arena::arrayBytes<float>(s.warped)                                // image-1 rows, warped rows
           + 3U * Arena::arrayBytes<double>(s.width)                                // column sums A, B, C
           + 2U * Arena::arrayBytes<double>(s.band)                                 // image-1 window sum, variance (NCC)
           + 4U * Arena::arrayBytes<float>(s.band)                                  // best, previous, below, above score
           + Arena::arrayBytes<std::int16_t>(s.band);                               // best plane
}

Status PlaneSweep::init(const Config& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const Sizes s = sizesOf(config);
    homographies_ = arena.allocateArray<double>(9U * s.planes);
    inverseDepth_ = arena.allocateArray<double>(s.planes);
    image2_ = arena.allocateArray<std::uint16_t>(s.image);
    filterRow_ = arena.allocateArray<std::int32_t>(s.width);
    image1Rows_ = arena.allocateArray<float>(s.warped);
    warped_ = arena.allocateArray<float>(s.warped);
    colA_ = arena.allocateArray<double>(s.width);
    colB_ = arena.allocateArray<double>(s.width);
    colC_ = arena.allocateArray<double>(s.width);
    sumI_ = arena.allocateArray<double>(s.band);
    varI_ = arena.allocateArray<double>(s.band);
    bestScore_ = arena.allocateArray<float>(s.band);
    prevScore_ = arena.allocateArray<float>(s.band);
    belowScore_ = arena.allocateArray<float>(s.band);
    aboveScore_ = arena.allocateArray<float>(s.band);
    bestIndex_ = arena.allocateArray<std::int16_t>(s.band);
    if (bestIndex_.empty() || aboveScore_.empty() || belowScore_.empty() || prevScore_.empty() ||
        bestScore_.empty() || varI_.empty() || sumI_.empty() || colC_.empty() ||
        colB_.empty() || colA_.empty() || warped_.empty() || image1Rows_.empty() || filterRow_.empty() ||
        image2_.empty() || inverseDepth_.empty() || homographies_.empty()) {
        return Status(StatusCode::kOutOfMemory, "PlaneSweep::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    radius_ = config.window / 2;
    width_ = 0;
    height_ = 0;
    initialized_ = true;
    return Status::ok();
}

Status PlaneSweep::setDepthRange(double depth_min_m, double depth_max_m, double min_parallax_px) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PlaneSweep::setDepthRange: init() has not succeeded");
    }
    Config c = config_;
    c.depth_min_m = depth_min_m;
    c.depth_max_m = depth_max_m;
    c.min_parallax_px = min_parallax_px;
    VTM_RETURN_IF_ERROR(c.validate());
    config_ = c;
    return Status::ok();
}

}  // namespace vtm::descent
