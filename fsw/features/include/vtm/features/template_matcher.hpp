// Guided template matching: each feature of image A is searched in image B only inside
// the region that odometry and a range interval predict, coarse to fine with normalised
// correlation (NCC), then checked by matching back from B to A (docs/features.md).
//
// Geometry (shared with fsw/motion and fsw/rectify): cameras A and B are
// vtm::CameraModel's, each in its own reference frame; X_b = R_b_from_a X_a + t_b_from_a_m.
// A feature's range is the distance along A's back-projected ray from the ray's origin.
//
// Per feature (all bounded, see the constants below):
//  1. Region: A's ray at kRaySamples ranges, uniform in 1/range over [range_min_m,
//     range_max_m], projected into B (samples that do not project are dropped): a polyline,
//     widened by margin_px; clipped to B's image.
//  2. Coarse search: every pixel of the region at the coarsest usable pyramid level (2x2
//     averaging, pyramid_levels halvings; a level is usable when the template fits
//     around the feature), at most kMaxCoarseCandidates positions in raster order.
//  3. Refinement at each finer level: +-kRefineRadius px around the position the coarser
//     level predicts; at full resolution a parabola through the NCC in x and in y gives the
//     subpixel position (vertex clamped to +-0.5 px).
//  4. Mutual check: B's point is searched back in A by the same steps with the inverse pose
//     and B's ray (ranges widened by the baseline); the result must lie within
//     mutual_tolerance_px of the feature.
// NCC is computed from exact integer sums with one correctly rounded sqrt: the same bits
// on every target. Pyramids live in the workspace and are rebuilt by every match() call.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/forstner.hpp"

namespace vtm::features {

constexpr std::int32_t kMaxPyramidLevels = 4;
constexpr std::int32_t kRaySamples = 33;               // range samples along A's ray
constexpr std::int32_t kMaxCoarseCandidates = 16384;   // NCC positions per feature at the coarse level
constexpr std::int32_t kRefineRadius = 2;              // +-px searched at each finer level

// The search region in B for a feature of A.
struct MatchPrediction {
    const CameraModel* model_a = nullptr;
    const CameraModel* model_b = nullptr;
    Mat3 R_b_from_a = Mat3::Identity();
    Vec3 t_b_from_a_m = Vec3::Zero();                 // from odometry
    double range_min_m = 1.0, range_max_m = 100.0;    // along A's ray; 0 < min < max, finite
    double margin_px = 40.0;                          // odometry uncertainty around the predicted segment, >= 0
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
    [[nodiscard]] Status validate() const noexcept;
};

// Every attempted feature ends in exactly one of no_region, low_score, not_mutual, matched.
struct MatchStats {
    std::int32_t attempted = 0, no_region = 0, low_score = 0, not_mutual = 0, matched = 0;
};

class TemplateMatcher {
public:
    // Arena bytes init() takes (both pyramids), 0 for an invalid configuration.
    [[nodiscard]] static std::size_t workspaceBytes(const MatcherConfig& config) noexcept;
    [[nodiscard]] Status init(const MatcherConfig& config, Arena& arena) noexcept;
    // Matches features_a (found in image_a) into image_b. Errors (out.count = 0):
    // kNotInitialized; kInvalidArgument: an empty image, a null model, features_a.count
    // outside 0..kMaxFeatures, range_min_m <= 0, range_min_m >= range_max_m, a non-finite
    // range or margin, margin_px < 0; kSizeMismatch: an image over the capacity, or a
    // model whose width_px/height_px differ from its image. A feature without a match is
    // not an error: it is counted in stats.
    [[nodiscard]] Status match(const ImageView<const std::uint8_t>& image_a,
                               const ImageView<const std::uint8_t>& image_b, const FeatureSet& features_a,
                               const MatchPrediction& prediction, MatchSet& out,
                               MatchStats* stats = nullptr) noexcept;

    [[nodiscard]] const MatcherConfig& config() const noexcept { return config_; }

    // Level 0 is the caller's image; levels 1..pyramid_levels live in the workspace.
    struct Pyramid {
        ImageView<const std::uint8_t> level[kMaxPyramidLevels + 1];
        std::int32_t levels = 0;  // usable halvings (images at least template_window wide/high)
    };

private:
    void buildPyramid(const ImageView<const std::uint8_t>& image, Span<std::uint8_t> storage,
                      Pyramid& pyramid) const noexcept;

    MatcherConfig config_{};
    bool initialized_ = false;
    Span<std::uint8_t> storageA_{};
    Span<std::uint8_t> storageB_{};
};

}  // namespace vtm::features
