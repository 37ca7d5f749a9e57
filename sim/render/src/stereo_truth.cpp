// True disparity of a rectified stereo pair over the terrain, with visibility in the right
// camera (docs/sim-render.md "Ground truth").
#include <cmath>
#include <limits>

#include "sensor_model.hpp"
#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/math.hpp"

namespace vtm::sim {

namespace {

using detail::kNoHitF;

bool undistortedPinhole(const CameraModel& m) noexcept {
    return m.kind == CameraModelKind::kPinholeBrown && m.k1 == 0.0 && m.k2 == 0.0 && m.k3 == 0.0 &&
           m.p1 == 0.0 && m.p2 == 0.0;
}

Status checkView(bool present, bool valid, bool sized, const char* reason, std::int32_t width) noexcept {
    if (present && (!valid || !sized)) {
        return Status(StatusCode::kSizeMismatch, reason, width);
    }
    return Status::ok();
}

Status validateStereoRequest(const StereoTruthRequest& r, const StereoTruthOutput& out) noexcept {
    if (r.terrain == nullptr || !r.terrain->built()) {
        return Status(StatusCode::kInvalidArgument, "request.terrain: null or not built");
    }
    VTM_RETURN_IF_ERROR(validateCameraModel(r.left_model));
    if (!undistortedPinhole(r.left_model)) {
        return Status(StatusCode::kInvalidArgument, "request.left_model: must be an undistorted pinhole");
    }
    if (r.left_model.width_px > kMaxRenderSizePx || r.left_model.height_px > kMaxRenderSizePx) {
        return Status(StatusCode::kInvalidArgument, "request.left_model: size above kMaxRenderSizePx (2048)");
    }
    if (!math::isFinite(r.baseline_m) || !(r.baseline_m > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "request.baseline_m: must be finite and > 0");
    }
    if (!math::isFinite(r.max_range_m) || !(r.max_range_m > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "request.max_range_m: must be finite and > 0");
    }
    const Mat3& R = r.left_pose.R;
    const Mat3 e = R.transpose() * R - Mat3::Identity();
    const bool finite = math::isFinite(R.sum()) && math::isFinite(r.left_pose.t_m.sum());
    if (!finite || !(e.cwiseAbs().maxCoeff() <= 1e-6) || R.determinant() < 0.0) {
        return Status(StatusCode::kInvalidArgument, "request.left_pose: not finite or not a rotation (1e-6)");
    }
    const std::int32_t w = r.left_model.width_px;
    const std::int32_t h = r.left_model.height_px;
    VTM_RETURN_IF_ERROR(checkView(true, out.disparity_px.valid(), out.disparity_px.sameSize(w, h),
                                  "out.disparity_px: must be the left image size", out.disparity_px.width()));
    VTM_RETURN_IF_ERROR(checkView(out.code.data() != nullptr, out.code.valid(), out.code.sameSize(w, h),
                                  "out.code: must be the left image size", out.code.width()));
    return checkView(out.left_depth_m.data() != nullptr, out.left_depth_m.valid(), out.left_depth_m.sameSize(w, h),
                     "out.left_depth_m: must be the left image size", out.left_depth_m.width());
}

struct PairSetup {
    const StereoTruthRequest* request = nullptr;
    Vec3 right_centre_site_m = Vec3::Zero();
};

// Visibility of the site point p in the right camera.
DisparityTruthCode rightVisibility(const PairSetup& s, const Vec3& p_site_m) noexcept {
    const StereoTruthRequest& r = *s.request;
    const Mat3& R = r.left_pose.R;
    const Vec3 p_right = R.transpose() * (p_site_m - s.right_centre_site_m);
    Vec2 pixel;
    const bool projects = projectPoint(r.left_model, p_right, pixel).isOk();
    const double w = static_cast<double>(r.left_model.width_px);
    const double h = static_cast<double>(r.left_model.height_px);
    if (!projects || pixel.x() < -0.5 || pixel.x() >= w - 0.5 || pixel.y() < -0.5 || pixel.y() >= h - 0.5) {
        return DisparityTruthCode::kOutOfView;
    }
    const Vec3 to_point = p_site_m - s.right_centre_site_m;
    const double distance_m = to_point.norm();
    const Vec3 dir = to_point / distance_m;
    const TerrainHit blocker = r.terrain->intersect(s.right_centre_site_m, dir, distance_m);
    const double tolerance_m = 1e-3 > 1e-4 * distance_m ? 1e-3 : 1e-4 * distance_m;
    if (blocker.hit && blocker.t_m < distance_m - tolerance_m) {
        return DisparityTruthCode::kOccluded;
    }
    return DisparityTruthCode::kVisible;
}

void disparityRow(const PairSetup& s, const StereoTruthOutput& out, std::int32_t y) noexcept {
    const StereoTruthRequest& r = *s.request;
    const Mat3& R = r.left_pose.R;
    const std::int32_t w = r.left_model.width_px;
    for (std::int32_t x = 0; x < w; ++x) {
        CameraRay ray;
        const bool ok = backProjectPixel(r.left_model, Vec2(static_cast<double>(x), static_cast<double>(y)), ray).isOk();
        TerrainHit hit;
        if (ok) {
            hit = r.terrain->intersect(R * ray.origin_m + r.left_pose.t_m, R * ray.direction, r.max_range_m);
        }
        const double depth_m = hit.t_m * ray.direction.z();
        const bool valid = ok && hit.hit && depth_m > 0.0;
        out.disparity_px.row(y)[x] = valid ? static_cast<float>(r.left_model.fx_px * r.baseline_m / depth_m) : kNoHitF;
        if (out.left_depth_m.data() != nullptr) {
            out.left_depth_m.row(y)[x] = valid ? static_cast<float>(depth_m) : kNoHitF;
        }
        if (out.code.data() != nullptr) {
            const DisparityTruthCode code = valid ? rightVisibility(s, hit.point_site_m) : DisparityTruthCode::kNoHit;
            out.code.row(y)[x] = static_cast<std::uint8_t>(code);
        }
    }
}

}  // namespace

RigidPose rightPoseOfRectifiedPair(const RigidPose& site_from_left, double baseline_m) noexcept {
    RigidPose site_from_right = site_from_left;
    site_from_right.t_m = site_from_left.t_m + site_from_left.R * Vec3(baseline_m, 0.0, 0.0);
    return site_from_right;
}

Status rectifiedDisparity(const StereoTruthRequest& request, const StereoTruthOutput& out) noexcept {
    VTM_RETURN_IF_ERROR(validateStereoRequest(request, out));
    PairSetup s;
    s.request = &request;
    s.right_centre_site_m = rightPoseOfRectifiedPair(request.left_pose, request.baseline_m).t_m;
    for (std::int32_t y = 0; y < request.left_model.height_px; ++y) {
        disparityRow(s, out, y);
    }
    return Status::ok();
}

}  // namespace vtm::sim
