// Guided template matching: each feature of image A is searched in image B only inside
// the region that odometry and a range interval predict, coarse to fine with normalised
// correlation (NCC), then checked by matching back from B to A (docs/features.md).
//
// Geometry (shared with fsw/motion and fsw/rectify): a vtm::CameraPair (vtm/core/pose.hpp):
// cameras A and B, each in its own reference frame, and b_from_a: X_b = R X_a + t_m.
// A feature's range is the distance along A's back-projected ray from the ray's origin.
//
// Per feature (all bounded, see the constants below):
//  1. Region: A's ray over [range_min_m, range_max_m] projected into B: the part whose
//     image meets B's image widened by margin_px (found by a scan of 129 points), sampled
//     at kRaySamples points evenly spaced along its image (a projective parameter: exact
//     for a pinhole), a polyline widened by margin_px, clipped to B's image.
//  2. Warps: at each sample the local affine map M from A-pixel offsets to B-pixel
//     offsets induced by a plane through the sample's 3D point (M = J_b J_a^-1, from
//     projectPoint of the point and two points 1 % of the range away in the plane):
//     the terrain plane (prediction.surface_normal_a) and the plane perpendicular to A's
//     ray; without a normal only the latter. A's template is pre-warped into B's geometry,
//     T(u) = A(a + M^-1 u) (bilinear, weights in 1/256), at each pyramid level.
//  3. Coarse search: the region at the coarsest usable pyramid level (2x2 averaging,
//     pyramid_levels halvings; usable when the template fits around the feature); each
//     position is scored with the templates of its nearest ray sample (both warps, the
//     best counts). A region with more than kMaxCoarseCandidates positions in its box is
//     searched on the smallest stride s that fits (all of it, never cut off), and the
//     best position then re-searched within +-s at the same level.
//  4. Refinement at each finer level: +-kRefineRadius px around the prediction, with the
//     winning warp of the nearest sample; at full resolution a 2D quadratic through the
//     3x3 NCC neighbourhood gives the subpixel position (vertex clamped to +-0.5 px).
//  5. Affine refinement (refine_affine): Lucas-Kanade over position, a 2x2 affine map and
//     gain/offset on a kAffineWindow window, started from the winning warp
//     (affine_refine.hpp); a fit that fails, moves more than affine.max_shift_px or ends
//     below affine.min_score drops the match.
//     Steps 5 and 6 run for at most max_verified features of a call, the best forward
//     scores (a bound on the work for any content).
//  6. Mutual check: B's point is searched back in A by the same steps with the inverse
//     pose, B's ray (ranges widened by the baseline) and the normal rotated into B; the
//     result must lie within mutual_tolerance_px of the feature.
// NCC is computed from exact integer sums with one correctly rounded sqrt: the same bits
// on every target. Pyramids and the template bank live in the workspace.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/affine_refine.hpp"
#include "vtm/features/forstner.hpp"

