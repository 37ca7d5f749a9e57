// Which pixels of image A image B can see, predicted from odometry and a ground-plane prior
// (a rover stands on the terrain it images and knows its camera's height above it).
//
// Every pixel's ray in A gets a predicted range: where it meets a level ground plane
// camera_height_m below A's projection centre (site "up" given in A's frame), clamped to
// [range_min_m, range_max_m]; a ray at or above the horizon gets range_max_m. The pixel
// is visible when that point projects into B, at least margin_px inside B's image. Used to
// keep Förstner features on the part of A that B shares (features elsewhere can never be
// matched and would take the grid's places). The prediction is coarse on purpose: rocks and
// slopes change real ranges, so callers keep a margin.
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/template_matcher.hpp"

namespace vtm::features {

struct VisibilityPrior {
    Vec3 up_a = Vec3::Zero();       // the site's up direction in A's reference frame (unit within 1e-6 .. normalised)
    double camera_height_m = 1.9;   // A's projection centre above the ground plane, > 0
    double margin_px = 16.0;        // >= 0: inside B by at least this much
    std::int32_t stride_px = 8;     // the prediction is made every stride_px pixels (1..64), blocks filled
};

// mask: A's size (pair.model_a's width_px x height_px), written 1 (visible) / 0. Uses
// prediction's pair (models, b_from_a) and range interval. kInvalidArgument naming the input
// (bad ranges, zero up vector, height <= 0, stride out of range);
// kSizeMismatch for a mask of another size. Returns the visible pixel count in `visible`.
[[nodiscard]] Status predictVisibility(const MatchPrediction& prediction, const VisibilityPrior& prior,
                                       const ImageView<std::uint8_t>& mask, std::int64_t& visible) noexcept;

}  // namespace vtm::features
