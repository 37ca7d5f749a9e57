// Maximum-likelihood dense stereo (Olson, PAMI 24(6) 2002), as a flight module.
//
// For a rectified pair, every left-image pixel (x, y) gets the disparity d in
// [d_min, d_max] whose window of left pixels is most likely to have come from the right
// image around (x - d, y). A template pixel (x', y', I) is scored by its distance, in
// (x, y, beta * intensity) space, to the NEAREST right-image pixel — precomputed for the
// whole search image as a 3D distance transform — through a density with an explicit
// outlier term: f(D) = alpha * N(D; 0, sigma) + (1 - alpha) * f_out. The score of a
// window is the sum of ln f over its pixels, tabulated as small integers; window sums
// are reused between neighbouring positions (running column and row sums), so the cost
// per (pixel, disparity) does not depend on the window size. Subpixel disparity from a
// parabola through the log-likelihood at the best disparity and its neighbours; sigma
// from its curvature. Every pixel gets a disparity or kNoDisparity with a reason.
//
// Memory: the pair is processed as a stream of rows with ring buffers (row bands), so
// the workspace depends on width, disparity count and window, not on height:
// workspaceBytes(config), carved from an Arena at init(); compute() never allocates.
// Deterministic: integer arithmetic on the hot path, tables built at init with
// vtm::math, bit-identical on every target.
// docs/stereo.md has the algorithm, the formula and the measured accuracy.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::stereo {

// Disparity in fixed point: 1/16 pixel (like OpenCV's DISPARITY_SHIFT = 4).
constexpr std::int32_t kDisparityShift = 4;
constexpr std::int32_t kDisparityScale = 1 << kDisparityShift;
// The value of a pixel without a disparity.
constexpr std::int16_t kNoDisparity = INT16_MIN;
// Largest |disparity| a search may reach, whole px: in 1/16 px with its subpixel part it
// fits int16 and never equals kNoDisparity.
constexpr std::int32_t kMaxDisparityPx = (32767 - 8) / kDisparityScale;  // 2047

// Why a pixel has no disparity (kValid when it has one). Values are stable (telemetry).
enum class Reason : std::uint8_t {
    kValid = 0,
    kBorder = 1,             // the search leaves the right image (Config::clip_search_to_image)
    kNoTexture = 2,          // likelihood curve too flat around its peak
    kAmbiguous = 3,          // a separate peak almost as likely as the best
    kLeftRightMismatch = 4,  // right-to-left search disagrees by more than lr_max_diff_px
    kOutOfRange = 5,         // best disparity on the boundary of [d_min, d_max]
    kLowLikelihood = 6,      // even the best window is mostly outliers
    kSpeckle = 7,            // an island too small to trust (SpeckleFilter, speckle_filter.hpp)
    kNoPrior = 8,            // not searched: the disparity prior has none here (setDisparityPrior)
};
constexpr std::int32_t kReasonCount = 9;

// Intensity preprocessing before matching (both images).
enum class Prefilter : std::uint8_t {
    kNone = 0,            // raw grey levels
    kLocalMeanRemoved = 1,  // I - local mean over prefilter_window, clamped, offset to 128
};

