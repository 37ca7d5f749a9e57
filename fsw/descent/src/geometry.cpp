// Geometry of the sweep: input checks, the planes' homographies and the prefilter scale.
#include "geometry.hpp"

#include <cmath>

namespace vtm::descent {
namespace detail {

Status checkPinhole(const CameraModel& camera) noexcept {
    if (camera.kind != CameraModelKind::kPinholeBrown) {
        return Status(StatusCode::kUnsupported,
                      "camera: the descent sweep needs a pinhole model (CAHV/CAHVOR: convert or undistort first)",
                      static_cast<std::int64_t>(camera.kind));
    }
    if (camera.k1 != 0.0 || camera.k2 != 0.0 || camera.k3 != 0.0 || camera.p1 != 0.0 || camera.p2 != 0.0) {
        return Status(StatusCode::kUnsupported,
                      "camera: the descent sweep needs an undistorted pinhole (k1..p2 must be 0; undistort first)");
    }
    if (!validateCameraModel(camera).isOk()) {
        return Status(StatusCode::kInvalidArgument, "camera: invalid pinhole model (validateCameraModel)");
    }
    return Status::ok();
}

}  // namespace detail

Status checkCamera(const CameraModel& camera) noexcept { return detail::checkPinhole(camera); }

namespace detail {

Status checkPose(const RigidPose& pose, const char* reason) noexcept {
    return checkRigidPose(pose, 1.0e-6, reason);
}

Mat3 intrinsics(const CameraModel& c) noexcept {
    Mat3 k;
    k << c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0;
    return k;
}

Mat3 inverseIntrinsics(const CameraModel& c) noexcept {
    Mat3 k;
    k << 1.0 / c.fx_px, 0.0, -c.cx_px / c.fx_px, 0.0, 1.0 / c.fy_px, -c.cy_px / c.fy_px, 0.0, 0.0, 1.0;
    return k;
}

}  // namespace detail

namespace {

Status checkViews(const ImageView<const std::uint16_t>& image1, const ImageView<const std::uint16_t>& image2,
                  const SweepOutput& out, const Config& config) noexcept {
    if (!image1.valid() || !image2.valid() || !out.depth_m.valid()) {
        return Status(StatusCode::kInvalidArgument, "image1/image2/depth_m: empty or malformed view");
    }
    const std::int32_t w = image1.width();
    const std::int32_t h = image1.height();
    if (!image2.sameSize(w, h)) {
        return Status(StatusCode::kSizeMismatch, "image2: size differs from image1", image2.width());
    }
    if (w > config.max_width || h > config.max_height) {
        return Status(StatusCode::kSizeMismatch, "image1: larger than max_width x max_height", w);
    }
    if (w < config.window || h < config.window) {
        return Status(StatusCode::kSizeMismatch, "image1: smaller than the window", w);
    }
    if (!out.depth_m.sameSize(w, h)) {
        return Status(StatusCode::kSizeMismatch, "depth_m: size differs from image1", out.depth_m.width());
    }
    if (out.score.data() != nullptr && !out.score.sameSize(w, h)) {
        return Status(StatusCode::kSizeMismatch, "score: size differs from image1", out.score.width());
    }
    if (out.reason.data() != nullptr && !out.reason.sameSize(w, h)) {
        return Status(StatusCode::kSizeMismatch, "reason: size differs from image1", out.reason.width());
    }
    return Status::ok();
}

// Largest grey level of an image (the caller checks it against kMaxGreyLevel).
std::uint16_t maxLevel(const ImageView<const std::uint16_t>& image) noexcept {
    std::uint16_t m = 0U;
    for (std::int32_t y = 0; y < image.height(); ++y) {
        const std::uint16_t* row = image.row(y);
        for (std::int32_t x = 0; x < image.width(); ++x) {
            m = row[x] > m ? row[x] : m;
        }
    }
    return m;
}

Status checkGeometry(const PairGeometry& g, std::int32_t w, std::int32_t h) noexcept {
    VTM_RETURN_IF_ERROR(detail::checkPinhole(g.camera));
    if (g.camera.width_px != w || g.camera.height_px != h) {
        return Status(StatusCode::kSizeMismatch, "camera: width_px/height_px differ from the images' size",
                      g.camera.width_px);
    }
    VTM_RETURN_IF_ERROR(
        detail::checkPose(g.site_from_cam1, "site_from_cam1: not finite or its rotation is not a rotation"));
    VTM_RETURN_IF_ERROR(
        detail::checkPose(g.site_from_cam2, "site_from_cam2: not finite or its rotation is not a rotation"));
    const Vec3 baseline = g.site_from_cam2.t_m - g.site_from_cam1.t_m;
    if (!(baseline.norm() > 1.0e-9)) {
        return Status(StatusCode::kInvalidArgument,
                      "site_from_cam2: at site_from_cam1's position (no baseline, no depth)");
    }
    return Status::ok();
}

// Scale of image 2 relative to image 1 at the image centre under the row-major h[9]:
// sqrt |det J| of the local linear map, by unit steps (0 if a step maps behind camera 2).
double centreScale(const double* hk, double cx, double cy) noexcept {
    double u0 = 0.0, v0 = 0.0, ux = 0.0, vx = 0.0, uy = 0.0, vy = 0.0;
    if (!detail::mapPixel(hk, cx, cy, u0, v0) || !detail::mapPixel(hk, cx + 1.0, cy, ux, vx) ||
        !detail::mapPixel(hk, cx, cy + 1.0, uy, vy)) {
        return 0.0;
    }
    const double det = (ux - u0) * (vy - v0) - (uy - u0) * (vx - v0);
    return std::sqrt(std::fabs(det));
}

}  // namespace

Status PlaneSweep::prepare(const ImageView<const std::uint16_t>& image1,
                           const ImageView<const std::uint16_t>& image2, const PairGeometry& g,
                           const SweepOutput& out) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PlaneSweep::compute: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkViews(image1, image2, out, config_));
    VTM_RETURN_IF_ERROR(checkGeometry(g, image1.width(), image1.height()));
    const std::uint16_t m1 = maxLevel(image1);
    if (m1 > kMaxGreyLevel) {
        return Status(StatusCode::kInvalidArgument, "image1: grey level above 4095 (12 bits)", m1);
    }
    const std::uint16_t m2 = maxLevel(image2);
    if (m2 > kMaxGreyLevel) {
        return Status(StatusCode::kInvalidArgument, "image2: grey level above 4095 (12 bits)", m2);
    }
    // X2 = R X1 + t from X_site = R1 X1 + c1 = R2 X2 + c2.
    const Mat3 R = g.site_from_cam2.R.transpose() * g.site_from_cam1.R;
    const Vec3 t = g.site_from_cam2.R.transpose() * (g.site_from_cam1.t_m - g.site_from_cam2.t_m);
    const Mat3 K = detail::intrinsics(g.camera);
    const Mat3 Kinv = detail::inverseIntrinsics(g.camera);
    const double invFar = 1.0 / config_.depth_max_m;
    const double step = (1.0 / config_.depth_min_m - invFar) / static_cast<double>(config_.planes - 1);
    for (std::int32_t k = 0; k < config_.planes; ++k) {
        const double inv = invFar + step * static_cast<double>(k);
        inverseDepth_[static_cast<std::size_t>(k)] = inv;
        Mat3 A = R;
        A.col(2) += t * inv;  // R + t n^T / z_k with n = (0, 0, 1)
        const Mat3 H = K * A * Kinv;
        for (std::int32_t i = 0; i < 9; ++i) {
            homographies_[9U * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)] = H(i / 3, i % 3);
        }
    }
    // The nearest plane must lie in front of camera 2 at the image centre.
    const Vec3 nearCentre = R * Vec3(0.0, 0.0, config_.depth_min_m) + t;
    if (!(nearCentre.z() > 0.0)) {
        return Status(StatusCode::kDegenerate, "depth_min_m: the nearest plane passes behind camera 2");
    }
    width_ = image1.width();
    height_ = image1.height();
    const double* mid = &homographies_[9U * static_cast<std::size_t>(config_.planes / 2)];
    scale_ = centreScale(mid, g.camera.cx_px, g.camera.cy_px);
    // Footprint matching: image 2's pixel (a box of width 1) becomes a box of width s
    // (image-2 pixels) once blurred by a kernel of variance (s^2 - 1) / 12.
    const double s = scale_;
    prefilterSigma_ = s > 1.0 ? std::sqrt((s * s - 1.0) / 12.0) : 0.0;
    prefilter(image2, prefilterSigma_);
    return Status::ok();
}

ImageView<const std::uint16_t> PlaneSweep::prefilteredImage2() const noexcept {
    if (width_ == 0) {
        return ImageView<const std::uint16_t>();
    }
    return ImageView<const std::uint16_t>(image2_.data(), width_, height_);
}

Mat3 PlaneSweep::homography(std::int32_t k) const noexcept {
    VTM_ASSERT(k >= 0 && k < config_.planes, k, config_.planes);
    Mat3 H = Mat3::Zero();
    if (k >= 0 && k < config_.planes && !homographies_.empty()) {
        for (std::int32_t i = 0; i < 9; ++i) {
            H(i / 3, i % 3) = homographies_[9U * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)];
        }
    }
    return H;
}

double PlaneSweep::planeDepth(std::int32_t k) const noexcept {
    VTM_ASSERT(k >= 0 && k < config_.planes, k, config_.planes);
    if (k < 0 || k >= config_.planes || inverseDepth_.empty()) {
        return 0.0;
    }
    return 1.0 / inverseDepth_[static_cast<std::size_t>(k)];
}

}  // namespace vtm::descent
