// Line-of-sight test over an elevation grid.
#include "grid_occlusion.hpp"

#include <cmath>
#include <limits>

namespace vtm::kriging::detail {

double highestElevation(Span<const float> elevation_m) noexcept {
    double h = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < elevation_m.size(); ++k) {
        const float z = elevation_m[k];
        h = (!terrain::isNoData(z) && static_cast<double>(z) > h) ? static_cast<double>(z) : h;
    }
    return h;
}

double surfaceElevation(const ElevationSurface& s, double north_m, double east_m) noexcept {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double u = (east_m - s.grid.west_edge_m) / s.grid.cell_m - 0.5;
    const double v = (s.grid.north_edge_m - north_m) / s.grid.cell_m - 0.5;
    if (!(u >= 0.0) || !(v >= 0.0) || u >= static_cast<double>(s.grid.cols - 1) ||
        v >= static_cast<double>(s.grid.rows - 1)) {
        return nan;
    }
    const auto c0 = static_cast<std::int32_t>(u);
    const auto r0 = static_cast<std::int32_t>(v);
    const double fu = u - static_cast<double>(c0);
    const double fv = v - static_cast<double>(r0);
    const std::size_t k = static_cast<std::size_t>(r0) * static_cast<std::size_t>(s.grid.cols) +
                          static_cast<std::size_t>(c0);
    const std::size_t below = k + static_cast<std::size_t>(s.grid.cols);
    const float z00 = s.elevation_m[k];
    const float z01 = s.elevation_m[k + 1U];
    const float z10 = s.elevation_m[below];
    const float z11 = s.elevation_m[below + 1U];
    if (terrain::isNoData(z00) || terrain::isNoData(z01) || terrain::isNoData(z10) || terrain::isNoData(z11)) {
        return nan;
    }
    const double top = (1.0 - fu) * static_cast<double>(z00) + fu * static_cast<double>(z01);
    const double bottom = (1.0 - fu) * static_cast<double>(z10) + fu * static_cast<double>(z11);
    return (1.0 - fv) * top + fv * bottom;
}

bool occluded(const ElevationSurface& s, const Vec3& node_site_m, const Vec3& eye_site_m, double margin_m) noexcept {
    const Vec3 d = eye_site_m - node_site_m;
    const double horizontal = std::sqrt(d.x() * d.x() + d.y() * d.y());
    const double step = 0.5 * s.grid.cell_m;
    if (!(horizontal > 2.0 * step)) {
        return false;  // the eye above the node's own cell
    }
    const std::int64_t bound = 2 * (static_cast<std::int64_t>(s.grid.cols) + s.grid.rows) + 2;
    const auto wanted = static_cast<std::int64_t>(horizontal / step);
    const std::int64_t steps = wanted < bound ? wanted : bound;
    for (std::int64_t i = 2; i <= steps; ++i) {
        const double t = static_cast<double>(i) * step / horizontal;
        const double line_up_m = -(node_site_m.z() + t * d.z());
        if (line_up_m > s.highest_m) {
            return false;
        }
        const double ground = surfaceElevation(s, node_site_m.x() + t * d.x(), node_site_m.y() + t * d.y());
        if (ground > line_up_m + margin_m) {
            return true;
        }
    }
    return false;
}

}  // namespace vtm::kriging::detail
