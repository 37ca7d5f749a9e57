// boundByGround (vtm/terrain/ground_bound.hpp).
#include "vtm/terrain/ground_bound.hpp"

#include "vtm/core/math.hpp"

namespace vtm::terrain {

Status boundByGround(const RectifiedGeometry& geometry, double plane_z_site_m, std::int32_t window_min_px,
                     std::int32_t window_max_px, const ImageView<std::int16_t>& disparity_px16,
                     std::int32_t& dropped) noexcept {
    dropped = 0;
    VTM_RETURN_IF_ERROR(geometry.validate());
    if (!math::isFinite(plane_z_site_m)) {
        return Status(StatusCode::kInvalidArgument, "boundByGround: plane_z_site_m is not finite");
    }
    if (window_min_px > window_max_px) {
        return Status(StatusCode::kInvalidArgument, "boundByGround: window_min_px is above window_max_px",
                      window_min_px);
    }
    if (!disparity_px16.valid()) {
        return Status(StatusCode::kInvalidArgument, "boundByGround: disparity_px16 is empty");
    }
    const RectifiedGeometry& g = geometry;
    const double height = plane_z_site_m - g.left_centre_site_m.z();  // centre above the plane
    const double c0 = g.cx_left_px - g.cx_right_px;
    const Vec3 down_rect = g.R_site_from_rect.transpose() * Vec3(0.0, 0.0, 1.0);  // site down in the rectified frame
    for (std::int32_t y = 0; y < disparity_px16.height(); ++y) {
        std::int16_t* row = disparity_px16.row(y);
        const double ry = (static_cast<double>(y) - g.cy_px) / g.fy_px;
        for (std::int32_t x = 0; x < disparity_px16.width(); ++x) {
            if (row[x] == kNoDisparity) {
                continue;
            }
            // Ray (rx, ry, 1) in the rectified frame; its downward component per unit depth.
            const double rx = (static_cast<double>(x) - g.cx_left_px) / g.fx_px;
            const double down = rx * down_rect.x() + ry * down_rect.y() + down_rect.z();
            if (!(down > 1e-9) || !(height > 0.0)) {
                continue;  // the ray never reaches the plane: no bound
            }
            const double d_plane = g.fx_px * g.baseline_m * down / height + c0;  // Z_p = height / down
            const bool outside = g.baseline_m > 0.0 ? d_plane > static_cast<double>(window_max_px) + 1.0
                                                    : d_plane < static_cast<double>(window_min_px) - 1.0;
            if (outside) {
                row[x] = kNoDisparity;
                ++dropped;
            }
        }
    }
    return Status::ok();
}

}  // namespace vtm::terrain
