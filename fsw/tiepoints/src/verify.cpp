// Parallax consistency and grid thinning (verify.hpp).
#include "vtm/tiepoints/verify.hpp"
#include "vtm/core/config_check.hpp"

#include "vtm/core/math.hpp"

namespace vtm::tiepoints {
namespace {

using features::Match;


// The up-to-n nearest other matches of match k within radius (ascending distance, ties
// by index): indices into `matches`, returns how many.
std::int32_t nearest(Span<const Match> matches, std::size_t k, std::int32_t n, double radius_px,
                     std::int32_t (&index)[kMaxParallaxNeighbours], double (&dist2)[kMaxParallaxNeighbours]) noexcept {
    std::int32_t found = 0;
    const double r2 = radius_px * radius_px;
    for (std::size_t m = 0U; m < matches.size(); ++m) {
        if (m == k) {
            continue;
        }
        const double d2 = (matches[m].pixel_a - matches[k].pixel_a).squaredNorm();
        if (d2 > r2 || (found == n && d2 >= dist2[n - 1])) {
            continue;
        }
        std::int32_t slot = found < n ? found : n - 1;  // insertion: strict < keeps the lower index first
        while (slot > 0 && dist2[slot - 1] > d2) {  // bound: n <= kMaxParallaxNeighbours
            index[slot] = index[slot - 1];
            dist2[slot] = dist2[slot - 1];
            --slot;
        }
        index[slot] = static_cast<std::int32_t>(m);
        dist2[slot] = d2;
        found = found < n ? found + 1 : n;
    }
    return found;
}

double median(double* v, std::int32_t n) noexcept {
    for (std::int32_t i = 1; i < n; ++i) {  // insertion sort: n <= kMaxParallaxNeighbours
        const double x = v[i];
        std::int32_t j = i;
        while (j > 0 && v[j - 1] > x) {  // bound: i < n <= kMaxParallaxNeighbours
            v[j] = v[j - 1];
            --j;
        }
        v[j] = x;
    }
    return (n % 2 == 1) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Vec2 parallaxOf(const Match& m) noexcept { return m.pixel_b - m.pixel_a; }

// A plane of the parallax: p(x) = c + G (x - x_match), one coefficient vector
// (c, G_x, G_y) per parallax component.
struct Plane {
    Vec3 cx = Vec3::Zero();
    Vec3 cy = Vec3::Zero();
    [[nodiscard]] Vec2 at(const Vec2& offset) const noexcept {
        const Vec3 row(1.0, offset.x(), offset.y());
        return Vec2(cx.dot(row), cy.dot(row));
    }
};

// Least-squares plane over the neighbours with use[] set, offsets relative to the match
// (so the constant term is the prediction). False when fewer than 3 are used or the
// layout is degenerate (collinear: the position block's determinant < 1e-6 of its scale^2).
bool fitPlane(Span<const Match> matches, const Match& at, const std::int32_t* index, const std::uint8_t* use,
              std::int32_t n, Plane& plane) noexcept {
    Mat3 a = Mat3::Zero();
    Vec3 bx = Vec3::Zero();
    Vec3 by = Vec3::Zero();
    std::int32_t used = 0;
    for (std::int32_t q = 0; q < n; ++q) {
        if (use[q] == 0U) {
            continue;
        }
        const Match& m = matches[static_cast<std::size_t>(index[q])];
        const Vec2 d = m.pixel_a - at.pixel_a;
        const Vec3 row(1.0, d.x(), d.y());
        a += row * row.transpose();
        const Vec2 p = parallaxOf(m);
        bx += row * p.x();
        by += row * p.y();
        ++used;
    }
    if (used < 3) {
        return false;
    }
    const double scale = a(1, 1) + a(2, 2);
    const double det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1);
    if (!(scale > 0.0) || det <= 1e-6 * scale * scale) {
        return false;
    }
    const Eigen::LDLT<Mat3> ldlt(a);
    if (ldlt.info() != Eigen::Success) {
        return false;
    }
    plane.cx = ldlt.solve(bx);
    plane.cy = ldlt.solve(by);
    return math::isFinite(plane.cx(0)) && math::isFinite(plane.cy(0));
}

Vec2 medianParallax(Span<const Match> matches, const std::int32_t* index, std::int32_t n) noexcept {
    double px[kMaxParallaxNeighbours];
    double py[kMaxParallaxNeighbours];
    for (std::int32_t q = 0; q < n; ++q) {
        const Vec2 p = parallaxOf(matches[static_cast<std::size_t>(index[q])]);
        px[q] = p.x();
        py[q] = p.y();
    }
    return Vec2(median(px, n), median(py, n));
}

// The exact plane through neighbours a, b, c (offsets relative to the match); false when
// the three are (nearly) collinear: twice the triangle's area below 1 % of its longest
// side squared.
bool planeOfThree(const Match* m[3], const Match& at, Plane& plane) noexcept {
    const Vec2 d0 = m[0]->pixel_a - at.pixel_a;
    const Vec2 e1 = m[1]->pixel_a - m[0]->pixel_a;
    const Vec2 e2 = m[2]->pixel_a - m[0]->pixel_a;
    const double area2 = e1.x() * e2.y() - e1.y() * e2.x();
    const double side2 = e1.squaredNorm() > e2.squaredNorm() ? e1.squaredNorm() : e2.squaredNorm();
    if (!((area2 < 0.0 ? -area2 : area2) > 0.01 * side2)) {
        return false;
    }
    // Gradient from the two edges (Cramer), constant term from the first point.
    const Vec2 p0 = parallaxOf(*m[0]);
    const Vec2 q1 = parallaxOf(*m[1]) - p0;
    const Vec2 q2 = parallaxOf(*m[2]) - p0;
    const double gxx = (q1.x() * e2.y() - q2.x() * e1.y()) / area2;
    const double gxy = (e1.x() * q2.x() - e2.x() * q1.x()) / area2;
    const double gyx = (q1.y() * e2.y() - q2.y() * e1.y()) / area2;
    const double gyy = (e1.x() * q2.y() - e2.x() * q1.y()) / area2;
    plane.cx = Vec3(p0.x() - gxx * d0.x() - gxy * d0.y(), gxx, gxy);
    plane.cy = Vec3(p0.y() - gyx * d0.x() - gyy * d0.y(), gyx, gyy);
    return true;
}

// How many neighbours agree with the plane within tolerance_px; with `use`, marks them.
std::int32_t support(Span<const Match> matches, const Match& at, const std::int32_t* index, std::int32_t n,
                     const Plane& plane, double tolerance_px, std::uint8_t* use) noexcept {
    std::int32_t count = 0;
    for (std::int32_t q = 0; q < n; ++q) {
        const Match& m = matches[static_cast<std::size_t>(index[q])];
        const bool agrees = (parallaxOf(m) - plane.at(m.pixel_a - at.pixel_a)).norm() <= tolerance_px;
        count += agrees ? 1 : 0;
        if (use != nullptr) {
            use[q] = agrees ? 1U : 0U;
        }
    }
    return count;
}

// The predicted parallax at match k from its neighbours. Robust: every triple of
// neighbours (in index order) gives an exact plane; the plane that the most neighbours
// agree with within tolerance_px wins (the first one on a tie), and the least-squares plane
// through those neighbours is the prediction (its constant term). The component-wise
// median of the neighbours' parallax where no triple spans a plane.
Vec2 predictParallax(Span<const Match> matches, std::size_t k, const std::int32_t* index, std::int32_t n,
                     double tolerance_px) noexcept {
    const Match& at = matches[k];
    std::int32_t best = 0;
    std::uint8_t use[kMaxParallaxNeighbours];
    for (std::int32_t a = 0; a < n; ++a) {
        for (std::int32_t b = a + 1; b < n; ++b) {
            for (std::int32_t c = b + 1; c < n; ++c) {
                const Match* three[3] = {&matches[static_cast<std::size_t>(index[a])],
                                         &matches[static_cast<std::size_t>(index[b])],
                                         &matches[static_cast<std::size_t>(index[c])]};
                Plane plane;
                if (!planeOfThree(three, at, plane)) {
                    continue;
                }
                const std::int32_t agree = support(matches, at, index, n, plane, tolerance_px, nullptr);
                if (agree > best) {
                    best = support(matches, at, index, n, plane, tolerance_px, use);
                }
            }
        }
    }
    Plane fitted;
    if (best >= 3 && fitPlane(matches, at, index, use, n, fitted)) {
        return fitted.at(Vec2::Zero());
    }
    return medianParallax(matches, index, n);
}

}  // namespace

Status ParallaxConfig::validate() const noexcept {
    if (neighbours < 3 || neighbours > kMaxParallaxNeighbours) {
        return invalidConfig("parallax.neighbours: must be 3..16", neighbours);
    }
    if (min_neighbours < 3 || min_neighbours > neighbours) {
        return invalidConfig("parallax.min_neighbours: must be 3..neighbours", min_neighbours);
    }
    if (!math::isFinite(max_radius_px) || max_radius_px <= 0.0) {
        return invalidConfig("parallax.max_radius_px: must be finite and > 0");
    }
    if (!math::isFinite(tolerance_px) || tolerance_px <= 0.0) {
        return invalidConfig("parallax.tolerance_px: must be finite and > 0");
    }
    return Status::ok();
}

Status ThinningConfig::validate() const noexcept {
    if (cols < 1 || cols > 256) {
        return invalidConfig("grid.cols: must be 1..256", cols);
    }
    if (rows < 1 || rows > 256) {
        return invalidConfig("grid.rows: must be 1..256", rows);
    }
    return Status::ok();
}

Status checkParallax(Span<const Match> matches, const ParallaxConfig& config, Span<std::uint8_t> keep,
                     ParallaxStats* stats) noexcept {
    VTM_RETURN_IF_ERROR(config.validate());
    if (matches.size() > static_cast<std::size_t>(features::kMaxFeatures)) {
        return Status(StatusCode::kInvalidArgument, "checkParallax: matches: more than kMaxFeatures",
                      static_cast<std::int64_t>(matches.size()));
    }
    if (keep.size() < matches.size()) {
        return Status(StatusCode::kSizeMismatch, "checkParallax: keep: shorter than matches",
                      static_cast<std::int64_t>(keep.size()));
    }
    ParallaxStats s;
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        std::int32_t index[kMaxParallaxNeighbours];
        double dist2[kMaxParallaxNeighbours];
        const std::int32_t n = nearest(matches, k, config.neighbours, config.max_radius_px, index, dist2);
        if (n < config.min_neighbours) {
            keep[k] = 0U;
            ++s.isolated;
            continue;
        }
        const Vec2 predicted = predictParallax(matches, k, index, n, config.tolerance_px);
        const bool ok = (parallaxOf(matches[k]) - predicted).norm() <= config.tolerance_px;
        keep[k] = ok ? 1U : 0U;
        ++(ok ? s.consistent : s.inconsistent);
    }
    if (stats != nullptr) {
        *stats = s;
    }
    return Status::ok();
}

