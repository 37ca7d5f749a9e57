#include "geometry.hpp"

#include "vtm/core/math.hpp"

namespace vtm::tiepoints::detail {

bool siteRay(const CameraModel& model, const RigidPose& site_from_cam, const Vec2& pixel, SiteRay& ray) noexcept {
    CameraRay r;
    if (!backProjectPixel(model, pixel, r).isOk()) {
        return false;
    }
    ray.origin = transformPoint(site_from_cam, r.origin_m);
    ray.direction = site_from_cam.R * r.direction;
    return true;
}

bool midpoint(const SiteRay& a, const SiteRay& b, Vec3& point) noexcept {
    const Vec3 w = a.origin - b.origin;
    const double c = a.direction.dot(b.direction);
    const double d = a.direction.dot(w);
    const double e = b.direction.dot(w);
    const double den = 1.0 - c * c;
    if (!(den > 1e-12)) {
        return false;
    }
    const double s = (c * e - d) / den;  // along a
    const double t = (e - c * d) / den;  // along b
    if (!(s > 0.0) || !(t > 0.0)) {
        return false;
    }
    point = 0.5 * ((a.origin + s * a.direction) + (b.origin + t * b.direction));
    return true;
}

bool projectInside(const CameraModel& model, const RigidPose& site_from_cam, const Vec3& site_m, double border_px,
                   Vec2& pixel) noexcept {
    const Vec3 cam = site_from_cam.R.transpose() * (site_m - site_from_cam.t_m);
    if (!projectPoint(model, cam, pixel).isOk()) {
        return false;
    }
    return pixel.x() >= border_px && pixel.y() >= border_px &&
           pixel.x() <= static_cast<double>(model.width_px) - 1.0 - border_px &&
           pixel.y() <= static_cast<double>(model.height_px) - 1.0 - border_px;
}

double pixelsPerRadian(const CameraModel& model) noexcept {
    const Vec2 centre(0.5 * (static_cast<double>(model.width_px) - 1.0),
                      0.5 * (static_cast<double>(model.height_px) - 1.0));
    CameraRay r0;
    CameraRay r1;
    if (!backProjectPixel(model, centre, r0).isOk() ||
        !backProjectPixel(model, centre + Vec2(1.0, 0.0), r1).isOk()) {
        return 0.0;
    }
    const double angle = math::atan2(r0.direction.cross(r1.direction).norm(), r0.direction.dot(r1.direction));
    return angle > 0.0 ? 1.0 / angle : 0.0;
}

double elevationNear(const terrain::HeightMap& map, double north_m, double east_m, std::int32_t fill_radius) noexcept {
    const terrain::GridConfig& g = map.grid();
    const double fc = (east_m - g.west_edge_m) / g.cell_m;
    const double fr = (g.north_edge_m - north_m) / g.cell_m;
    if (!(fc >= 0.0) || !(fr >= 0.0) || fc >= static_cast<double>(g.cols) || fr >= static_cast<double>(g.rows)) {
        return math::kNaN;
    }
    const auto col = static_cast<std::int32_t>(fc);
    const auto row = static_cast<std::int32_t>(fr);
    if (map.count(col, row) > 0U) {
        return static_cast<double>(map.elevation(col, row));
    }
    for (std::int32_t radius = 1; radius <= fill_radius; ++radius) {
        double sum = 0.0;
        std::int32_t n = 0;
        for (std::int32_t r = row - radius; r <= row + radius; ++r) {
            for (std::int32_t c = col - radius; c <= col + radius; ++c) {
                if (r >= 0 && c >= 0 && r < g.rows && c < g.cols && map.count(c, r) > 0U) {
                    sum += static_cast<double>(map.elevation(c, r));
                    ++n;
                }
            }
        }
        if (n > 0) {
            return sum / static_cast<double>(n);
        }
    }
    return math::kNaN;
}

namespace {
// +1: the ray's point at `range` is above the map, -1 at or below, 0 unknown (no map there).
int sideAt(const terrain::HeightMap& map, const SiteRay& ray, double range, std::int32_t fill_radius) noexcept {
    const Vec3 p = ray.origin + range * ray.direction;
    const double ground = elevationNear(map, p.x(), p.y(), fill_radius);
    if (!math::isFinite(ground)) {
        return 0;
    }
    return (-p.z() > ground) ? 1 : -1;
}
}  // namespace

bool castOnMap(const terrain::HeightMap& map, const SiteRay& ray, double range_min_m, double range_max_m,
               std::int32_t steps, std::int32_t fill_radius, double& range_m) noexcept {
    double above = -1.0;  // last sampled range above the map
    for (std::int32_t k = 0; k <= steps; ++k) {
        const double r = range_min_m + (range_max_m - range_min_m) * static_cast<double>(k) / static_cast<double>(steps);
        const int side = sideAt(map, ray, r, fill_radius);
        if (side > 0) {
            above = r;
        } else if (side < 0) {
            if (above < 0.0) {
                return false;
            }
            double lo = above;
            double hi = r;
            for (std::int32_t b = 0; b < 12; ++b) {
                const double mid = 0.5 * (lo + hi);
                (sideAt(map, ray, mid, fill_radius) < 0 ? hi : lo) = mid;
            }
            range_m = 0.5 * (lo + hi);
            return true;
        }
    }
    return false;
}

}  // namespace vtm::tiepoints::detail
