#include "vtm/terrain/triangulation.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm::terrain {
namespace {

bool finite3(const Vec3& v) noexcept {
    return math::isFinite(v.x()) && math::isFinite(v.y()) && math::isFinite(v.z());
}

bool isRotation(const Mat3& R) noexcept {
    for (std::int32_t i = 0; i < 3; ++i) {
        if (!finite3(R.row(i).transpose())) {
            return false;
        }
    }
    const Mat3 e = R.transpose() * R - Mat3::Identity();
    return e.cwiseAbs().maxCoeff() <= 1e-9 && R.determinant() > 0.0;
}

}  // namespace

Status RectifiedGeometry::validate() const noexcept {
    const double numbers[] = {fx_px, fy_px, cx_left_px, cx_right_px, cy_px, baseline_m};
    for (const double v : numbers) {
        if (!math::isFinite(v)) {
            return Status(StatusCode::kInvalidArgument, "rectified geometry: a focal length, principal point or baseline is not finite");
        }
    }
    if (!(fx_px > 0.0) || !(fy_px > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "rectified geometry: fx_px and fy_px must be > 0");
    }
    if (baseline_m == 0.0) {
        return Status(StatusCode::kInvalidArgument, "rectified geometry: baseline_m must not be 0");
    }
    if (!isRotation(R_site_from_rect)) {
        return Status(StatusCode::kInvalidArgument, "rectified geometry: R_site_from_rect is not a rotation");
    }
    if (!finite3(left_centre_site_m)) {
        return Status(StatusCode::kInvalidArgument, "rectified geometry: left_centre_site_m is not finite");
    }
    return Status::ok();
}

Status TriangulationLimits::validate() const noexcept {
    if (!(min_range_m > 0.0) || !math::isFinite(min_range_m)) {
        return Status(StatusCode::kInvalidConfig, "triangulation: min_range_m must be > 0");
    }
    if (!(max_range_m > min_range_m) || !math::isFinite(max_range_m)) {
        return Status(StatusCode::kInvalidConfig, "triangulation: max_range_m must be > min_range_m and finite");
    }
    if (!(max_sigma_ratio > 0.0) || !math::isFinite(max_sigma_ratio)) {
        return Status(StatusCode::kInvalidConfig, "triangulation: max_sigma_ratio must be > 0");
    }
    if (!(default_sigma_px > 0.0) || !math::isFinite(default_sigma_px)) {
        return Status(StatusCode::kInvalidConfig, "triangulation: default_sigma_px must be > 0");
    }
    return Status::ok();
}

Status triangulatePixel(const RectifiedGeometry& g, const TriangulationLimits& limits, double x_px, double y_px,
                        double disparity_px, double sigma_d_px, TerrainPoint& point) noexcept {
    // Disparity at infinity is cx_left - cx_right; nearer points move it towards the
    // baseline's sign.
    const double shifted = disparity_px - (g.cx_left_px - g.cx_right_px);
    const double fb = g.fx_px * g.baseline_m;
    if (!math::isFinite(shifted) || !(shifted * g.baseline_m > 0.0)) {
        return Status(StatusCode::kNoData, "triangulation: disparity at or beyond infinity");
    }
    const double z = fb / shifted;
    const Vec3 p_rect(z * (x_px - g.cx_left_px) / g.fx_px, z * (y_px - g.cy_px) / g.fy_px, z);
    const double range = p_rect.norm();
    const double sigma_z = z * z / std::fabs(fb) * sigma_d_px;
    const double sigma_range = sigma_z * range / z;
    if (!(range >= limits.min_range_m) || !(range <= limits.max_range_m) ||
        !(sigma_range <= limits.max_sigma_ratio * range)) {
        return Status(StatusCode::kNoData, "triangulation: point out of the range or uncertainty limits");
    }
    const Vec3 p_site = g.left_centre_site_m + g.R_site_from_rect * p_rect;
    point.x_m = static_cast<float>(p_site.x());
    point.y_m = static_cast<float>(p_site.y());
    point.z_m = static_cast<float>(p_site.z());
    point.sigma_range_m = static_cast<float>(sigma_range);
    return Status::ok();
}

Status triangulate(const RectifiedGeometry& geometry, const TriangulationLimits& limits,
                   const ImageView<const std::int16_t>& disparity_px16, const ImageView<const float>& sigma_px,
                   Span<TerrainPoint> out, TriangulationStats& stats) noexcept {
    stats = TriangulationStats{};
    Status s = geometry.validate();
    if (s.isOk()) {
        s = limits.validate();
    }
    if (!s.isOk()) {
        return Status(StatusCode::kInvalidArgument, s.reason());
    }
    const bool have_sigma = sigma_px.data() != nullptr;
    if (have_sigma && (sigma_px.width() != disparity_px16.width() || sigma_px.height() != disparity_px16.height())) {
        return Status(StatusCode::kSizeMismatch, "triangulation: sigma_px is not the disparity image's size",
                      sigma_px.width());
    }
    const double scale = static_cast<double>(kDisparityScale);
    for (std::int32_t y = 0; y < disparity_px16.height(); ++y) {
        const std::int16_t* drow = disparity_px16.row(y);
        const float* srow = have_sigma ? sigma_px.row(y) : nullptr;
        for (std::int32_t x = 0; x < disparity_px16.width(); ++x) {
            const std::int16_t d16 = drow[x];
            if (d16 == kNoDisparity) {
                ++stats.no_disparity;
                continue;
            }
            const double sigma = (srow != nullptr) ? static_cast<double>(srow[x]) : limits.default_sigma_px;
            TerrainPoint p{};
            if (!triangulatePixel(geometry, limits, x, y, static_cast<double>(d16) / scale, sigma, p).isOk()) {
                ++stats.refused;
            } else if (static_cast<std::size_t>(stats.points) < out.size()) {
                out[static_cast<std::size_t>(stats.points)] = p;
                ++stats.points;
            } else {
                ++stats.dropped;
            }
        }
    }
    return Status::ok();
}

}  // namespace vtm::terrain
