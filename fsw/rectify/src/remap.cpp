// Point maps, fixed-point remap tables and bilinear resampling (vtm/rectify/rectifier.hpp).
//
// Table entry: the input position of a rectified pixel times 2^F, rounded to nearest
// (floor(p 2^F + 0.5)); a position whose rounded value falls outside
// [0, (size - 1) 2^F] on either axis is kOutsideInput. Resampling: integer part i and
// fraction f (F bits) per axis, weights (2^F - f, f), the four products summed in int32
// and rounded half up: (sum + 2^(2F-1)) >> 2F. The neighbour of the last column/row is
// itself (its weight is 0 there, as f = 0 on the edge).
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/rectify/rectifier.hpp"

namespace vtm::rectify {

const Rectifier::SideState& Rectifier::state(Side side) const noexcept {
    return sides_[side == Side::kA ? 0 : 1];
}

Status Rectifier::toInput(const SideState& side, const Vec2& rectified_px, Vec2& input_px) const noexcept {
    const Vec3 ray_rect((rectified_px.x() - side.cx_px) / fx_px_, (rectified_px.y() - cy_px_) / fy_px_, 1.0);
    const Vec3 point_ref = side.centre_ref_m + side.R_rect_from_ref.transpose() * ray_rect;
    return projectPoint(side.model, point_ref, input_px);
}

Status Rectifier::rectifyPixel(Side side, const Vec2& input_px, Vec2& rectified_px) const noexcept {
    if (!ready_) {
        return Status(StatusCode::kNotInitialized, "Rectifier.rectifyPixel: no successful compute()");
    }
    const SideState& s = state(side);
    CameraRay ray;
    VTM_RETURN_IF_ERROR(backProjectPixel(s.model, input_px, ray));
    const Vec3 d = s.R_rect_from_ref * ray.direction;
    if (!(d.z() > 0.0)) {
        return Status(StatusCode::kDegenerate, "Rectifier.rectifyPixel: ray behind the rectified image plane");
    }
    rectified_px = Vec2(fx_px_ * d.x() / d.z() + s.cx_px, fy_px_ * d.y() / d.z() + cy_px_);
    return Status::ok();
}

Status Rectifier::unrectifyPixel(Side side, const Vec2& rectified_px, Vec2& input_px) const noexcept {
    if (!ready_) {
        return Status(StatusCode::kNotInitialized, "Rectifier.unrectifyPixel: no successful compute()");
    }
    return toInput(state(side), rectified_px, input_px);
}

void Rectifier::buildTable(const SideState& side) const noexcept {
    const double scale = static_cast<double>(1 << fraction_bits_);
    const double max_x = static_cast<double>(side.model.width_px - 1) * scale;
    const double max_y = static_cast<double>(side.model.height_px - 1) * scale;
    std::int16_t* entry = side.table.data();
    for (std::int32_t y = 0; y < out_height_; ++y) {
        for (std::int32_t x = 0; x < out_width_; ++x) {
            Vec2 in_px = Vec2::Zero();
            const bool mapped =
                toInput(side, Vec2(static_cast<double>(x), static_cast<double>(y)), in_px).isOk();
            const double qx = math::floor(in_px.x() * scale + 0.5);  // no libm call on the 750
            const double qy = math::floor(in_px.y() * scale + 0.5);
            // NaN fails every comparison: outside.
            const bool inside = mapped && qx >= 0.0 && qx <= max_x && qy >= 0.0 && qy <= max_y;
            entry[0] = inside ? static_cast<std::int16_t>(qx) : kOutsideInput;
            entry[1] = inside ? static_cast<std::int16_t>(qy) : kOutsideInput;
            entry += 2;
        }
    }
}

Status Rectifier::tableEntry(Side side, std::int32_t x, std::int32_t y, std::int16_t& x_q,
                             std::int16_t& y_q) const noexcept {
    if (!ready_) {
        return Status(StatusCode::kNotInitialized, "Rectifier.tableEntry: no successful compute()");
    }
    if (x < 0 || y < 0 || x >= out_width_ || y >= out_height_) {
        return Status(StatusCode::kInvalidArgument, "Rectifier.tableEntry: pixel outside the rectified image",
                      x < 0 || x >= out_width_ ? x : y);
    }
    const std::size_t i = 2U * (static_cast<std::size_t>(y) * static_cast<std::size_t>(out_width_) +
                                static_cast<std::size_t>(x));
    x_q = state(side).table[i];
    y_q = state(side).table[i + 1U];
    return Status::ok();
}

namespace {

// One output row: bilinear interpolation of `input` at the table's positions.
void remapRow(const std::int16_t* entry, std::int32_t width, const ImageView<const std::uint8_t>& input,
              std::int32_t bits, std::uint8_t fill, std::uint8_t* out) noexcept {
    const std::int32_t one = 1 << bits;
    const std::int32_t mask = one - 1;
    const std::int32_t half = 1 << (2 * bits - 1);
    const std::int32_t last_x = input.width() - 1;
    const std::int32_t last_y = input.height() - 1;
    for (std::int32_t x = 0; x < width; ++x, entry += 2) {
        const std::int32_t qx = entry[0];
        const std::int32_t qy = entry[1];
        if (qx == kOutsideInput) {
            out[x] = fill;
            continue;
        }
        const std::int32_t ix = qx >> bits;  // qx >= 0: the table holds inside positions only
        const std::int32_t iy = qy >> bits;
        const std::int32_t fx = qx & mask;
        const std::int32_t fy = qy & mask;
        const std::int32_t ix1 = ix < last_x ? ix + 1 : ix;
        const std::uint8_t* r0 = input.row(iy);
        const std::uint8_t* r1 = input.row(iy < last_y ? iy + 1 : iy);
        const std::int32_t top = r0[ix] * (one - fx) + r0[ix1] * fx;
        const std::int32_t bottom = r1[ix] * (one - fx) + r1[ix1] * fx;
        out[x] = static_cast<std::uint8_t>((top * (one - fy) + bottom * fy + half) >> (2 * bits));
    }
}

}  // namespace

Status Rectifier::remap(Side side, const ImageView<const std::uint8_t>& input, const ImageView<std::uint8_t>& output,
                        std::uint8_t fill) const noexcept {
    if (!ready_) {
        return Status(StatusCode::kNotInitialized, "Rectifier.remap: no successful compute()");
    }
    if (!input.valid() || !output.valid()) {
        return Status(StatusCode::kInvalidArgument, "Rectifier.remap: empty or malformed image view");
    }
    const SideState& s = state(side);
    if (!input.sameSize(s.model.width_px, s.model.height_px)) {
        return Status(StatusCode::kSizeMismatch, "Rectifier.remap: input size differs from the camera model",
                      input.width());
    }
    if (!output.sameSize(out_width_, out_height_)) {
        return Status(StatusCode::kSizeMismatch, "Rectifier.remap: output size differs from the rectified size",
                      output.width());
    }
    for (std::int32_t y = 0; y < out_height_; ++y) {
        const std::int16_t* entry =
            s.table.data() + 2 * static_cast<std::ptrdiff_t>(y) * static_cast<std::ptrdiff_t>(out_width_);
        remapRow(entry, out_width_, input, fraction_bits_, fill, output.row(y));
    }
    return Status::ok();
}

}  // namespace vtm::rectify
