// Affine Lucas-Kanade refinement of one match (docs/features.md, "Affine refinement").
//
// NCC on a pixel grid with a parabola through its peak locates a match to a few tenths
// of a pixel; with the wide baselines' perspective distortion, 0.3-1 px (measured in
// docs/wide-baseline-evaluation.md). Motion refinement turns that error into pose error.
// This step refines the match by Gauss-Newton over eight parameters: B's position of the
// feature (2), the local affine map from A-pixel offsets to B-pixel offsets (4), and a
// photometric gain and offset (2), minimising
//     sum over the window (u, v) of [ B(b + W (u, v)) - (gain A(a + (u, v)) + offset) ]^2
// with A and B sampled bilinearly (in double) and B's gradient by central differences
// at +-0.5 px. The window is kAffineWindow x kAffineWindow around A's subpixel feature.
//
// Bounded: at most max_steps Gauss-Newton steps (8 x 8 Cholesky each), stopping early
// when a step moves the position by less than kAffineConvergence_px. No heap, no state:
// a free function over the caller's images. Only + - * / and sqrt: the same bits on
// every target.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"

namespace vtm::features {

constexpr std::int32_t kAffineWindow = 15;           // px, odd: the window of the fit
constexpr std::int32_t kAffineMaxSteps = 50;         // upper bound of AffineRefineConfig.max_steps
constexpr double kAffineConvergence_px = 1.0e-3;     // a step moving b less than this ends the fit

struct AffineRefineConfig {
    std::int32_t max_steps = 20;      // Gauss-Newton steps, 1..kAffineMaxSteps
    double max_shift_px = 2.0;        // the result may lie at most this far from the start, > 0
    float min_score = 0.7f;           // NCC of the fitted window at the result, [-1, 1]
    [[nodiscard]] Status validate() const noexcept;
};

// Why a fit was not accepted (kAccepted: it was).
enum class AffineOutcome : std::uint8_t {
    kAccepted,
    kLeftImage,    // the window (with the gradient's half pixel) left image A or B
    kSingular,     // flat texture: the normal equations are not positive definite
    kBadWarp,      // the affine map degenerated (area ratio outside 1/16..16 or an entry beyond +-8)
    kMovedTooFar,  // the result lies more than max_shift_px from the start
    kLowScore,     // the NCC of the fitted window is below min_score
};

struct AffineMatch {
    Vec2 pixel_b = Vec2::Zero();      // refined position in B of A's feature
    Mat2 warp = Mat2::Identity();     // refined map from A-pixel offsets to B-pixel offsets
    double gain = 1.0, offset = 0.0;  // B ~ gain A + offset over the window
    double score = -1.0;              // NCC of the two windows at the result
    std::int32_t steps = 0;           // Gauss-Newton steps taken
    AffineOutcome outcome = AffineOutcome::kLeftImage;
};

// Refines the match pixel_a (image_a) <-> pixel_b (image_b), starting from the affine map
// `warp` (e.g. the plane-induced warp of the template matcher). out.pixel_b holds the
// result only when out.outcome == kAccepted; otherwise the start. Errors:
// kInvalidConfig (config), kInvalidArgument: an empty image, a non-finite pixel or warp.
[[nodiscard]] Status refineAffine(const ImageView<const std::uint8_t>& image_a,
                                  const ImageView<const std::uint8_t>& image_b, const Vec2& pixel_a,
                                  const Vec2& pixel_b, const Mat2& warp, const AffineRefineConfig& config,
                                  AffineMatch& out) noexcept;

}  // namespace vtm::features
