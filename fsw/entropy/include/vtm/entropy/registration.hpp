// Registration of two images of different modality through their local-entropy images
// (paper §5; Olson, CVPR 2001), as a flight module.
//
// The answer is a similarity transform from image 1 to image 2, in pixels of each image
// (origin at the centre of the top-left pixel, x right, y down):
//
//   p2 = s R(theta) (p1 - c1) + c2 + t,     R(theta) = [cos -sin; sin cos]
//
// with c1, c2 the image centres ((width - 1) / 2, (height - 1) / 2); theta turns +x
// towards +y (clockwise on the screen), t is where image 1's centre lands relative to
// image 2's centre. As a 2x3 matrix G: [x2 y2]^T = G [x1 y1 1]^T.
//
// Method (docs/entropy.md):
//  1. Each image equalised (over the whole image, or each pixel's rank in the square of
//     equalise_radius_px around it), then its entropy image (LocalEntropy); or the grey
//     levels themselves with Representation::kIntensity, the same search on intensities.
//     Then pyramids of `levels` levels by 2x2 averaging (vtm::halveImage).
//  2. Coarse search on the coarsest level: every rotation and scale of a grid spaced about
//     one coarse pixel of motion at the image's edge, within the request's ranges; for each,
//     image 2's level warped once (bilinear, fixed point) onto image 1's grid widened by the
//     shift range, then every integer shift scored by normalised correlation over the
//     overlap (exact integer sums). The `candidates` best mutually separated peaks are kept.
//  3. Each candidate refined level by level down to full resolution: a pattern search over
//     (theta, log s, tx, ty) with steps of one pixel of motion at that level, halved when no
//     neighbour improves, never leaving the request's ranges; then a parabola through the
//     scores at -h, 0, +h per parameter.
//  4. Confidence: the best peak's NCC and the NCC of the best peak separated from it (its
//     corners more than 2 coarse pixels away). Refusals: kNoData when no candidate overlaps
//     image 1 by min_overlap or the peak is below min_ncc; kDegenerate when an image has no
//     contrast at the coarse level or the second peak reaches max_peak_ratio of the best.
//
// Memory: the two pyramids, the entropy workspace and one warped coarse level, from an
// Arena at init() (workspaceBytes(config)); registerImages() never allocates. Work is
// bounded by the configuration (grid capacities, candidates, rounds), not by the content.
// Deterministic: integer sums, double geometry with + - * / and vtm::math sin/cos/exp/log.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/entropy/local_entropy.hpp"

