// The template matcher's search region (polyline.hpp).
#include "polyline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

// An x interval of the row y whose positions lie within the band of the segment (a, b)
// of length `length`: the projection's parameter inside [1e-9, 1 - 1e-9] and the distance
// from the segment's line below (1 - 1e-9) limit (the square root of limit_sq), so that segmentWithin() is true
// there whatever its rounding; then shrunk by far more than the rounding of the interval's
// own arithmetic. Empty (lo > hi) when there is none.
void sureInterval(const Vec2& a, const Vec2& b, double length, double y, double limit, double& lo,
                  double& hi) noexcept {
    lo = 1.0;
    hi = -1.0;
    const Vec2 d = b - a;
    const double len2 = d.squaredNorm();
    if (!(len2 > 0.0) || !(length > 0.0)) {
        return;
    }
    const double tight = 1.0 - 1e-9;
    const double reach = limit * tight * length;  // |cross(d, p - a)| below this
    const double c = d.x() * (y - a.y());                       // cross(d, p - a) = c - d.y (x - a.x)
    double u0 = -std::numeric_limits<double>::infinity();       // bounds of x - a.x
    double u1 = std::numeric_limits<double>::infinity();
    if (d.y() != 0.0) {
        const double p0 = (c - reach) / d.y();
        const double p1 = (c + reach) / d.y();
        u0 = std::min(p0, p1);
        u1 = std::max(p0, p1);
    } else if (!(std::fabs(c) < reach)) {
        return;
    }
    const double e = (y - a.y()) * d.y();  // (p - a) . d = (x - a.x) d.x + e
    const double s0 = 1e-9 * len2 - e;
    const double s1 = tight * len2 - e;
    if (d.x() != 0.0) {
        const double q0 = s0 / d.x();
        const double q1 = s1 / d.x();
        u0 = std::max(u0, std::min(q0, q1));
        u1 = std::min(u1, std::max(q0, q1));
    } else if (!(s0 <= 0.0 && s1 >= 0.0)) {
        return;
    }
    if (!(u0 <= u1) || !std::isfinite(u0) || !std::isfinite(u1)) {
        return;
    }
    const double x0 = a.x() + u0;
    const double x1 = a.x() + u1;
    const double shrink = 1e-9 * (1.0 + std::fabs(x0) + std::fabs(x1) + std::fabs(a.x()));
    lo = x0 + shrink;
    hi = x1 - shrink;
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
    reach_ = reach;
    limit_ = math::sqrt(limit_sq);
    for (std::int32_t i = 1; i < n_; ++i) {
        lo_[i] = std::min(poly[i - 1].x(), poly[i].x()) - reach;
        hi_[i] = std::max(poly[i - 1].x(), poly[i].x()) + reach;
        length_[i] = math::sqrt((poly[i] - poly[i - 1]).squaredNorm());
    }
    active_count_ = 0;
    last_hit_ = 0;
    hint_ = 0;
    // The vertices by x (insertion sort, at most 33; ties by index).
    finite_ = true;
    for (std::int32_t i = 0; i < n_; ++i) {
        finite_ = finite_ && std::isfinite(poly[i].x()) && std::isfinite(poly[i].y());
        std::int32_t j = i;
        while (j > 0 && sorted_x_[j - 1] > poly[i].x()) {  // bound: j <= i < 33
            sorted_x_[j] = sorted_x_[j - 1];
            by_x_[j] = by_x_[j - 1];
            --j;
        }
        sorted_x_[j] = poly[i].x();
        by_x_[j] = i;
    }
    // The envelope's condition: neighbours by x at least kMinVertexGapX apart, or the same point.
    spread_ = finite_;
    for (std::int32_t k = 1; k < n_ && spread_; ++k) {
        const Vec2& a = poly[by_x_[k - 1]];
        const Vec2& b = poly[by_x_[k]];
        spread_ = b.x() - a.x() >= kMinVertexGapX || (b.x() == a.x() && b.y() == a.y());
    }
    piece_count_ = 0;
}

// The sure interval of one segment on this row, kept sorted by lo (insertion, at most 32).
void PolylineScan::addSure(const Vec2& a, const Vec2& b, double length) noexcept {
    double lo = 0.0, hi = 0.0;
    sureInterval(a, b, length, y_, limit_, lo, hi);
    if (!(lo <= hi)) {
        return;
    }
    std::int32_t j = sure_count_;
    while (j > 0 && sure_lo_[j - 1] > lo) {  // bound: j <= sure_count_ < 33
        sure_lo_[j] = sure_lo_[j - 1];
        sure_hi_[j] = sure_hi_[j - 1];
        --j;
    }
    sure_lo_[j] = lo;
    sure_hi_[j] = hi;
    ++sure_count_;
}