namespace vtm::features {

constexpr std::int32_t kMaxPyramidLevels = 4;
constexpr std::int32_t kRaySamples = 33;               // samples along the image of A's ray
constexpr std::int32_t kMaxCoarseCandidates = 16384;   // grid positions per region box (else strided)
constexpr std::int32_t kRefineRadius = 2;              // +-px searched at each finer level

// The search region in B for a feature of A.
struct MatchPrediction {
    CameraPair pair{};                                // models and b_from_a (from odometry)
    double range_min_m = 1.0, range_max_m = 100.0;    // along A's ray; 0 < min < max, finite
    double margin_px = 40.0;                          // odometry uncertainty around the predicted segment, >= 0
    // Unit normal of the local terrain (site "up") in A's reference frame, from the
    // attitude; templates are warped for this plane. Zero = unknown: the plane
    // perpendicular to A's ray (fronto-parallel) is used. Finite; zero or norm 0.5..2.
    Vec3 surface_normal_a = Vec3::Zero();
};

// pixel_a: the feature's (subpixel) position in A; pixel_b: its match in B (subpixel);
// score: NCC at the match, -1..1; feature_index: index into the FeatureSet.
struct Match {
    Vec2 pixel_a = Vec2::Zero();
    Vec2 pixel_b = Vec2::Zero();
    float score = 0.f;
    std::int32_t feature_index = -1;
};

struct MatchSet {
    Match items[kMaxFeatures];
    std::int32_t count = 0;
};

struct MatcherConfig {
    std::int32_t max_width = 1024, max_height = 1024;  // capacity of both images, 1..4096
    std::int32_t template_window = 11;                 // odd, 3..31, at every level
    std::int32_t pyramid_levels = 2;                   // coarse search at 1 / 2^levels; 0..kMaxPyramidLevels
    float min_score = 0.8f;                            // NCC of an accepted match, [-1, 1]
    float mutual_tolerance_px = 1.0f;                  // B->A match must return within this, > 0
    // Step 5 (before the mutual check): every match refined by affine Lucas-Kanade
    // (affine_refine.hpp) from the winning template's warp; a fit that is not accepted
    // drops the match (not_refined).
    bool refine_affine = true;
    AffineRefineConfig affine{};
    // Steps 5 and 6 (the affine refinement and the backward search) for at most this many
    // features of one call: those whose forward search scored highest (the lower feature
    // index first among equal scores); the other passing features end as `unverified`.
    // Bounds the verification work per call for any image content (issue 22 item 5: an
    // image where every forward search passes min_score costs twice the searches of one
    // where a fifth do). 1..kMaxFeatures; kMaxFeatures: every passing feature is verified.
    std::int32_t max_verified = kMaxFeatures;
    // This configuration with another capacity (what a module that states the capacity once
    // for several sub-modules hands down).
    [[nodiscard]] MatcherConfig withCapacity(std::int32_t width, std::int32_t height) const noexcept {
        MatcherConfig c = *this;
        c.max_width = width;
        c.max_height = height;
        return c;
    }
    [[nodiscard]] Status validate() const noexcept;
};

// Every attempted feature ends in exactly one of no_region, low_score, unverified,
// not_refined, not_mutual, matched.
struct MatchStats {
    std::int32_t attempted = 0, no_region = 0, low_score = 0, not_refined = 0, not_mutual = 0, matched = 0;
    std::int32_t unverified = 0;  // passed min_score but not among the max_verified best
};

namespace detail {
class PolylineScan;
struct ForwardMatch;
}  // namespace detail

class TemplateMatcher {
public:
    // Arena bytes init() takes (both pyramids, the template bank), 0 for an invalid configuration.
    [[nodiscard]] static std::size_t workspaceBytes(const MatcherConfig& config) noexcept;
    [[nodiscard]] Status init(const MatcherConfig& config, Arena& arena) noexcept;
    // Matches features_a (found in image_a) into image_b. Errors (out.count = 0):
    // kNotInitialized; kInvalidArgument: an empty image, features_a.count
    // outside 0..kMaxFeatures, range_min_m <= 0, range_min_m >= range_max_m, a non-finite
    // range or margin, margin_px < 0, surface_normal_a neither zero nor of norm 0.5..2
    // (it is normalised); kSizeMismatch: an image over the capacity, or a
    // pair model whose width_px/height_px differ from its image. A feature without a match is
    // not an error: it is counted in stats.
    [[nodiscard]] Status match(const ImageView<const std::uint8_t>& image_a,
                               const ImageView<const std::uint8_t>& image_b, const FeatureSet& features_a,
                               const MatchPrediction& prediction, MatchSet& out,
                               MatchStats* stats = nullptr) noexcept;

    // match() in two steps, for a caller that searches many features of one image pair,
    // each with a prediction of its own (fsw/tiepoints' inter-stereo search): prepare()
    // builds both images' pyramids once; matchPrepared() then matches against them and
    // gives bit for bit what match() gives with the same images. The images must stay
    // valid and unchanged until the next prepare() or match() (match() prepares too).
    // prepare() errors: kNotInitialized; kInvalidArgument: an empty image; kSizeMismatch:
    // an image over the capacity. matchPrepared() errors (out.count = 0):
    // kNotInitialized also when nothing has been prepared; the rest as match().
    [[nodiscard]] Status prepare(const ImageView<const std::uint8_t>& image_a,
                                 const ImageView<const std::uint8_t>& image_b) noexcept;
    [[nodiscard]] Status matchPrepared(const FeatureSet& features_a, const MatchPrediction& prediction,
                                       MatchSet& out, MatchStats* stats = nullptr) noexcept;

    [[nodiscard]] const MatcherConfig& config() const noexcept { return config_; }

    // Level 0 is the caller's image; levels 1..pyramid_levels live in the workspace.
    struct Pyramid {
        ImageView<const std::uint8_t> level[kMaxPyramidLevels + 1];
        std::int32_t levels = 0;  // usable halvings (images at least template_window wide/high)
        // Level float_level (= pyramid_levels when all of them were built, else -1: none) as
        // floats in the workspace, for the coarse search's products (see the .cpp).
        ImageView<const float> coarse_float{};
        std::int32_t float_level = -1;
    };

private:
    void buildPyramid(const ImageView<const std::uint8_t>& image, Span<std::uint8_t> storage, Span<float> floats,
                      Pyramid& pyramid) const noexcept;

    MatcherConfig config_{};
    bool initialized_ = false;
    bool prepared_ = false;
    Pyramid pyramidA_{};  // of the prepared images (level 0: the caller's)
    Pyramid pyramidB_{};
    Span<std::uint8_t> storageA_{};
    Span<std::uint8_t> storageB_{};
    Span<float> floatA_{};  // the coarsest level of each pyramid as floats
    Span<float> floatB_{};
    Span<std::uint16_t> bank_{};  // warped templates of one search (see the .cpp)
    Span<float> floatBank_{};     // the coarse templates as floats
    // The coarse scan's region test (private src/polyline.hpp), in the arena rather than
    // on the stack (about 1.4 KB).
    detail::PolylineScan* scan_ = nullptr;
    Span<std::uint32_t> columnSum_{};    // the coarse search's column sums (see the .cpp)
    Span<std::uint32_t> columnSumSq_{};
    // The forward search's result of every feature of a call (kMaxFeatures, arena), kept
    // until the verification step has chosen the max_verified best.
    detail::ForwardMatch* forward_ = nullptr;
};

}  // namespace vtm::features
