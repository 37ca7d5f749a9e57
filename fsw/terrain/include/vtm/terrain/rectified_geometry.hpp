// The rectified pair of fsw/rectify placed in the site frame, as triangulation needs it
// (terrain::RectifiedGeometry, triangulation.hpp). docs/terrain.md.
#pragma once

#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::terrain {

// From the rectifier's output and camera A's site pose (X_site = R X_a + t_m):
//   fx, fy, cy = pair.model_a's; cx_left = pair.model_a.cx_px, cx_right = pair.model_b.cx_px;
//   baseline_m = pair.centre_b_rect_m.x() (signed);
//   R_site_from_rect = site_from_cam_a.R * pair.R_rect_from_a^T;
//   left_centre_site_m = site_from_cam_a.t_m + site_from_cam_a.R * pair.centre_a_ref_m.
// kInvalidArgument with RectifiedGeometry::validate()'s reason (non-finite numbers, a
// zero baseline, a rotation that is not one); `out` is written only on success.
[[nodiscard]] Status rectifiedGeometry(const rectify::RectifiedPair& pair, const RigidPose& site_from_cam_a,
                                       RectifiedGeometry& out) noexcept;

}  // namespace vtm::terrain