struct Config {
    // Capacity: largest image processed (pixels). Workspace grows with max_width only.
    std::int32_t max_width = 1024;
    std::int32_t max_height = 1024;
    // Disparity search range, pixels, inclusive; left (x, y) matches right (x - d, y).
    // d_min may be negative (verged cameras). 1 <= d_max - d_min + 1 <= 1024.
    std::int32_t d_min = 0;
    std::int32_t d_max = 63;
    // Matching window side, pixels: odd, 3..31.
    std::int32_t window = 15;
    // Intensity weight beta of the distance transform, pixels per grey level, in
    // 1/1024 units (e.g. 64 = 0.0625 px per grey level). 1..65535.
    std::int32_t beta_q10 = 192;
    // Grey-level bins of the 3D distance transform: 8, 16, 32 or 64.
    std::int32_t intensity_bins = 64;
    // Inlier density: Gaussian sigma of D, in 1/16 px. 4..128.
    std::int32_t inlier_sigma_px16 = 6;
    // Probability that a pixel is an inlier (alpha), in percent: 1..99.
    std::int32_t inlier_percent = 50;
    // Outlier density f_out relative to the inlier density's peak, in percent: 1..99.
    std::int32_t outlier_level_percent = 5;
    // false: f(D) = N(D; 0, sigma) only, truncated at the distance transform's radius
    // (ablation of the outlier term).
    bool outlier_enabled = true;
    // Radius of the distance transform in inlier sigmas (the search for the nearest
    // right pixel and the truncation of D): 1..6.
    std::int32_t truncation_sigmas = 3;
    // false: plain overlap (SSD-like, no distance transform) for the ablation study.
    bool distance_transform_enabled = true;
    Prefilter prefilter = Prefilter::kLocalMeanRemoved;
    std::int32_t prefilter_window = 9;  // odd, 3..31
    // Failure indicators (0 disables each). The defaults give dense output (what the
    // Middlebury figures measure); conservative() turns on the checks that trade density
    // for fewer wrong disparities.
    std::int32_t uniqueness_percent = 0;     // second separated peak within this % of the best: ambiguous
    std::int32_t lr_max_diff_px = -1;        // left-right check tolerance, pixels; -1 disables
    std::int32_t min_curvature = 1;          // cost units; flatter peaks are kNoTexture
    std::int32_t max_outlier_percent = 90;   // best window's mean cost above this % of the
                                             // outlier cost: kLowLikelihood (100 disables)
    // false: a pixel some of whose search leaves the right image is kBorder. true: it
    // searches the part inside (at least 3 disparities, else kBorder; a best on that
    // part's boundary is kOutOfRange). For wide searches, where few pixels have all of it
    // inside (stereo::PyramidStereo).
    bool clip_search_to_image = false;

    // kOk, or kInvalidConfig with the field named in the reason and its value in detail.
    [[nodiscard]] Status validate() const noexcept;

    // Named presets (the defaults above are the dense one).
    // conservative(): left-right check (1 px) and uniqueness (5 %) on: fewer disparities,
    // fewer wrong ones — for hazard detection, where a false obstacle is worse than none.
    [[nodiscard]] static Config conservative() noexcept {
        Config c;
        c.uniqueness_percent = 5;
        c.lr_max_diff_px = 1;
        return c;
    }
};

// Caller-provided outputs, each exactly the input size. disparity_px16: 1/16 px, kNoDisparity where reason != kValid. sigma_px: 1-sigma
// uncertainty of the disparity in pixels (+inf where no disparity). reason: Reason.
struct DisparityOutput {
    ImageView<std::int16_t> disparity_px16;
    ImageView<float> sigma_px;       // may be empty (not produced)
    ImageView<std::uint8_t> reason;  // may be empty (not produced)
};

// Quality figures of one compute().
struct StereoStats {
    std::int32_t valid_pixels = 0;
    std::int32_t reason_counts[kReasonCount] = {};
};

class MlStereo {
public:
    // Bytes of arena the module needs for this configuration (every buffer, alignment
    // padding included). docs/stereo.md gives the formula term by term.
    [[nodiscard]] static std::size_t workspaceBytes(const Config& config) noexcept;

    // Validates the config, carves the workspace from `arena`, builds the tables.
    // kInvalidConfig (bad field) or kOutOfMemory (arena too small).
    [[nodiscard]] Status init(const Config& config, Arena& arena) noexcept;