// Overlapping sure intervals become one (a position in either is in the union).
void PolylineScan::mergeSure() noexcept {
    std::int32_t m = 0;
    for (std::int32_t k = 1; k < sure_count_; ++k) {
        if (sure_lo_[k] <= sure_hi_[m]) {
            sure_hi_[m] = std::max(sure_hi_[m], sure_hi_[k]);
        } else {
            ++m;
            sure_lo_[m] = sure_lo_[k];
            sure_hi_[m] = sure_hi_[k];
        }
    }
    sure_count_ = sure_count_ > 0 ? m + 1 : 0;
}

void PolylineScan::row(double y) noexcept {
    y_ = y;
    active_count_ = 0;
    last_hit_ = 0;
    sure_count_ = 0;
    sure_hint_ = 0;
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
            if (finite_) {
                addSure(poly_[i - 1], poly_[i], length_[i]);
            }
        }
    }
    mergeSure();
    setPieces();
}

// The lower envelope of the lines -2 x_i x + x_i^2 + dy_i^2 over the vertices sorted by x
// (each vertex nearer than its left neighbours right of where it meets them), then each
// piece shrunk by tol at its inner ends and clipped to the span (polyline.hpp).
void PolylineScan::setPieces() noexcept {
    piece_count_ = 0;
    piece_at_ = 0;
    double lo = 0.0, hi = 0.0;
    span(lo, hi);
    if (!spread_ || n_ == 0 || !(lo <= hi) || !std::isfinite(y_)) {
        return;
    }
    double reach = std::max(std::fabs(lo), std::fabs(hi));
    double max_dy2 = 0.0;
    for (std::int32_t i = 0; i < n_; ++i) {
        reach = std::max(reach, std::fabs(poly_[i].x()));
        max_dy2 = std::max(max_dy2, dy2_[i]);
    }
    // Every squared distance the walk compares for x in [lo, hi] is at most `big`, so its
    // rounding is below 1e-15 big; inside a piece, tol from its ends, the next nearest
    // vertex is farther by at least 2 kMinVertexGapX (tol - the ends' own rounding) > eps.
    const double big = 4.0 * reach * reach + max_dy2;
    const double eps = 1e-12 * (1.0 + big);
    const double tol = eps / (2.0 * kMinVertexGapX) + 1e-9 * (1.0 + reach + max_dy2 / kMinVertexGapX);
    std::int32_t vertex[kMaxPolylineVertices];
    double start[kMaxPolylineVertices];  // where vertex[k] becomes the nearest
    std::int32_t count = 0;
    for (std::int32_t k = 0; k < n_; ++k) {  // bound: n_ <= 33; each vertex pushed once, popped at most once
        const std::int32_t i = by_x_[k];
        const double xi = poly_[i].x();
        if (count > 0 && xi == poly_[vertex[count - 1]].x()) {
            continue;  // the same point as a lower index (spread_): that one wins the tie
        }
        double meet = -std::numeric_limits<double>::infinity();
        while (count > 0) {  // bound: pops at most the count - 1 vertices pushed before
            const std::int32_t j = vertex[count - 1];
            const double xj = poly_[j].x();
            meet = 0.5 * (xj + xi) + (dy2_[i] - dy2_[j]) / (2.0 * (xi - xj));
            if (count > 1 && meet <= start[count - 1]) {
                --count;  // j is nowhere the nearest
                continue;
            }
            break;
        }
        vertex[count] = i;
        start[count] = meet;  // -inf for the first vertex (nothing to meet)
        ++count;
    }
    for (std::int32_t k = 0; k < count; ++k) {
        const double a = k == 0 ? lo : std::max(lo, start[k] + tol);
        const double b = k + 1 == count ? hi : std::min(hi, start[k + 1] - tol);
        if (a <= b) {
            piece_lo_[piece_count_] = a;
            piece_hi_[piece_count_] = b;
            piece_vertex_[piece_count_] = vertex[k];
            ++piece_count_;
        }
    }
}

