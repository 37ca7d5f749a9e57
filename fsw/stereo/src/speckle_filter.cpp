// Speckle filter (speckle_filter.hpp): breadth-first fill of each region of similar
// disparities with a queue in the workspace; small regions lose their disparities.
#include "vtm/stereo/speckle_filter.hpp"

#include <algorithm>
#include <limits>

namespace vtm::stereo {

namespace {

constexpr std::int32_t kMaxSide = 4096;
constexpr std::int32_t kMaxRegion = 65536;

std::size_t pixelCount(const SpeckleConfig& c) noexcept {
    return static_cast<std::size_t>(c.max_width) * static_cast<std::size_t>(c.max_height);
}

// |a - b| <= max_diff for two valid disparities (int32 arithmetic: no overflow).
bool similar(std::int16_t a, std::int16_t b, std::int32_t max_diff) noexcept {
    const std::int32_t d = static_cast<std::int32_t>(a) - static_cast<std::int32_t>(b);
    return d <= max_diff && -d <= max_diff;
}

}  // namespace

Status SpeckleConfig::validate() const noexcept {
    if (max_width < 1 || max_width > kMaxSide) {
        return Status(StatusCode::kInvalidConfig, "SpeckleConfig.max_width: must be 1..4096", max_width);
    }
    if (max_height < 1 || max_height > kMaxSide) {
        return Status(StatusCode::kInvalidConfig, "SpeckleConfig.max_height: must be 1..4096", max_height);
    }
    if (max_region_px < 0 || max_region_px > kMaxRegion) {
        return Status(StatusCode::kInvalidConfig, "SpeckleConfig.max_region_px: must be 0..65536", max_region_px);
    }
    if (max_diff_px16 < 0 || max_diff_px16 > std::numeric_limits<std::int16_t>::max()) {
        return Status(StatusCode::kInvalidConfig, "SpeckleConfig.max_diff_px16: must be 0..32767", max_diff_px16);
    }
    return Status::ok();
}

std::size_t SpeckleFilter::workspaceBytes(const SpeckleConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t n = pixelCount(config);
    return Arena::arrayBytes<std::uint8_t>(n)      // visited flags
           + Arena::arrayBytes<std::int32_t>(n);   // fill queue
}

Status SpeckleFilter::init(const SpeckleConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t n = pixelCount(config);
    visited_ = arena.allocateArray<std::uint8_t>(n);
    queue_ = arena.allocateArray<std::int32_t>(n);
    if (visited_.empty() || queue_.empty()) {
        return Status(StatusCode::kOutOfMemory, "SpeckleFilter::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

// Breadth-first fill of the region of `seed` (valid, not yet visited): queue_[0, size)
// holds its pixels, each once, and they are marked visited. Returns size.
std::int32_t SpeckleFilter::fillRegion(const ImageView<std::int16_t>& disp, std::int32_t seed) noexcept {
    const std::int32_t w = disp.width();
    const std::int32_t h = disp.height();
    const std::int32_t max_diff = config_.max_diff_px16;
    visited_[static_cast<std::size_t>(seed)] = 1U;
    queue_[0] = seed;
    std::int32_t tail = 1;
    for (std::int32_t head = 0; head < tail; ++head) {  // bound: w * h (each pixel enters once)
        const std::int32_t p = queue_[static_cast<std::size_t>(head)];
        const std::int32_t px = p % w;
        const std::int32_t py = p / w;
        const std::int16_t d = disp.row(py)[px];
        const std::int32_t nx[4] = {px - 1, px + 1, px, px};
        const std::int32_t ny[4] = {py, py, py - 1, py + 1};
        for (std::int32_t k = 0; k < 4; ++k) {
            if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) {
                continue;
            }
            const std::int32_t q = ny[k] * w + nx[k];
            const std::int16_t dq = disp.row(ny[k])[nx[k]];
            if (visited_[static_cast<std::size_t>(q)] != 0U || dq == kNoDisparity || !similar(d, dq, max_diff)) {
                continue;
            }
            visited_[static_cast<std::size_t>(q)] = 1U;
            queue_[static_cast<std::size_t>(tail)] = q;
            ++tail;
        }
    }
    return tail;
}

// The region in queue_[0, size) loses its disparities.
void SpeckleFilter::dropRegion(const DisparityOutput& out, std::int32_t size) noexcept {
    const std::int32_t w = out.disparity_px16.width();
    const bool has_sigma = out.sigma_px.data() != nullptr;
    const bool has_reason = out.reason.data() != nullptr;
    for (std::int32_t i = 0; i < size; ++i) {  // bound: max_region_px
        const std::int32_t p = queue_[static_cast<std::size_t>(i)];
        const std::int32_t px = p % w;
        const std::int32_t py = p / w;
        out.disparity_px16.row(py)[px] = kNoDisparity;
        if (has_sigma) {
            out.sigma_px.row(py)[px] = std::numeric_limits<float>::infinity();
        }
        if (has_reason) {
            out.reason.row(py)[px] = static_cast<std::uint8_t>(Reason::kSpeckle);
        }
    }
}

Status SpeckleFilter::apply(const DisparityOutput& out, StereoStats* stats, std::int32_t* removed) noexcept {
    if (removed != nullptr) {
        *removed = 0;
    }
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "SpeckleFilter::apply: init() has not succeeded");
    }
    const ImageView<std::int16_t>& disp = out.disparity_px16;
    if (!disp.valid()) {
        return Status(StatusCode::kInvalidArgument, "SpeckleFilter::apply: out.disparity_px16 is empty or malformed");
    }
    const std::int32_t w = disp.width();
    const std::int32_t h = disp.height();
    if (w > config_.max_width || h > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "SpeckleFilter::apply: disparity exceeds max_width x max_height",
                      w > config_.max_width ? w : h);
    }
    const bool has_sigma = out.sigma_px.data() != nullptr;
    const bool has_reason = out.reason.data() != nullptr;
    if ((has_sigma && !out.sigma_px.sameSize(w, h)) || (has_reason && !out.reason.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "SpeckleFilter::apply: sigma_px or reason is not the disparity's size",
                      w);
    }
    std::fill(visited_.data(), visited_.data() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h),
              std::uint8_t{0});
    std::int32_t cut = 0;
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            const std::int32_t seed = y * w + x;  // < 4096 * 4096: no overflow
            if (visited_[static_cast<std::size_t>(seed)] != 0U || disp.row(y)[x] == kNoDisparity) {
                continue;
            }
            const std::int32_t size = fillRegion(disp, seed);
            if (size <= config_.max_region_px) {
                dropRegion(out, size);
                cut += size;
            }
        }
    }
    if (stats != nullptr) {
        stats->valid_pixels -= cut;
        stats->reason_counts[static_cast<std::size_t>(Reason::kValid)] -= cut;
        stats->reason_counts[static_cast<std::size_t>(Reason::kSpeckle)] += cut;
    }
    if (removed != nullptr) {
        *removed = cut;
    }
    return Status::ok();
}

}  // namespace vtm::stereo