namespace vtm::entropy {

constexpr std::int32_t kMaxCandidates = 16;
constexpr std::int32_t kMaxLevels = 6;
constexpr std::int32_t kMaxEqualiseRadius = 63;  // RegistrationConfig::equalise_radius_px

using Mat23 = Eigen::Matrix<double, 2, 3>;

// What the images are matched on.
enum class Representation : std::uint8_t {
    kEntropy = 0,    // local-entropy images (different sensors)
    kIntensity = 1,  // the grey levels themselves (same sensor; the peer of the entropy images)
};

struct RegistrationConfig {
    // Capacity of either image, pixels: 16..4096.
    std::int32_t max_width = 512;
    std::int32_t max_height = 512;
    // The entropy images (its max_width / max_height are taken from the fields above).
    EntropyConfig entropy{};
    Representation representation = Representation::kEntropy;
    // Histogram-equalise each image before its entropy image (integer CDF table): the
    // bins then cut every sensor's own grey-level distribution into equal shares, so a
    // low-contrast sensor (thermal infrared) uses all of them. Ignored for kIntensity.
    bool equalise = true;
    // Where equalisation looks: 0 over the whole image (histogram equalisation); r > 0
    // within the (2 r + 1)^2 square around each pixel (its rank among its neighbours,
    // 1..kMaxEqualiseRadius), which also takes out a response that varies across the image. 12: measured
    // on the SRIF optical-infrared pairs, 95 % registered against 59.5 % with the whole
    // image (docs/entropy.md).
    std::int32_t equalise_radius_px = 12;
    // Grey levels at or below this are no data (-1: none), e.g. the black fill around a
    // rotated or cropped product: such pixels, and (entropy) every pixel whose window
    // reaches one, take no part in equalisation or scores. -1..254.
    std::int32_t fill_max_grey = -1;
    // Pyramid levels, 1..kMaxLevels; the coarse search runs on level levels - 1, whose
    // images must be at least 8 x 8.
    std::int32_t levels = 3;
    // Coarse grid capacities: rotations, scales, and integer shifts per axis (odd). A
    // request wider than the capacity gets a coarser grid (the step grows), never more work.
    std::int32_t max_angle_steps = 128;  // 1..1024
    std::int32_t max_scale_steps = 16;   // 1..256
    std::int32_t max_shift_steps = 33;   // odd, 1..129
    std::int32_t candidates = 4;         // 1..kMaxCandidates peaks refined
    std::int32_t refine_rounds = 8;      // 1..64 pattern-search rounds per level
    // Least overlap of image 1 with image 2, fraction of image 1's area: (0, 1].
    double min_overlap = 0.25;
    // Refusal thresholds: best NCC below min_ncc (0..1) -> kNoData; second separated peak
    // at or above max_peak_ratio (0..1] of the best -> kDegenerate.
    double min_ncc = 0.2;
    double max_peak_ratio = 0.95;

    // kOk, or kInvalidConfig naming the field ("registration.levels: ...",
    // "entropy.window: ..."), integer value in detail.
    [[nodiscard]] Status validate() const noexcept;
};

// The search range of one registration.
struct RegistrationRequest {
    double angle_min_rad = -0.5236;  // -30 deg; angle_max_rad - angle_min_rad <= 2 pi
    double angle_max_rad = 0.5236;
    double scale_min = 0.8;          // 0.125 <= scale_min <= scale_max <= 8
    double scale_max = 1.25;
    // Expected t (px of image 2) and the half-width of the square searched around it.
    double shift_x_px = 0.0;
    double shift_y_px = 0.0;
    double shift_range_px = 16.0;    // 0..4096
};

struct Registration {
    Mat23 image2_from_image1 = Mat23::Zero();  // [x2 y2]^T = G [x1 y1 1]^T, pixels
    double angle_rad = 0.0;
    double scale = 0.0;
    double shift_x_px = 0.0;      // t: image 1's centre in image 2 minus image 2's centre
    double shift_y_px = 0.0;
    double ncc = -1.0;            // best peak's NCC at full resolution
    double second_ncc = -1.0;     // best peak separated from it (-1: none)
    double overlap = 0.0;         // fraction of image 1 that maps into image 2
    std::int32_t coarse_scored = 0;  // coarse transforms scored
    std::int32_t fine_scored = 0;    // refinement evaluations
};

class EntropyRegistration {
public:
    // Bytes of arena for this configuration (every buffer and its padding), 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const RegistrationConfig& config) noexcept;

    // Validates the config and carves the workspace. kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const RegistrationConfig& config, Arena& arena) noexcept;

    // Registers image 1 to image 2 (8-bit grey; sizes may differ, each within capacity and
    // at least 8 px at the coarse level). `result` is filled whenever a best peak exists,
    // also on kNoData / kDegenerate (for diagnosis). Errors: kNotInitialized;
    // kInvalidArgument (empty view, request out of range, naming the field); kSizeMismatch
    // (an image above capacity or too small for `levels`); kDegenerate (no contrast;
    // ambiguous peak); kNoData (overlap or peak too small). Never allocates.
    [[nodiscard]] Status registerImages(const ImageView<const std::uint8_t>& image1,
                                        const ImageView<const std::uint8_t>& image2,
                                        const RegistrationRequest& request, Registration& result) noexcept;

