// Terrain::intersect(): first hit of a ray with the bilinear clipmap surface.
//
// The ray is cut into the pieces where one level governs (finest level containing the
// point): with I_k the ray's interval inside level k's square (I_0 in I_1 in ...), the
// pieces in ray order are I_{L-1} before I_{L-2}, ..., I_0, ..., I_{L-1} after I_{L-2}.
// Each piece is walked on its level's max-height mip pyramid: a mip cell is skipped when
// the ray's lowest elevation across it is above the cell's maximum, entered (one mip
// down) otherwise; a single grid cell is tested exactly (ray vs bilinear patch: a
// quadratic in t). Level borders lie on grid lines of both levels (design in
// docs/sim-terrain.md), so a piece never needs a cell of the finer level's interior.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/terrain.hpp"

namespace vtm::sim {

class TerrainRayCaster {
public:
    TerrainRayCaster(const Terrain& terrain, const Vec3& origin, const Vec3& dir) noexcept
        : t_(terrain), o_(origin), d_(dir) {
        const TerrainParams& p = terrain.params_;
        so_n_ = (origin.x() - p.centre_north_m) / p.finest_cell_m;
        so_e_ = (origin.y() - p.centre_east_m) / p.finest_cell_m;
        sd_n_ = dir.x() / p.finest_cell_m;
        sd_e_ = dir.y() / p.finest_cell_m;
    }

    TerrainHit run(double t_max, TerrainRayStats* stats) noexcept {
        TerrainHit hit;
        const int levels = t_.levels_;
        double lo[kMaxTerrainLevels] = {};
        double hi[kMaxTerrainLevels] = {};
        bool in[kMaxTerrainLevels] = {};
        for (int k = levels - 1; k >= 0; --k) {  // bound: levels
            in[k] = interval(k, t_max, lo[k], hi[k]);
            if (k + 1 < levels) {  // keep the nesting exact despite rounding
                lo[k] = std::max(lo[k], lo[k + 1]);
                hi[k] = std::min(hi[k], hi[k + 1]);
                in[k] = in[k] && in[k + 1] && lo[k] <= hi[k];
            }
        }
        bool done = false;
        for (int k = levels - 1; k >= 0 && !done; --k) {  // bound: levels (entry pieces)
            if (in[k]) {
                const double end = (k > 0 && in[k - 1]) ? lo[k - 1] : hi[k];
                done = traverse(k, lo[k], end, hit);
            }
        }
        for (int k = 1; k < levels && !done; ++k) {  // bound: levels (exit pieces)
            if (in[k] && in[k - 1]) {
                done = traverse(k, hi[k - 1], hi[k], hit);
            }
        }
        if (stats != nullptr) {
            stats->rays += 1U;
            stats->steps += steps_;
            stats->bound_exceeded += exceeded_ ? 1U : 0U;
        }
        return hit;
    }

private:
    // Grid coordinates on level k of the ray: U(t) = u0 + t du (north), V(t) likewise (east).
    struct Line {
        double u0;
        double du;
        double v0;
        double dv;
    };
    [[nodiscard]] Line line(int k) const noexcept {
        const double scale = 1.0 / static_cast<double>(std::int64_t{1} << static_cast<unsigned>(k));
        const double half = 0.5 * static_cast<double>(t_.n_);
        return Line{so_n_ * scale + half, sd_n_ * scale, so_e_ * scale + half, sd_e_ * scale};
    }
    [[nodiscard]] double elevation(double t) const noexcept { return -(o_.z() + t * d_.z()); }

    static bool slab(double x0, double dx, double top, double& lo, double& hi) noexcept {
        if (dx == 0.0) {
            return x0 >= 0.0 && x0 <= top;
        }
        const double a = (0.0 - x0) / dx;
        const double b = (top - x0) / dx;
        lo = std::max(lo, std::min(a, b));
        hi = std::min(hi, std::max(a, b));
        return lo <= hi;
    }

    // Ray interval inside level k's square, clipped to [0, t_max].
    bool interval(int k, double t_max, double& lo, double& hi) const noexcept {
        const Line l = line(k);
        const double top = static_cast<double>(t_.n_);
        lo = 0.0;
        hi = t_max;
        const bool a = slab(l.u0, l.du, top, lo, hi);
        const bool b = slab(l.v0, l.dv, top, lo, hi);
        return a && b && lo <= hi;
    }

