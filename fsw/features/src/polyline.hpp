// The template matcher's search region (private to fsw/features): the image of A's ray in
// B as a polyline of its samples, and for a position of B which sample is nearest and
// whether it lies within the matching margin. PolylineScan answers both for the positions
// of one row at a time, with the same bits as the plain functions and far fewer
// operations: the coarse scan asks them of every position of the region's bounding box.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"

namespace vtm::features::detail {

// The most vertices a polyline has (the matcher's ray samples).
constexpr std::int32_t kMaxPolylineVertices = 33;
// PolylineScan's envelope needs its vertices at least this far apart in x (pixels).
constexpr double kMinVertexGapX = 1e-2;

// Index of the vertex of poly[0..n) nearest to p (the first of equal distances).
[[nodiscard]] std::int32_t nearestVertex(const Vec2& p, const Vec2* poly, std::int32_t n) noexcept;

// Whether p is within the squared distance limit_sq of the polyline poly[0..n): its first
// vertex or some segment (closest point by the clamped projection) is. A segment whose
// bounding box lies farther than that, with a guard far above rounding (1e-6 relative),
// cannot be and is not projected on. A NaN distance to the first vertex counts as within,
// a NaN segment as not.
[[nodiscard]] bool withinPolyline(const Vec2& p, const Vec2* poly, std::int32_t n, double limit_sq) noexcept;

// nearestVertex() and withinPolyline() for the positions (x, y) of one row y: set() once
// per polyline (n <= kMaxPolylineVertices), row() once per row, then nearest(x) and
// within(x) return exactly what the functions return for (x, y). A row keeps only the
// segments whose bounding box comes within the guard of it, each with the x interval
// outside which it cannot be within; the distances to the vertices reuse the row's
// (y - v.y)^2; nearest() walks the vertices sorted by x outwards from x and stops on each
// side where (x - v.x)^2 alone is farther than the best, skipping a vertex whose row term
// alone is no nearer (equal distances: the lower index, as nearestVertex()). Before the
// walk it looks x up in the row's pieces: along a row the squared distance to vertex i is
// x^2 plus a line in x, -2 x_i x + x_i^2 + dy_i^2, so the nearest vertex is the lower
// envelope of those lines (row(): O(n), the vertices being sorted by x). Each piece is
// shrunk at both ends by far more than the rounding of the distances and of its ends
// (vertices at least kMinVertexGapX apart in x, distances bounded by the row's span), so
// inside a piece its vertex is the strict nearest whatever the rounding: the walk's
// answer. A position near a piece's end, outside the span, or on a polyline whose vertices
// are not that far apart in x (a near-vertical ray) takes the walk.
class PolylineScan {
public:
    void set(const Vec2* poly, std::int32_t n, double limit_sq) noexcept;
    void row(double y) noexcept;
    // Not const: within() remembers the segment that last held the position (tried first
    // next time: any segment answers the same), nearest() where the last answer lay in
    // the vertices sorted by x.
    [[nodiscard]] bool within(double x) noexcept {
        // Inline: most positions of a search lie in the sure interval of the last one.
        const std::int32_t h = sure_hint_;
        return (h < sure_count_ && x >= sure_lo_[h] && x <= sure_hi_[h]) || withinSlow(x);
    }
    // After row(): an interval [lo, hi] of x outside which within(x) is certainly false on
    // this row (the first vertex's reach and the active segments' intervals); lo > hi when
    // no position of the row can be within. NaN vertices: the whole line.
    void span(double& lo, double& hi) const noexcept;
    [[nodiscard]] std::int32_t nearest(double x) noexcept {
        // Inline: most positions of a search lie in the piece of the last one.
        const std::int32_t p = piece_at_;
        if (p < piece_count_ && x >= piece_lo_[p] && x <= piece_hi_[p]) {
            return piece_vertex_[p];
        }
        return nearestSlow(x);
    }

private:
    void addSure(const Vec2& a, const Vec2& b, double length) noexcept;
    void mergeSure() noexcept;
    void setPieces() noexcept;
    [[nodiscard]] bool withinSlow(double x) noexcept;
    [[nodiscard]] std::int32_t nearestSlow(double x) noexcept;
    [[nodiscard]] std::int32_t nearestByWalk(double x) noexcept;

    const Vec2* poly_ = nullptr;
    std::int32_t n_ = 0;
    double limit_sq_ = 0.0;
    double guard_ = 0.0;
    double reach_ = 0.0;  // beyond this in x alone nothing is within (set())
    double limit_ = 0.0;  // sqrt(limit_sq_)
    double y_ = 0.0;
    double lo_[kMaxPolylineVertices] = {};   // segment i (poly[i-1], poly[i]): x interval, widened
    double hi_[kMaxPolylineVertices] = {};
    double dy2_[kMaxPolylineVertices] = {};  // this row: (y - poly[i].y)^2
    double length_[kMaxPolylineVertices] = {};  // segment i: |poly[i] - poly[i-1]|
    // This row: x intervals whose positions are certainly within (each segment's band,
    // tightened and shrunk well beyond rounding), sorted and merged where they overlap.
    double sure_lo_[kMaxPolylineVertices] = {};
    double sure_hi_[kMaxPolylineVertices] = {};
    std::int32_t sure_count_ = 0;
    std::int32_t sure_hint_ = 0;  // within(): the interval the last x fell before or in
    std::int32_t active_[kMaxPolylineVertices] = {};
    std::int32_t active_count_ = 0;
    std::int32_t last_hit_ = 0;                     // segment that last held a position, 0: none
    std::int32_t by_x_[kMaxPolylineVertices] = {};  // vertex indices sorted by x
    double sorted_x_[kMaxPolylineVertices] = {};    // their x
    std::int32_t hint_ = 0;                         // nearest(): where the last x fell in sorted_x_
    bool finite_ = true;                            // every vertex finite (else the plain loop)
    // The envelope (setPieces()): vertices apart by at least kMinVertexGapX in x (exact
    // repeats of a vertex aside); this row's pieces, sorted, and the last one looked up.
    bool spread_ = false;
    double piece_lo_[kMaxPolylineVertices] = {};
    double piece_hi_[kMaxPolylineVertices] = {};
    std::int32_t piece_vertex_[kMaxPolylineVertices] = {};
    std::int32_t piece_count_ = 0;
    std::int32_t piece_at_ = 0;
};

}  // namespace vtm::features::detail
