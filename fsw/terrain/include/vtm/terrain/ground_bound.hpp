// The ground bound on a rectified pair's disparities (docs/terrain.md): along a ray that
// points down, the terrain is hit no farther than a level plane it does not go below (the
// ground under the rover lowered by the relief the map allows), which bounds the ray's
// depth and so its disparity. A disparity searched in a window that this bound puts beyond
// the window cannot be the true one: it is a wrong match and is dropped.
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::terrain {

// For every pixel (x, y) of the left rectified image with a disparity: its ray
// (rx, ry, 1) = ((x - cx_left) / fx, (y - cy) / fy, 1) in the rectified frame, its
// downward component per unit depth down = (rx, ry, 1) . (R_site_from_rect^T (0, 0, 1));
// the plane lies height = plane_z_site_m - left_centre_site_m.z below the left centre
// (site z is down). When down > 1e-9 and height > 0, the ray meets the plane at depth
// Z_p = height / down, so the true depth is at most Z_p and the true disparity lies
// beyond d_p = fx b / Z_p + (cx_left - cx_right) = fx b down / height + (cx_left - cx_right)
// (above it for b > 0, below it for b < 0). The disparity is set to kNoDisparity when d_p
// lies beyond the window by more than a pixel: d_p > window_max_px + 1 (b > 0) or
// d_p < window_min_px - 1 (b < 0). Rays that never reach the plane are not bounded.
// `dropped` = the pixels set to kNoDisparity here.
// kInvalidArgument naming the input: the geometry (its validate() reason), a plane not
// finite, window_min_px > window_max_px, an empty disparity image; nothing is changed then.
[[nodiscard]] Status boundByGround(const RectifiedGeometry& geometry, double plane_z_site_m,
                                   std::int32_t window_min_px, std::int32_t window_max_px,
                                   const ImageView<std::int16_t>& disparity_px16, std::int32_t& dropped) noexcept;

}  // namespace vtm::terrain
