// Geometry of the sweep: input checks, the planes' homographies and the prefilter scale.
#include "geometry.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

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

// The sweep's planes n . X1 = z_k, n = (0, 0, 1), uniform in 1/z from 1/depth_max (k = 0)
// to 1/depth_min (k = count - 1), and their homographies H_k = K (R + t n^T / z_k) K^-1.
struct PlaneFamily {
    Mat3 K, Kinv, R;
    Vec3 t;
    double invFar, invNear;

    [[nodiscard]] double inverseDepth(std::int32_t k, std::int32_t count) const noexcept {
        const double step = (invNear - invFar) / static_cast<double>(count - 1);
        return invFar + step * static_cast<double>(k);
    }
    // Row-major into h[9].
    void homography(double inv, double* h) const noexcept {
        Mat3 A = R;
        A.col(2) += t * inv;
        const Mat3 H = K * A * Kinv;
        for (std::int32_t i = 0; i < 9; ++i) {
            h[i] = H(i / 3, i % 3);
        }
    }
};

// Points per axis of the grid over image 1 at which Config::max_plane_step_px is checked.
constexpr std::int32_t kStepGrid = 33;
constexpr std::int32_t kStepPoints = kStepGrid * kStepGrid;

// Which points of the grid over image 1 (kStepGrid^2, corners included, row by row) have
// image-2 positions inside image 2 (image 1's size) at both ends of the range: those that
// can get a depth. One bit each: the sweep runs on the flight stack.
struct StepGrid {
    double width = 0.0;   // image 1's last column and row
    double height = 0.0;
    std::uint32_t in_view[(kStepPoints + 31) / 32] = {};

    [[nodiscard]] double x(std::int32_t i) const noexcept {
        const std::int32_t column = i % kStepGrid;
        return width * static_cast<double>(column) / static_cast<double>(kStepGrid - 1);
    }
    [[nodiscard]] double y(std::int32_t i) const noexcept {
        const std::int32_t row = i / kStepGrid;  // the grid's row of point i
        return height * static_cast<double>(row) / static_cast<double>(kStepGrid - 1);
    }
    [[nodiscard]] bool seen(std::int32_t i) const noexcept { return ((in_view[i / 32] >> (i % 32)) & 1U) != 0U; }
};

double distance(const double* ha, const double* hb, double x, double y) noexcept {
    double ua = 0.0, va = 0.0, ub = 0.0, vb = 0.0;
    if (!detail::mapPixel(ha, x, y, ua, va) || !detail::mapPixel(hb, x, y, ub, vb)) {
        return 0.0;
    }
    return std::sqrt((ua - ub) * (ua - ub) + (va - vb) * (va - vb));
}

// Fills the grid; returns the largest parallax over the range among its points, image-2 px.
double inViewGrid(const PlaneFamily& f, std::int32_t width, std::int32_t height, StepGrid& grid) noexcept {
    double hFar[9], hNear[9];
    f.homography(f.invFar, hFar);
    f.homography(f.invNear, hNear);
    grid = StepGrid{};
    grid.width = static_cast<double>(width - 1);
    grid.height = static_cast<double>(height - 1);
    const double w = grid.width;
    const double h = grid.height;
    const auto inside = [w, h](double u, double v) { return u >= 0.0 && u <= w && v >= 0.0 && v <= h; };
    double largest = 0.0;
    for (std::int32_t i = 0; i < kStepPoints; ++i) {
        const double x = grid.x(i);
        const double y = grid.y(i);
        double un = 0.0, vn = 0.0, uf = 0.0, vf = 0.0;
        if (detail::mapPixel(hNear, x, y, un, vn) && detail::mapPixel(hFar, x, y, uf, vf) && inside(un, vn) &&
            inside(uf, vf)) {
            grid.in_view[i / 32] |= 1U << static_cast<std::uint32_t>(i % 32);
            const double p = std::sqrt((un - uf) * (un - uf) + (vn - vf) * (vn - vf));  // the positions just mapped
            largest = p > largest ? p : largest;
        }
    }
    return largest;
}

