// Linear reduction of camera models (vtm/rectify/linear_camera.hpp).
#include "vtm/rectify/linear_camera.hpp"

#include "vtm/core/math.hpp"

namespace vtm::rectify {
namespace {

Vec3 vec(const double (&v)[3]) noexcept { return Vec3(v[0], v[1], v[2]); }

LinearCamera fromPinhole(const CameraModel& m) noexcept {
    LinearCamera cam;
    cam.K << m.fx_px, 0.0, m.cx_px, 0.0, m.fy_px, m.cy_px, 0.0, 0.0, 1.0;
    return cam;
}

// Yakimovsky-Cunningham: [H; V; A] / |A| = K R with R's last row A^ and K upper
// triangular (RQ decomposition by Gram-Schmidt from the last row up). Dividing by |A|
// keeps the projection exact for an A that is unit only within the validation tolerance.
Status fromCahv(const CameraModel& m, LinearCamera& cam) noexcept {
    const Vec3 a_raw = vec(m.a);
    const double a_norm = math::sqrt(a_raw.dot(a_raw));
    const Vec3 a = a_raw / a_norm;
    const Vec3 h = vec(m.h) / a_norm;
    const Vec3 v = vec(m.v) / a_norm;
    const double vc = v.dot(a);
    const Vec3 v_perp = v - vc * a;
    const double vs = math::sqrt(v_perp.dot(v_perp));
    const Vec3 r2 = v_perp / vs;
    const Vec3 r1 = r2.cross(a);
    const double hs = h.dot(r1);
    if (!(hs > 0.0)) {
        return Status(StatusCode::kInvalidArgument,
                      "linearizeCamera: CAHV model is mirrored (H x V points against A)");
    }
    cam.K << hs, h.dot(r2), h.dot(a), 0.0, vs, vc, 0.0, 0.0, 1.0;
    cam.R_cam_from_ref.row(0) = r1.transpose();
    cam.R_cam_from_ref.row(1) = r2.transpose();
    cam.R_cam_from_ref.row(2) = a.transpose();
    cam.centre_ref_m = vec(m.c);
    return Status::ok();
}

}  // namespace

Status linearizeCamera(const CameraModel& model, LinearCamera& out) noexcept {
    if (model.kind == CameraModelKind::kNone) {
        return Status(StatusCode::kInvalidArgument, "linearizeCamera: camera model kind is none");
    }
    VTM_RETURN_IF_ERROR(validateCameraModel(model));
    LinearCamera cam;
    if (model.kind == CameraModelKind::kPinholeBrown) {
        cam = fromPinhole(model);
    } else {
        VTM_RETURN_IF_ERROR(fromCahv(model, cam));
    }
    cam.width_px = model.width_px;
    cam.height_px = model.height_px;
    out = cam;
    return Status::ok();
}

}  // namespace vtm::rectify