    [[nodiscard]] float height(const Terrain::Level& lv, std::int32_t i, std::int32_t j) const noexcept {
        const std::size_t side = static_cast<std::size_t>(t_.n_) + 1U;
        return lv.height_m[static_cast<std::size_t>(i) * side + static_cast<std::size_t>(j)];
    }

    [[nodiscard]] double cellMax(const Terrain::Level& lv, int mip, std::int32_t i, std::int32_t j) const noexcept {
        if (mip == 0) {
            const float m = std::max(std::max(height(lv, i, j), height(lv, i + 1, j)),
                                     std::max(height(lv, i, j + 1), height(lv, i + 1, j + 1)));
            return static_cast<double>(m);
        }
        const std::size_t cells = static_cast<std::size_t>(t_.n_) >> static_cast<unsigned>(mip);
        return static_cast<double>(lv.mip_max_m[mip][static_cast<std::size_t>(i) * cells + static_cast<std::size_t>(j)]);
    }

    // Child (0 or 1) of a parent cell that the coordinate x enters moving with dx.
    static std::int32_t child(double x, double mid, double dx) noexcept {
        return (x > mid || (x == mid && dx > 0.0)) ? 1 : 0;
    }

    // Smallest root in [0, len] of a s^2 + b s + c with c < 0, or -1.
    static double firstRoot(double a, double b, double c, double len) noexcept {
        double r1 = -1.0;
        double r2 = -1.0;
        if (a == 0.0) {
            if (b != 0.0) {
                r1 = -c / b;
            }
        } else {
            const double disc = b * b - 4.0 * a * c;
            if (disc < 0.0) {
                return -1.0;
            }
            const double sq = std::sqrt(disc);
            const double q = -0.5 * (b + (b >= 0.0 ? sq : -sq));
            if (q != 0.0) {
                r1 = c / q;
                r2 = q / a;
            }
        }
        const bool ok1 = r1 >= 0.0 && r1 <= len;
        const bool ok2 = r2 >= 0.0 && r2 <= len;
        if (ok1 && ok2) {
            return std::min(r1, r2);
        }
        return ok1 ? r1 : (ok2 ? r2 : -1.0);
    }

    // Exact test against the bilinear patch of cell (i, j) on level k for t in [t0, t1].
    bool patch(int k, const Line& l, std::int32_t i, std::int32_t j, double t0, double t1,
               TerrainHit& hit) const noexcept {
        const Terrain::Level& lv = t_.level_[k];
        const double h00 = static_cast<double>(height(lv, i, j));
        const double h10 = static_cast<double>(height(lv, i + 1, j));
        const double h01 = static_cast<double>(height(lv, i, j + 1));
        const double h11 = static_cast<double>(height(lv, i + 1, j + 1));
        const double hu = h10 - h00;
        const double hv = h01 - h00;
        const double hk = h11 - h10 - h01 + h00;
        const double u0 = (l.u0 + t0 * l.du) - static_cast<double>(i);
        const double v0 = (l.v0 + t0 * l.dv) - static_cast<double>(j);
        // f(s) = surface - ray elevation along t = t0 + s; the ray elevation rises at -dz.
        const double c = h00 + u0 * hu + v0 * hv + u0 * v0 * hk - elevation(t0);
        double s = 0.0;
        if (c < 0.0) {
            const double b = hu * l.du + hv * l.dv + hk * (u0 * l.dv + v0 * l.du) + d_.z();
            s = firstRoot(hk * l.du * l.dv, b, c, t1 - t0);
            if (s < 0.0) {
                return false;
            }
        }  // c >= 0: the ray is already on or below the surface where it enters the cell
        const double t = t0 + s;
        const double u = std::clamp(u0 + s * l.du, 0.0, 1.0);
        const double v = std::clamp(v0 + s * l.dv, 0.0, 1.0);
        const double dh_dn = (hu + hk * v) / lv.cell_m;
        const double dh_de = (hv + hk * u) / lv.cell_m;
        const Vec3 n(-dh_dn, -dh_de, -1.0);
        hit.hit = true;
        hit.t_m = t;
        hit.point_site_m = o_ + t * d_;
        hit.normal_site = n / std::sqrt(n.squaredNorm());
        hit.level = k;
        return true;
    }