// The largest image-2 step between neighbouring planes of a `count`-plane family over the
// grid. A point's image-2 position moves along a line as a Moebius map of 1/z, which
// steps monotonically faster or slower along the range: the first or the last step is
// the largest.
double largestStep(const PlaneFamily& f, std::int32_t count, const StepGrid& grid) noexcept {
    double h0[9], h1[9], hm[9], hn[9];
    f.homography(f.inverseDepth(0, count), h0);
    f.homography(f.inverseDepth(1, count), h1);
    f.homography(f.inverseDepth(count - 2, count), hm);
    f.homography(f.inverseDepth(count - 1, count), hn);
    double largest = 0.0;
    for (std::int32_t i = 0; i < kStepPoints; ++i) {
        if (!grid.seen(i)) {
            continue;
        }
        const double a = distance(h1, h0, grid.x(i), grid.y(i));
        const double b = distance(hn, hm, grid.x(i), grid.y(i));
        largest = a > largest ? a : largest;
        largest = b > largest ? b : largest;
    }
    return largest;
}

// Config::max_plane_step_px: the fewest planes (3..planes) whose largest step over the
// grid stays within it, from the estimate parallax / step + 1 upwards; every plane when
// it is 0.
std::int32_t planesToSweep(const Config& c, const PlaneFamily& f, double parallax_px, const StepGrid& grid) noexcept {
    if (!(c.max_plane_step_px > 0.0)) {
        return c.planes;
    }
    const double estimate = -math::floor(-(parallax_px / c.max_plane_step_px)) + 1.0;  // ceil + 1
    std::int32_t n = estimate < static_cast<double>(c.planes) ? static_cast<std::int32_t>(estimate) : c.planes;
    n = n > 3 ? n : 3;
    // bound: at most planes - 3 more counts (Config::planes <= kMaxPlanes)
    while (n < c.planes && largestStep(f, n, grid) > c.max_plane_step_px) {
        ++n;
    }
    return n;
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
    const PlaneFamily family{detail::intrinsics(g.camera), detail::inverseIntrinsics(g.camera), R, t,
                             1.0 / config_.depth_max_m, 1.0 / config_.depth_min_m};
    StepGrid grid;
    maxParallax_ = inViewGrid(family, image1.width(), image1.height(), grid);
    planes_ = planesToSweep(config_, family, maxParallax_, grid);
    for (std::int32_t k = 0; k < planes_; ++k) {
        const double inv = family.inverseDepth(k, planes_);
        inverseDepth_[static_cast<std::size_t>(k)] = inv;
        family.homography(inv, &homographies_[9U * static_cast<std::size_t>(k)]);
    }
    // The nearest plane must lie in front of camera 2 at the image centre.
    const Vec3 nearCentre = R * Vec3(0.0, 0.0, config_.depth_min_m) + t;
    if (!(nearCentre.z() > 0.0)) {
        return Status(StatusCode::kDegenerate, "depth_min_m: the nearest plane passes behind camera 2");
    }
    width_ = image1.width();
    height_ = image1.height();
    const double* mid = &homographies_[9U * static_cast<std::size_t>(planes_ / 2)];
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
    VTM_ASSERT(k >= 0 && k < planes_, k, planes_);
    Mat3 H = Mat3::Zero();
    if (k >= 0 && k < planes_ && !homographies_.empty()) {
        for (std::int32_t i = 0; i < 9; ++i) {
            H(i / 3, i % 3) = homographies_[9U * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)];
        }
    }
    return H;
}

double PlaneSweep::planeDepth(std::int32_t k) const noexcept {
    VTM_ASSERT(k >= 0 && k < planes_, k, planes_);
    if (k < 0 || k >= planes_ || inverseDepth_.empty()) {
        return 0.0;
    }
    return 1.0 / inverseDepth_[static_cast<std::size_t>(k)];
}

}  // namespace vtm::descent