    // The disparity window of the following compute() calls: d_min .. d_min + count - 1,
    // count = config.d_max - config.d_min + 1 fixed at init (init() sets the Config's own
    // window, d_min = config.d_min). A caller that knows where the scene lies (PyramidStereo
    // at its coarse level, from the range asked for) moves the window per request, as
    // descent::PlaneSweep's setDepthRange moves its depths; the workspace does not change.
    // The search runs in window coordinates: the right image is moved by
    // shift = d_min - config.d_min columns inside the workspace (right'(u) = right(u - shift)),
    // its columns outside the image black (grey level 0, before the prefilter), and the
    // Config's d_min..d_max are searched on (left, right'); shift is added to every
    // disparity found. So right columns beyond the moved image (u - shift < 0 or >= width)
    // are black pixels to the prefilter, the distance transform and the left-right check
    // (not "no pixel": only columns outside 0..width-1 of right' are), and right columns
    // that the move pushes off the image are not seen at all (docs/stereo.md).
    // kNotInitialized; kInvalidArgument when the window leaves -2047..2047 px (the
    // disparities in 1/16 px, with their subpixel part, must fit int16).
    [[nodiscard]] Status setDisparityWindow(std::int32_t d_min) noexcept;
    // A disparity prior per left pixel (whole pixels; kNoDisparity: do not search this
    // pixel), for the following compute() calls until clearDisparityPrior() or
    // setDisparityWindow(): pixel (x, y) then searches prior(x, y) + d_min ..
    // prior(x, y) + d_max, the Config's d_min..d_max being offsets around the prior. Each
    // template pixel q of the window is compared at q - prior(q) - offset, so the window
    // follows the prior's surface (a sheared window); the window sums are reused as
    // without a prior and the cost per pixel and offset is the same. A prior whose search
    // leaves the right image is kBorder, one whose disparities would not fit int16 in
    // 1/16 px kOutOfRange, a pixel without prior kNoPrior. The view is read, not copied:
    // it must stay valid and the image size (compute() checks). The window is reset to
    // the Config's own (offsets are relative to the prior).
    // kNotInitialized; kInvalidArgument for an empty view.
    [[nodiscard]] Status setDisparityPrior(const ImageView<const std::int16_t>& prior_px) noexcept;
    void clearDisparityPrior() noexcept { prior_ = ImageView<const std::int16_t>(); }
    [[nodiscard]] bool hasDisparityPrior() const noexcept { return prior_.valid(); }

    // The window searched (inclusive).
    [[nodiscard]] std::int32_t windowMin() const noexcept { return window_min_; }
    [[nodiscard]] std::int32_t windowMax() const noexcept { return window_min_ + (config_.d_max - config_.d_min); }

    // Dense disparity of a rectified 8-bit pair (same size, within capacity), over the
    // disparity window (setDisparityWindow; the Config's d_min..d_max unless moved).
    // kNotInitialized, kSizeMismatch (sizes differ / exceed capacity / outputs too
    // small), kInvalidArgument (empty view). Never allocates.
    [[nodiscard]] Status compute(const ImageView<const std::uint8_t>& left,
                                 const ImageView<const std::uint8_t>& right,
                                 const DisparityOutput& out, StereoStats* stats = nullptr) noexcept;

    [[nodiscard]] const Config& config() const noexcept { return config_; }

private:
    Config config_{};
    std::int32_t window_min_ = 0;  // the searched window's first disparity
    ImageView<const std::int16_t> prior_{};  // per-pixel disparity prior (setDisparityPrior)
    bool initialized_ = false;
    // Workspace spans, carved at init (see ml_stereo.cpp for the layout).
    Span<std::uint8_t> costTable_{};     // cost by squared distance (D2 units)
    Span<std::uint8_t> leftFiltered_{};  // prefiltered left image, max_width * max_height
    Span<std::uint8_t> rightFiltered_{};
    Span<std::int32_t> boxColumns_{};    // prefilter column sums, max_width
    Span<std::uint8_t> dtRing_{};        // x-pass rows of the right image's distance transform
    Span<std::uint8_t> dtRow_{};         // one row of the DT as matching costs, per intensity bin
    Span<std::int32_t> templateOffset_{};// per column: bin row of the template pixel in dtRow_
    Span<std::uint8_t> costRing_{};      // per-pixel costs of the rows in the window
    Span<std::uint16_t> colSums_{};      // window column sums per disparity
    Span<std::uint16_t> winSums_{};      // window sums per disparity for the current row
    Span<std::int32_t> bestCost_{};      // per column: best and second-best window sums
    Span<std::int32_t> secondCost_{};
    Span<std::int16_t> bestIndex_{};
    Span<std::int32_t> rlCost_{};        // per right column: best sum seen from the right
    Span<std::int16_t> rlDisparity_{};   // per right column: its disparity (whole px)
};

}  // namespace vtm::stereo
