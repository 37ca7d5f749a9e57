// The template matcher's search region (polyline.hpp).
#include "polyline.hpp"

#include <algorithm>

#include "vtm/core/math.hpp"

namespace vtm::features::detail {
namespace {

// The guard of withinPolyline(): a segment's bounding box farther than this is skipped.
double guardOf(double limit_sq) noexcept { return limit_sq * (1.0 + 1e-6) + 1e-9; }

// Distance of t from the interval [min(a, b), max(a, b)] (0 inside).
double gap(double t, double a, double b) noexcept {
    return std::max({0.0, std::min(a, b) - t, t - std::max(a, b)});
}

// withinPolyline()'s test of the segment (a, b), guard included.
bool segmentWithin(const Vec2& p, const Vec2& a, const Vec2& b, double limit_sq, double guard) noexcept {
    const double gx = gap(p.x(), a.x(), b.x());
    const double gy = gap(p.y(), a.y(), b.y());
    if (gx * gx + gy * gy > guard) {
        return false;
    }
    const Vec2 d = b - a;
    const double len2 = d.squaredNorm();
    double s = 0.0;
    if (len2 > 0.0) {
        s = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
    }
    const Vec2 q = a + s * d;
    return (p - q).squaredNorm() <= limit_sq;
}

}  // namespace

std::int32_t nearestVertex(const Vec2& p, const Vec2* poly, std::int32_t n) noexcept {
    double best = (p - poly[0]).squaredNorm();
    std::int32_t vertex = 0;
    for (std::int32_t i = 1; i < n; ++i) {
        const double dv = (p - poly[i]).squaredNorm();
        if (dv < best) {
            best = dv;
            vertex = i;
        }
    }
    return vertex;
}

bool withinPolyline(const Vec2& p, const Vec2* poly, std::int32_t n, double limit_sq) noexcept {
    if (!((p - poly[0]).squaredNorm() > limit_sq)) {
        return true;
    }
    const double guard = guardOf(limit_sq);
    for (std::int32_t i = 1; i < n; ++i) {
        if (segmentWithin(p, poly[i - 1], poly[i], limit_sq, guard)) {
            return true;
        }
    }
    return false;
}

void PolylineScan::set(const Vec2* poly, std::int32_t n, double limit_sq) noexcept {
    poly_ = poly;
    n_ = std::clamp(n, std::int32_t{0}, kMaxPolylineVertices);
    limit_sq_ = limit_sq;
    guard_ = guardOf(limit_sq);
    // Beyond this distance in x alone a segment's box fails the guard whatever the row:
    // gx > reach gives gx^2 > guard with a margin far above rounding.
    const double reach = math::sqrt(guard_) * (1.0 + 1e-6) + 1.0;
    for (std::int32_t i = 1; i < n_; ++i) {
        lo_[i] = std::min(poly[i - 1].x(), poly[i].x()) - reach;
        hi_[i] = std::max(poly[i - 1].x(), poly[i].x()) + reach;
    }
    active_count_ = 0;
}

void PolylineScan::row(double y) noexcept {
    y_ = y;
    active_count_ = 0;
    for (std::int32_t i = 0; i < n_; ++i) {
        const double dy = y - poly_[i].y();
        dy2_[i] = dy * dy;
    }
    for (std::int32_t i = 1; i < n_; ++i) {
        // gx^2 >= 0, so a rounded gx^2 + gy^2 is above the guard whenever gy^2 is.
        const double gy = gap(y, poly_[i - 1].y(), poly_[i].y());
        if (!(gy * gy > guard_)) {
            active_[active_count_] = i;
            ++active_count_;
        }
    }
}

bool PolylineScan::within(double x) const noexcept {
    if (n_ == 0) {
        return false;
    }
    const double dx0 = x - poly_[0].x();
    if (!(dx0 * dx0 + dy2_[0] > limit_sq_)) {  // (p - poly[0]).squaredNorm(): dx^2 + dy^2
        return true;
    }
    const Vec2 p(x, y_);
    for (std::int32_t k = 0; k < active_count_; ++k) {
        const std::int32_t i = active_[k];
        if (x >= lo_[i] && x <= hi_[i] && segmentWithin(p, poly_[i - 1], poly_[i], limit_sq_, guard_)) {
            return true;
        }
    }
    return false;
}

std::int32_t PolylineScan::nearest(double x) const noexcept {
    if (n_ == 0) {
        return 0;
    }
    const double dx0 = x - poly_[0].x();
    double best = dx0 * dx0 + dy2_[0];
    std::int32_t vertex = 0;
    for (std::int32_t i = 1; i < n_; ++i) {
        if (!(dy2_[i] < best)) {
            continue;  // dx^2 + dy^2 >= dy^2 >= best after rounding too: not nearer
        }
        const double dx = x - poly_[i].x();
        const double dv = dx * dx + dy2_[i];
        if (dv < best) {
            best = dv;
            vertex = i;
        }
    }
    return vertex;
}

}  // namespace vtm::features::detail
