// Coarse-to-fine ML stereo over a wide disparity range at a bounded cost.
//
// A wide-baseline pair spans thousands of disparities (a 5 m pair: -190..2190 px), far
// more than one MlStereo window can search at full resolution. PyramidStereo searches at a
// coarse level of the pair (2x2 averaging, `levels` times) either the whole range or a
// window around a surface the caller gives (sheared along it), fills small holes of the
// coarse disparity along its rows, and interpolates it (bilinear) into a prior per
// full-resolution pixel; the full-resolution MlStereo then searches only the
// prior +- fine_radius_px (MlStereo::setDisparityPrior: the window follows the prior's
// surface). The cost is fixed by the Config, whatever the content: the coarse level's
// (W H / 4^levels) x coarse_disparities plus W H x (2 fine_radius_px + 1) per
// (pixel, disparity), against W H x (d_max - d_min + 1) for one full-resolution search.
//
// Memory: workspaceBytes(config), carved from an Arena at init(); compute() never
// allocates. Deterministic: integer arithmetic, bit-identical on every target.
// docs/stereo.md ("Disparity prior and coarse to fine") has the steps and the measured effect.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {

struct PyramidConfig {
    // Capacity: largest full-resolution image (pixels).
    std::int32_t max_width = 1024;
    std::int32_t max_height = 1024;
    // The coarse level is 1 / 2^levels of the full resolution: 1..3.
    std::int32_t levels = 1;
    // Disparities searched at the coarse level (its workspace), 3..1024: covers a
    // full-resolution range of about 2^levels x (coarse_disparities - 2) px, around the
    // surface when compute() is given one (the defaults: +-128 px around it).
    std::int32_t coarse_disparities = 128;
    // Matching window at the coarse level: odd, 3..31.
    std::int32_t coarse_window = 13;
    // The coarse level's left-right check tolerance, coarse px, -1 (off)..16: its result is
    // only the fine search's centre, and is checked again there (off: measured on the
    // mission pair, more coverage at the same error; docs/stereo.md).
    std::int32_t coarse_lr_max_diff_px = -1;
    // Full-resolution search around the prior: prior - r .. prior + r, 1..64 px.
    std::int32_t fine_radius_px = 12;
    // A coarse pixel without a disparity takes the smaller disparity (the farther surface)
    // of the nearest pixels with one in its row within this many coarse pixels, left and
    // right (0: no filling; 0..64).
    // Further holes are not searched (Reason::kNoPrior).
    std::int32_t fill_reach_px = 16;
    // The matcher's model and checks at both levels; its capacity, disparity and (coarse)
    // window fields are set from the fields above (coarseConfig(), fineConfig()), and
    // clip_search_to_image is on. Its uniqueness check is off at both levels: measured on
    // the rover pair (docs/stereo.md), it called 77 % of the coarse and 60 % of the fine
    // pixels ambiguous, most of them right; the left-right check stays.
    Config matcher = Config::conservative();

    // kOk, or kInvalidConfig naming the field.
    [[nodiscard]] Status validate() const noexcept;
    // The MlStereo configurations of the two levels.
    [[nodiscard]] Config coarseConfig() const noexcept;
    [[nodiscard]] Config fineConfig() const noexcept;
};

// Figures of one compute().
struct PyramidStats {
    StereoStats coarse{};             // the coarse search, before filling
    StereoStats fine{};               // the full-resolution search (what `out` holds)
    std::int32_t coarse_d_min = 0;    // the coarse disparities searched, over all pixels (coarse px)
    std::int32_t coarse_d_max = 0;
    std::int32_t coarse_filled = 0;   // coarse pixels given a disparity by filling
    std::int32_t prior_pixels = 0;    // full-resolution pixels with a prior (searched)
};

class PyramidStereo {
public:
    [[nodiscard]] static std::size_t workspaceBytes(const PyramidConfig& config) noexcept;
    // kInvalidConfig or kOutOfMemory (arena smaller than workspaceBytes).
    [[nodiscard]] Status init(const PyramidConfig& config, Arena& arena) noexcept;

    // Dense disparity of a rectified 8-bit pair over [d_min, d_max] (whole pixels, the
    // range the scene can take, e.g. RectifiedPair::d_min/d_max). Every output pixel gets
    // a disparity or a Reason (kNoPrior where the coarse level gave none nearby).
    // `surface` (optional; empty: none): a disparity per full-resolution pixel (whole px,
    // kNoDisparity: none) of a surface the scene lies near, such as the plane through
    // known disparities (fitDisparityPlane). The coarse search then follows it (its window
    // sheared along the surface, coarse_disparities centred on it) instead of searching
    // d_min..d_max fronto-parallel: a steep slant (level ground in a wide-baseline pair
    // changes disparity by about baseline / camera height px per row, at every level of
    // the pyramid) is found.
    // kNotInitialized; kSizeMismatch (sizes differ, exceed the capacity, outputs or
    // surface of another size, or an image smaller than 8 px at the coarse level);
    // kInvalidArgument when d_max < d_min or, without a surface, the range is wider than
    // the coarse window covers (detail: the width).
    [[nodiscard]] Status compute(const ImageView<const std::uint8_t>& left,
                                 const ImageView<const std::uint8_t>& right,
                                 const ImageView<const std::int16_t>& surface, std::int32_t d_min,
                                 std::int32_t d_max, const DisparityOutput& out,
                                 PyramidStats* stats = nullptr) noexcept;

    // The prior of the last compute() (whole pixels, kNoDisparity where none), for
    // reports and tests.
    [[nodiscard]] ImageView<const std::int16_t> prior() const noexcept { return priorView_; }
    [[nodiscard]] const PyramidConfig& config() const noexcept { return config_; }

private:
    [[nodiscard]] Status buildLevels(const ImageView<const std::uint8_t>& left,
                                     const ImageView<const std::uint8_t>& right) noexcept;
    [[nodiscard]] Status searchCoarse(const ImageView<const std::int16_t>& surface, std::int32_t d_min,
                                      std::int32_t d_max, const ImageView<std::int16_t>& coarse,
                                      PyramidStats& stats) noexcept;
    void fillCoarseHoles(const ImageView<std::int16_t>& coarse, PyramidStats& stats) noexcept;
    void interpolatePrior(const ImageView<const std::int16_t>& coarse, std::int32_t width,
                          std::int32_t height, PyramidStats& stats) noexcept;

    PyramidConfig config_{};
    bool initialized_ = false;
    MlStereo coarse_{};
    MlStereo fine_{};
    Span<std::uint8_t> leftLevels_{};   // levels 1..L of the left image, one after another
    Span<std::uint8_t> rightLevels_{};
    Span<std::int16_t> coarseDisparity_{};
    Span<std::int16_t> coarsePrior_{};  // the surface at the coarse level, minus half the window
    Span<std::int16_t> rowScratch_{};  // one coarse row (hole filling)
    Span<std::int16_t> prior_{};
    ImageView<std::uint8_t> coarseLeft_{};
    ImageView<std::uint8_t> coarseRight_{};
    ImageView<const std::int16_t> priorView_{};
};

}  // namespace vtm::stereo
