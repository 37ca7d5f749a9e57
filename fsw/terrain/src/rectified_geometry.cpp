// rectifiedGeometry (vtm/terrain/rectified_geometry.hpp).
#include "vtm/terrain/rectified_geometry.hpp"

namespace vtm::terrain {

Status rectifiedGeometry(const rectify::RectifiedPair& pair, const RigidPose& site_from_cam_a,
                         RectifiedGeometry& out) noexcept {
    RectifiedGeometry g;
    g.fx_px = pair.model_a.fx_px;
    g.fy_px = pair.model_a.fy_px;
    g.cx_left_px = pair.model_a.cx_px;
    g.cx_right_px = pair.model_b.cx_px;
    g.cy_px = pair.model_a.cy_px;
    g.baseline_m = pair.centre_b_rect_m.x();
    g.R_site_from_rect = site_from_cam_a.R * pair.R_rect_from_a.transpose();
    g.left_centre_site_m = site_from_cam_a.t_m + site_from_cam_a.R * pair.centre_a_ref_m;
    VTM_RETURN_IF_ERROR(g.validate());
    out = g;
    return Status::ok();
}

}  // namespace vtm::terrain
