// Speckle filter of a disparity image (after MlStereo::compute): removes the small islands
// of disparities that wrong matches leave in texture-poor or occluded areas (docs/stereo.md,
// "Speckle filter").
//
// A region is a 4-connected set of valid pixels whose neighbours differ by at most
// max_diff_px16 (1/16 px). A region of at most max_region_px pixels loses its disparities:
// disparity kNoDisparity, sigma +inf, reason Reason::kSpeckle. Larger regions are kept as
// they are. Each region is found by a breadth-first fill with an explicit queue in the
// workspace (no recursion); every valid pixel enters the queue once, so the cost is
// O(width * height) whatever the content. Integer only: the same bits on every target.
// Memory: workspaceBytes(config), carved at init(); apply() never allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {

struct SpeckleConfig {
    std::int32_t max_width = 1024, max_height = 1024;  // capacity, pixels: 1..4096 each
    std::int32_t max_region_px = 100;                   // regions this small are removed: 0 (off)..65536
    std::int32_t max_diff_px16 = kDisparityScale;       // neighbours in one region: |d1 - d2| <= this, 0..32767
    // kOk, or kInvalidConfig naming the field, detail = its value.
    [[nodiscard]] Status validate() const noexcept;
};

class SpeckleFilter {
public:
    // Arena bytes init() takes (a visited flag and a queue entry per pixel), 0 for an
    // invalid configuration.
    [[nodiscard]] static std::size_t workspaceBytes(const SpeckleConfig& config) noexcept;
    // Validates the config (kInvalidConfig) and carves the workspace (kOutOfMemory).
    [[nodiscard]] Status init(const SpeckleConfig& config, Arena& arena) noexcept;
    // Filters `out` in place. out.disparity_px16 is required; out.sigma_px and out.reason
    // are updated where given (each the disparity's size, else kSizeMismatch). stats, if
    // given, moves the removed pixels from valid_pixels / kValid to kSpeckle. removed: the
    // pixels that lost their disparity. kNotInitialized before init(); kInvalidArgument for
    // an empty disparity view; kSizeMismatch beyond the capacity.
    [[nodiscard]] Status apply(const DisparityOutput& out, StereoStats* stats = nullptr,
                               std::int32_t* removed = nullptr) noexcept;

    [[nodiscard]] const SpeckleConfig& config() const noexcept { return config_; }

private:
    [[nodiscard]] std::int32_t fillRegion(const ImageView<std::int16_t>& disp, std::int32_t seed) noexcept;
    void dropRegion(const DisparityOutput& out, std::int32_t size) noexcept;

    SpeckleConfig config_{};
    bool initialized_ = false;
    Span<std::uint8_t> visited_{};  // per pixel (row stride = width)
    Span<std::int32_t> queue_{};    // pixel indices of the region being filled
};

}  // namespace vtm::stereo
