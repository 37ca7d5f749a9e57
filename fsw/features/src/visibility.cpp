#include "vtm/features/visibility.hpp"

#include <cmath>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/math.hpp"

namespace vtm::features {
namespace {

Status checkVisibilityInputs(const MatchPrediction& p, const VisibilityPrior& prior,
                             const ImageView<std::uint8_t>& mask) noexcept {
    if (!(p.range_min_m > 0.0) || !(p.range_max_m > p.range_min_m) || !math::isFinite(p.range_max_m)) {
        return Status(StatusCode::kInvalidArgument, "predictVisibility: need 0 < range_min_m < range_max_m, finite");
    }
    const double n = prior.up_a.norm();
    if (!(n > 0.5) || !(n < 2.0)) {
        return Status(StatusCode::kInvalidArgument, "predictVisibility: up_a must be a unit vector");
    }
    if (!(prior.camera_height_m > 0.0) || !math::isFinite(prior.camera_height_m) || !(prior.margin_px >= 0.0) ||
        !math::isFinite(prior.margin_px)) {
        return Status(StatusCode::kInvalidArgument, "predictVisibility: camera_height_m must be > 0 and margin_px >= 0");
    }
    if (prior.stride_px < 1 || prior.stride_px > 64) {
        return Status(StatusCode::kInvalidArgument, "predictVisibility: stride_px must be 1..64", prior.stride_px);
    }
    if (mask.data() == nullptr || mask.width() != p.pair.model_a.width_px || mask.height() != p.pair.model_a.height_px) {
        return Status(StatusCode::kSizeMismatch, "predictVisibility: mask is not pair.model_a's size", mask.width());
    }
    return Status::ok();
}

// The ground-prior point of A's ray through `pixel` seen in B: true when inside B's image
// by margin.
bool seenByB(const MatchPrediction& p, const VisibilityPrior& prior, const Vec3& up, const Vec2& pixel) noexcept {
    CameraRay ray;
    if (!backProjectPixel(p.pair.model_a, pixel, ray).isOk()) {
        return false;
    }
    const double down = -ray.direction.dot(up);  // > 0: the ray descends
    double range = p.range_max_m;
    if (down > 0.0) {
        range = prior.camera_height_m / down;
        range = (range < p.range_min_m) ? p.range_min_m : ((range > p.range_max_m) ? p.range_max_m : range);
    }
    const Vec3 x_b = p.pair.b_from_a.R * (ray.origin_m + range * ray.direction) + p.pair.b_from_a.t_m;
    Vec2 px;
    if (!projectPoint(p.pair.model_b, x_b, px).isOk()) {
        return false;
    }
    const double m = prior.margin_px;
    return px.x() >= m - 0.5 && px.y() >= m - 0.5 && px.x() <= p.pair.model_b.width_px - 0.5 - m &&
           px.y() <= p.pair.model_b.height_px - 0.5 - m;
}

}  // namespace

Status predictVisibility(const MatchPrediction& prediction, const VisibilityPrior& prior,
                         const ImageView<std::uint8_t>& mask, std::int64_t& visible) noexcept {
    visible = 0;
    VTM_RETURN_IF_ERROR(checkVisibilityInputs(prediction, prior, mask));
    const Vec3 up = prior.up_a / prior.up_a.norm();
    const std::int32_t s = prior.stride_px;
    for (std::int32_t by = 0; by < mask.height(); by += s) {
        for (std::int32_t bx = 0; bx < mask.width(); bx += s) {
            const std::int32_t ex = (bx + s < mask.width()) ? bx + s : mask.width();
            const std::int32_t ey = (by + s < mask.height()) ? by + s : mask.height();
            const Vec2 centre(0.5 * static_cast<double>(bx + ex - 1), 0.5 * static_cast<double>(by + ey - 1));
            const std::uint8_t v = seenByB(prediction, prior, up, centre) ? 1U : 0U;
            for (std::int32_t y = by; y < ey; ++y) {
                std::uint8_t* row = mask.row(y);
                for (std::int32_t x = bx; x < ex; ++x) {
                    row[x] = v;
                }
            }
            visible += (v != 0U) ? static_cast<std::int64_t>(ex - bx) * (ey - by) : 0;
        }
    }
    return Status::ok();
}

}  // namespace vtm::features