bool PolylineScan::withinSlow(double x) noexcept {
    if (n_ == 0) {
        return false;
    }
    const double dx0 = x - poly_[0].x();
    if (!(dx0 * dx0 + dy2_[0] > limit_sq_)) {  // (p - poly[0]).squaredNorm(): dx^2 + dy^2
        return true;
    }
    // Inside a sure interval: true, as the tests below would say. The positions of a row
    // come in increasing x, so the interval is found from the last one.
    if (sure_hint_ > 0 && x < sure_lo_[sure_hint_]) {
        sure_hint_ = 0;
    }
    while (sure_hint_ < sure_count_ && sure_hi_[sure_hint_] < x) {  // bound: sure_count_ <= 32
        ++sure_hint_;
    }
    if (sure_hint_ < sure_count_ && x >= sure_lo_[sure_hint_]) {
        return true;
    }
    const Vec2 p(x, y_);
    // Any segment that holds p answers true, so the order of the tests does not matter:
    // the last one that held a position of this row first (usually the same segment).
    const std::int32_t last = last_hit_;
    if (last > 0 && x >= lo_[last] && x <= hi_[last] && segmentWithin(p, poly_[last - 1], poly_[last], limit_sq_, guard_)) {
        return true;
    }
    for (std::int32_t k = 0; k < active_count_; ++k) {
        const std::int32_t i = active_[k];
        if (i != last && x >= lo_[i] && x <= hi_[i] && segmentWithin(p, poly_[i - 1], poly_[i], limit_sq_, guard_)) {
            last_hit_ = i;
            return true;
        }
    }
    return false;
}

void PolylineScan::span(double& lo, double& hi) const noexcept {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    if (n_ == 0) {
        return;
    }
    if (!finite_) {
        lo = -std::numeric_limits<double>::infinity();
        hi = std::numeric_limits<double>::infinity();
        return;
    }
    // within(): the first vertex needs dx0^2 <= limit_sq (< guard: |dx0| < reach_), a
    // segment x in [lo_, hi_].
    if (!(dy2_[0] > limit_sq_)) {
        lo = poly_[0].x() - reach_;
        hi = poly_[0].x() + reach_;
    }
    for (std::int32_t k = 0; k < active_count_; ++k) {
        const std::int32_t i = active_[k];
        lo = std::min(lo, lo_[i]);
        hi = std::max(hi, hi_[i]);
    }
}

std::int32_t PolylineScan::nearestSlow(double x) noexcept {
    if (piece_count_ > 0) {
        // The positions of a row come in increasing x: the piece from the last one's.
        std::int32_t p = x < piece_lo_[piece_at_] ? 0 : piece_at_;
        while (p + 1 < piece_count_ && x >= piece_lo_[p + 1]) {  // bound: piece_count_ <= 33
            ++p;
        }
        piece_at_ = p;
        if (x >= piece_lo_[p] && x <= piece_hi_[p]) {
            return piece_vertex_[p];
        }
    }
    return nearestByWalk(x);
}

std::int32_t PolylineScan::nearestByWalk(double x) noexcept {
    if (n_ == 0) {
        return 0;
    }
    if (!finite_) {
        return nearestVertex(Vec2(x, y_), poly_, n_);
    }
    // Outwards from x through the vertices sorted by x: on each side (x - v.x)^2 only grows,
    // and dx^2 + dy^2 >= dx^2 after rounding too, so a side ends where dx^2 > best.
    // hi: the first sorted vertex with x >= the position, found from the last call's
    // (the scan moves along a row: usually no step or one).
    std::int32_t hi = hint_;
    while (hi > 0 && sorted_x_[hi - 1] >= x) {  // bound: n_ <= 33
        --hi;
    }
    while (hi < n_ && sorted_x_[hi] < x) {  // bound: n_ <= 33
        ++hi;
    }
    hint_ = hi;
    std::int32_t lo = hi - 1;
    double best = std::numeric_limits<double>::infinity();
    std::int32_t vertex = n_;
    auto consider = [&](std::int32_t s, bool& go) {
        const std::int32_t i = by_x_[s];
        const double dx = x - poly_[i].x();
        const double dx2 = dx * dx;
        if (dx2 > best) {
            go = false;
            return;
        }
        if (!(dy2_[i] <= best)) {
            return;  // dy^2 alone is farther
        }
        const double dv = dx2 + dy2_[i];
        if (dv < best || (dv == best && i < vertex)) {
            best = dv;
            vertex = i;
        }
    };
    bool goLo = lo >= 0;
    bool goHi = hi < n_;
    while (goLo || goHi) {  // bound: each step moves lo down or hi up, at most n_ steps
        if (goHi) {
            consider(hi, goHi);
            ++hi;
            goHi = goHi && hi < n_;
        }
        if (goLo) {
            consider(lo, goLo);
            --lo;
            goLo = goLo && lo >= 0;
        }
    }
    return vertex;
}

}  // namespace vtm::features::detail
