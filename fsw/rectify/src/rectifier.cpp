// Fusiello rectification: configuration, workspace and the rectified geometry
// (vtm/rectify/rectifier.hpp, docs/rectify.md). The tables and the point maps are in
// remap.cpp.
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/rectify/rectifier.hpp"

namespace vtm::rectify {

// Everything compute() derives from the input before the intrinsics, in A's reference
// frame ("ref_a").
struct Rectifier::Geometry {
    LinearCamera lin_a{}, lin_b{};
    Mat3 R_a_from_b = Mat3::Identity();        // reference frames: X_a = R_a_from_b (X_b - t)
    Mat3 R_rect_from_a = Mat3::Identity();     // Fusiello's R (rows v1, v2, v3)
    double sign = 1.0;                         // +1: B's centre on the rectified +x side
    double baseline_m = 0.0;
    double convergence_deg = 0.0;
};

namespace {

// Tolerance of R_b_from_a's orthonormality (max |R^T R - I| element).
constexpr double kRotationTolerance = 1e-9;
// Shorter baselines are "zero": the rectified x axis would be noise.
constexpr double kMinBaselineM = 1e-9;
constexpr double kDegPerRad = 180.0 / math::kPi;
// Disparity bounds are clamped to this so that they always fit int32 (report only).
constexpr double kDisparityClamp = 1.0e9;

// Unit ray (not normalised: z = 1 in camera coordinates) of a pixel of a linear camera,
// in its reference frame: R^T K^-1 (u, v, 1).
Vec3 linearRayRef(const LinearCamera& cam, double u, double v) noexcept {
    const double y = (v - cam.K(1, 2)) / cam.K(1, 1);
    const double x = (u - cam.K(0, 2) - cam.K(0, 1) * y) / cam.K(0, 0);
    return cam.R_cam_from_ref.transpose() * Vec3(x, y, 1.0);
}

double clampDisparity(double d) noexcept {
    return d < -kDisparityClamp ? -kDisparityClamp : (d > kDisparityClamp ? kDisparityClamp : d);
}

}  // namespace

Status Config::validate() const noexcept {
    if (max_width < 1 || max_width > kMaxImageSide) {
        return Status(StatusCode::kInvalidConfig, "Config.max_width: must be 1..4094", max_width);
    }
    if (max_height < 1 || max_height > kMaxImageSide) {
        return Status(StatusCode::kInvalidConfig, "Config.max_height: must be 1..4094", max_height);
    }
    if (out_width < 0 || out_width > max_width) {
        return Status(StatusCode::kInvalidConfig, "Config.out_width: must be 0..max_width", out_width);
    }
    if (out_height < 0 || out_height > max_height) {
        return Status(StatusCode::kInvalidConfig, "Config.out_height: must be 0..max_height", out_height);
    }
    if ((out_width == 0) != (out_height == 0)) {
        return Status(StatusCode::kInvalidConfig, "Config.out_width/out_height: both 0 or both set");
    }
    if (!math::isFinite(range_min_m) || !(range_min_m > 0.0)) {
        return Status(StatusCode::kInvalidConfig, "Config.range_min_m: must be finite and > 0");
    }
    if (!math::isFinite(range_max_m) || !(range_max_m > range_min_m)) {
        return Status(StatusCode::kInvalidConfig, "Config.range_max_m: must be finite and > range_min_m");
    }
    if (!(min_baseline_angle_deg >= 0.0 && min_baseline_angle_deg < 90.0)) {
        return Status(StatusCode::kInvalidConfig, "Config.min_baseline_angle_deg: must be in [0, 90)");
    }
    return Status::ok();
}

std::size_t Rectifier::workspaceBytes(const Config& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    // One table per side: an (x, y) pair of int16 per rectified pixel of the capacity.
    const std::size_t entries = 2U * static_cast<std::size_t>(config.max_width) *
                                static_cast<std::size_t>(config.max_height);
    return 2U * Arena::blockBytes(entries * sizeof(std::int16_t));
}

Status Rectifier::init(const Config& config, Arena& arena) noexcept {
    initialized_ = false;
    ready_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t entries = 2U * static_cast<std::size_t>(config.max_width) *
                                static_cast<std::size_t>(config.max_height);
    for (SideState& side : sides_) {
        side.table = arena.allocateArray<std::int16_t>(entries);
        if (side.table.empty()) {
            return Status(StatusCode::kOutOfMemory, "Rectifier: arena too small for the remap tables",
                          static_cast<std::int64_t>(workspaceBytes(config)));
        }
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

Status Rectifier::checkInput(const RectifyInput& input) const noexcept {
    const CameraModel* models[2] = {&input.pair.model_a, &input.pair.model_b};
    for (const CameraModel* m : models) {
        if (m->width_px > kMaxImageSide || m->height_px > kMaxImageSide) {
            return Status(StatusCode::kInvalidArgument, "Rectifier.compute: model image side above 4094 px",
                          m->width_px > m->height_px ? m->width_px : m->height_px);
        }
    }
    const RigidPose& b_from_a = input.pair.b_from_a;
    if (!isRotation(b_from_a.R, kRotationTolerance)) {
        return Status(StatusCode::kInvalidArgument, "Rectifier.compute: pair.b_from_a.R is not a rotation");
    }
    if (!math::isFinite(b_from_a.t_m.x()) || !math::isFinite(b_from_a.t_m.y()) || !math::isFinite(b_from_a.t_m.z())) {
        return Status(StatusCode::kInvalidArgument, "Rectifier.compute: pair.b_from_a.t_m is not finite");
    }
    return Status::ok();
}

namespace {

// Fusiello's rotation: v1 = +-(c_b - c_a) (sign: along A's +x), v2 = k x v1 with k A's
// optical axis, v3 = v1 x v2.
Status rectifyingRotation(const RectifyInput& input, double min_angle_deg, Mat3& R_rect_from_a, double& sign,
                          double& baseline_m, const LinearCamera& lin_a, const LinearCamera& lin_b) noexcept {
    const Mat3 R_a_from_b = input.pair.b_from_a.R.transpose();
    const Vec3 c_b_in_a = R_a_from_b * (lin_b.centre_ref_m - input.pair.b_from_a.t_m);
    const Vec3 base = c_b_in_a - lin_a.centre_ref_m;
    baseline_m = math::sqrt(base.dot(base));
    if (!(baseline_m > kMinBaselineM)) {
        return Status(StatusCode::kDegenerate, "Rectifier.compute: zero baseline (camera centres coincide)");
    }
    const Vec3 k = lin_a.R_cam_from_ref.row(2).transpose();
    Vec3 v1 = base / baseline_m;
    const double cos_limit = math::cos(min_angle_deg / kDegPerRad);
    if (std::fabs(v1.dot(k)) > cos_limit) {
        return Status(StatusCode::kDegenerate,
                      "Rectifier.compute: baseline within min_baseline_angle_deg of A's optical axis");
    }
    sign = (v1.dot(lin_a.R_cam_from_ref.row(0).transpose()) >= 0.0) ? 1.0 : -1.0;
    v1 *= sign;
    Vec3 v2 = k.cross(v1);
    v2 /= math::sqrt(v2.dot(v2));
    const Vec3 v3 = v1.cross(v2);
    R_rect_from_a.row(0) = v1.transpose();
    R_rect_from_a.row(1) = v2.transpose();
    R_rect_from_a.row(2) = v3.transpose();
    return Status::ok();
}

}  // namespace

// Common K = mean of the two (zero skew); each side's cx and the common cy put the
// centre ray of each input image on its rectified image's centre (Fusiello 2003), cy the
// mean of the two vertical shifts (rows must agree).
Status Rectifier::setIntrinsics(const Geometry& g) noexcept {
    fx_px_ = 0.5 * (g.lin_a.K(0, 0) + g.lin_b.K(0, 0));
    fy_px_ = 0.5 * (g.lin_a.K(1, 1) + g.lin_b.K(1, 1));
    const LinearCamera* lins[2] = {&g.lin_a, &g.lin_b};
    double cy[2] = {0.0, 0.0};
    for (std::size_t i = 0U; i < 2U; ++i) {
        const LinearCamera& cam = *lins[i];
        const Vec3 ray = sides_[i].R_rect_from_ref *
                         linearRayRef(cam, 0.5 * (cam.width_px - 1), 0.5 * (cam.height_px - 1));
        if (!(ray.z() > 0.0)) {
            return Status(StatusCode::kDegenerate,
                          "Rectifier.compute: an image centre looks behind the rectified image plane");
        }
        sides_[i].cx_px = 0.5 * (out_width_ - 1) - fx_px_ * ray.x() / ray.z();
        cy[i] = 0.5 * (out_height_ - 1) - fy_px_ * ray.y() / ray.z();
    }
    cy_px_ = 0.5 * (cy[0] + cy[1]);
    return Status::ok();
}

Status Rectifier::compute(const RectifyInput& input, RectifiedPair& out) noexcept {
    ready_ = false;
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "Rectifier.compute: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkInput(input));
    Geometry g;
    VTM_RETURN_IF_ERROR(linearizeCamera(input.pair.model_a, g.lin_a));
    VTM_RETURN_IF_ERROR(linearizeCamera(input.pair.model_b, g.lin_b));
    out_width_ = config_.out_width != 0 ? config_.out_width : g.lin_a.width_px;
    out_height_ = config_.out_height != 0 ? config_.out_height : g.lin_a.height_px;
    if (out_width_ > config_.max_width || out_height_ > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "Rectifier.compute: rectified size exceeds max_width/max_height",
                      out_width_ > config_.max_width ? out_width_ : out_height_);
    }
    VTM_RETURN_IF_ERROR(rectifyingRotation(input, config_.min_baseline_angle_deg, g.R_rect_from_a, g.sign,
                                           g.baseline_m, g.lin_a, g.lin_b));
    g.R_a_from_b = input.pair.b_from_a.R.transpose();
    const Vec3 axis_a = g.lin_a.R_cam_from_ref.row(2).transpose();
    const Vec3 axis_b = g.R_a_from_b * g.lin_b.R_cam_from_ref.row(2).transpose();
    g.convergence_deg = kDegPerRad * math::atan2(math::sqrt(axis_a.cross(axis_b).squaredNorm()), axis_a.dot(axis_b));
    sides_[0].model = input.pair.model_a;
    sides_[0].R_rect_from_ref = g.R_rect_from_a;
    sides_[0].centre_ref_m = g.lin_a.centre_ref_m;
    sides_[1].model = input.pair.model_b;
    sides_[1].R_rect_from_ref = g.R_rect_from_a * g.R_a_from_b;
    sides_[1].centre_ref_m = g.lin_b.centre_ref_m;
    VTM_RETURN_IF_ERROR(setIntrinsics(g));
    std::int32_t largest = 0;
    for (const SideState& s : sides_) {
        largest = s.model.width_px > largest ? s.model.width_px : largest;
        largest = s.model.height_px > largest ? s.model.height_px : largest;
    }
    fraction_bits_ = ((largest + 1) << 5) <= 32767 ? 5 : (((largest + 1) << 4) <= 32767 ? 4 : 3);
    buildTable(sides_[0]);
    buildTable(sides_[1]);
    fillPair(g, out);
    ready_ = true;
    return Status::ok();
}

// The rectified models, poses and the disparity range d = (cx_a - cx_b) + s fx B / Z,
// Z the depth in the rectified frame: for a point at range r seen through A's rectified
// image, r cos(theta_max) <= Z <= r, theta_max the angle of the farthest image corner
// (pixel edges) from the rectified optical axis.
void Rectifier::fillPair(const Geometry& g, RectifiedPair& out) const noexcept {
    RectifiedPair p;
    for (std::size_t i = 0U; i < 2U; ++i) {
        CameraModel& m = (i == 0U) ? p.model_a : p.model_b;
        m.kind = CameraModelKind::kPinholeBrown;
        m.width_px = static_cast<std::uint16_t>(out_width_);
        m.height_px = static_cast<std::uint16_t>(out_height_);
        m.fx_px = fx_px_;
        m.fy_px = fy_px_;
        m.cx_px = sides_[i].cx_px;
        m.cy_px = cy_px_;
    }
    p.R_rect_from_a = sides_[0].R_rect_from_ref;
    p.R_rect_from_b = sides_[1].R_rect_from_ref;
    p.baseline_m = g.baseline_m;
    p.centre_b_rect_m = Vec3(g.sign * g.baseline_m, 0.0, 0.0);
    p.centre_a_ref_m = g.lin_a.centre_ref_m;
    p.convergence_deg = g.convergence_deg;
    const double dx = std::fabs(-0.5 - sides_[0].cx_px) > std::fabs(out_width_ - 0.5 - sides_[0].cx_px)
                          ? -0.5 - sides_[0].cx_px
                          : out_width_ - 0.5 - sides_[0].cx_px;
    const double dy = std::fabs(-0.5 - cy_px_) > std::fabs(out_height_ - 0.5 - cy_px_) ? -0.5 - cy_px_
                                                                                      : out_height_ - 0.5 - cy_px_;
    const double tan2 = (dx / fx_px_) * (dx / fx_px_) + (dy / fy_px_) * (dy / fy_px_);
    const double z_near = config_.range_min_m / math::sqrt(1.0 + tan2);
    const double offset = sides_[0].cx_px - sides_[1].cx_px;
    const double near_px = g.sign * fx_px_ * g.baseline_m / z_near;
    const double far_px = g.sign * fx_px_ * g.baseline_m / config_.range_max_m;
    const double lo = offset + (near_px < far_px ? near_px : far_px);
    const double hi = offset + (near_px < far_px ? far_px : near_px);
    p.d_min = static_cast<std::int32_t>(clampDisparity(std::floor(lo) - 1.0));
    p.d_max = static_cast<std::int32_t>(clampDisparity(std::ceil(hi) + 1.0));
    out = p;
}

}  // namespace vtm::rectify