Status thinByGrid(Span<const Match> matches, const ThinningConfig& grid, std::int32_t width, std::int32_t height,
                  Span<std::uint8_t> keep, std::int32_t& kept) noexcept {
    kept = 0;
    if (!grid.validate().isOk() || width < 1 || height < 1) {
        return Status(StatusCode::kInvalidArgument, "thinByGrid: grid outside 1..256 or image size < 1", width);
    }
    if (keep.size() < matches.size()) {
        return Status(StatusCode::kSizeMismatch, "thinByGrid: keep: shorter than matches",
                      static_cast<std::int64_t>(keep.size()));
    }
    const auto cellOf = [&](const Match& m) noexcept {
        const double fx = (m.pixel_a.x() + 0.5) * static_cast<double>(grid.cols) / static_cast<double>(width);
        const double fy = (m.pixel_a.y() + 0.5) * static_cast<double>(grid.rows) / static_cast<double>(height);
        std::int32_t cx = fx <= 0.0 ? 0 : static_cast<std::int32_t>(fx);
        std::int32_t cy = fy <= 0.0 ? 0 : static_cast<std::int32_t>(fy);
        cx = cx >= grid.cols ? grid.cols - 1 : cx;
        cy = cy >= grid.rows ? grid.rows - 1 : cy;
        return cy * grid.cols + cx;
    };
    // Pass 1 marks losers with 2 (a better kept match shares the cell); pass 2 clears them.
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        if (keep[k] == 0U) {
            continue;
        }
        const std::int32_t cell = cellOf(matches[k]);
        for (std::size_t m = 0U; m < matches.size(); ++m) {
            if (m == k || keep[m] == 0U || cellOf(matches[m]) != cell) {
                continue;
            }
            const bool earlier = m < k;  // ties go to the earlier match
            const bool better = matches[m].score > matches[k].score || (matches[m].score == matches[k].score && earlier);
            if (better) {
                keep[k] = 2U;
                break;
            }
        }
    }
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        keep[k] = keep[k] == 1U ? 1U : 0U;
        kept += keep[k];
    }
    return Status::ok();
}

}  // namespace vtm::tiepoints