    // Walks the mip pyramid of level k over [ta, tb]; true on a hit.
    bool traverse(int k, double ta, double tb, TerrainHit& hit) noexcept {
        if (!(tb > ta)) {
            return false;
        }
        const Terrain::Level& lv = t_.level_[k];
        const Line l = line(k);
        const int top = t_.n_log2_;
        const std::int32_t sx = l.du > 0.0 ? 1 : -1;
        const std::int32_t sy = l.dv > 0.0 ? 1 : -1;
        constexpr double kInf = std::numeric_limits<double>::infinity();
        int mip = top;
        std::int32_t i = 0;
        std::int32_t j = 0;
        double t = ta;
        // A line crosses at most 2n + 2 cells of a level; each costs at most one descent
        // and one ascent per mip, so 4 (top + 1)(n + 2) iterations cannot be exceeded by
        // a correct walk.
        const std::int64_t bound = 4 * static_cast<std::int64_t>(top + 1) * (t_.n_ + 2);
        for (std::int64_t iter = 0; iter < bound; ++iter) {  // bound: 4 (samples_log2 + 1)(n + 2)
            ++steps_;
            const double size = static_cast<double>(std::int64_t{1} << static_cast<unsigned>(mip));
            const double x0 = static_cast<double>(i) * size;
            const double y0 = static_cast<double>(j) * size;
            const double txe = l.du > 0.0 ? (x0 + size - l.u0) / l.du : (l.du < 0.0 ? (x0 - l.u0) / l.du : kInf);
            const double tye = l.dv > 0.0 ? (y0 + size - l.v0) / l.dv : (l.dv < 0.0 ? (y0 - l.v0) / l.dv : kInf);
            const double te = std::max(t, std::min(std::min(txe, tye), tb));
            const double lowest = std::min(elevation(t), elevation(te));
            const double hmax = cellMax(lv, mip, i, j);
            if (lowest <= hmax + 1e-7 * (1.0 + std::fabs(hmax))) {
                if (mip > 0) {
                    --mip;
                    const double half = size * 0.5;
                    i = 2 * i + child(l.u0 + t * l.du, x0 + half, l.du);
                    j = 2 * j + child(l.v0 + t * l.dv, y0 + half, l.dv);
                    continue;
                }
                if (patch(k, l, i, j, t, te, hit)) {
                    return true;
                }
            }
            if (te >= tb) {
                return false;
            }
            t = te;
            const std::int32_t oi = i;
            const std::int32_t oj = j;
            i += (txe <= tye) ? sx : 0;
            j += (tye <= txe) ? sy : 0;
            const std::int32_t cells = t_.n_ >> static_cast<unsigned>(mip);
            if (i < 0 || j < 0 || i >= cells || j >= cells) {
                return false;  // left the level's square (tb is on its border)
            }
            if (mip < top && ((i >> 1) != (oi >> 1) || (j >> 1) != (oj >> 1))) {
                ++mip;
                i >>= 1;
                j >>= 1;
            }
        }
        exceeded_ = true;
        return false;
    }

    const Terrain& t_;
    Vec3 o_;
    Vec3 d_;
    double so_n_ = 0.0;  // origin offset from the centre in level-0 cells
    double so_e_ = 0.0;
    double sd_n_ = 0.0;  // direction in level-0 cells per metre
    double sd_e_ = 0.0;
    std::uint64_t steps_ = 0U;
    bool exceeded_ = false;
};

TerrainHit Terrain::intersect(const Vec3& origin_site_m, const Vec3& dir_site, double t_max_m,
                              TerrainRayStats* stats) const noexcept {
    if (!built_ || !(t_max_m > 0.0)) {
        return TerrainHit{};
    }
    TerrainRayCaster caster(*this, origin_site_m, dir_site);
    return caster.run(t_max_m, stats);
}

}  // namespace vtm::sim