    // Level-0 images the last registerImages() matched (entropy or intensity): for tests,
    // pictures and peers. Empty before the first call.
    [[nodiscard]] ImageView<const std::uint8_t> matchedImage1() const noexcept;
    [[nodiscard]] ImageView<const std::uint8_t> matchedImage2() const noexcept;

    // Normalised correlation of the level-`level` images under a transform given as
    // angle, scale, shift (Registration's parameters), and the overlap fraction it had;
    // -1 when the overlap is below min_overlap. For tests and peers.
    [[nodiscard]] double scoreAt(std::int32_t level, double angle_rad, double scale, double shift_x_px,
                                 double shift_y_px, double* overlap = nullptr) const noexcept;

    [[nodiscard]] const RegistrationConfig& config() const noexcept { return config_; }

private:
    struct Params {
        double angle = 0.0;
        double logScale = 0.0;
        double tx = 0.0;
        double ty = 0.0;
        double score = -1.0;
    };
    [[nodiscard]] Status prepare(const ImageView<const std::uint8_t>& image1,
                                 const ImageView<const std::uint8_t>& image2) noexcept;
    [[nodiscard]] Status prepareOne(std::int32_t index, const ImageView<const std::uint8_t>& image) noexcept;
    void buildMask(std::int32_t index, const ImageView<const std::uint8_t>& image) noexcept;
    [[nodiscard]] Status coarseSearch(const RegistrationRequest& request, Registration& result) noexcept;
    void warpCoarse(double angle, double logScale, double tx0, double ty0, std::int32_t margin) noexcept;
    void scoreShifts(std::int32_t margin) noexcept;
    [[nodiscard]] double shiftNcc(std::int32_t ux, std::int32_t uy, std::int32_t margin, std::int64_t& n) const noexcept;
    void offerShiftPeaks(double angle, double logScale, double tx0, double ty0, std::int32_t margin) noexcept;
    void offerCandidate(const Params& p) noexcept;
    void refine(Params& p, Registration& result) const noexcept;
    void searchLevel(std::int32_t level, Params& p, double* steps, Registration& result) const noexcept;
    void fitParabolas(Params& p, const double* steps, Registration& result) const noexcept;
    [[nodiscard]] double score(std::int32_t level, const Params& p, double* overlap) const noexcept;
    [[nodiscard]] double cornerDistance(const Params& a, const Params& b) const noexcept;
    [[nodiscard]] Mat23 matrixOf(const Params& p) const noexcept;

    void clampToRequest(Params& p) const noexcept;

    RegistrationConfig config_{};
    RegistrationRequest request_{};  // of the registerImages() in progress
    bool initialized_ = false;
    LocalEntropy entropy_{};
    ImageView<std::uint8_t> levels1_[kMaxLevels]{};  // image 1's pyramid (views into the arena)
    ImageView<std::uint8_t> levels2_[kMaxLevels]{};
    Span<std::uint8_t> pyramid1_{};
    Span<std::uint8_t> pyramid2_{};
    Span<std::uint8_t> scratch_{};  // an equalised image before its entropy image; mask erosion
    Span<std::uint16_t> rankCounts_{};  // localRank()'s window counts
    ImageView<std::uint8_t> masks1_[kMaxLevels]{};  // 1 where image 1's level has data
    ImageView<std::uint8_t> masks2_[kMaxLevels]{};
    Span<std::uint8_t> maskPyramid1_{};
    Span<std::uint8_t> maskPyramid2_{};
    Span<std::int16_t> warp_{};  // coarse level of image 2 warped onto image 1's widened grid; -1 outside
    Span<double> shiftScores_{}; // NCC of every coarse shift of one rotation and scale
    std::int32_t warpStride_ = 0;
    std::int32_t candidateCount_ = 0;
    Params candidates_[kMaxCandidates]{};
    std::int32_t coarseScored_ = 0;
};

}  // namespace vtm::entropy
