// Affine Lucas-Kanade refinement of one match (affine_refine.hpp).
#include "vtm/features/affine_refine.hpp"

#include <algorithm>
#include <cmath>

#include "bilinear.hpp"
#include "feature_limits.hpp"
#include "vtm/core/math.hpp"

namespace vtm::features {
namespace {

constexpr std::int32_t kHalf = kAffineWindow / 2;
constexpr std::int32_t kSamples = kAffineWindow * kAffineWindow;
constexpr std::int32_t kParams = 8;  // b (2), warp (4, row-major), gain, offset
constexpr double kGradientStep_px = 0.5;
using detail::kMaxWarpArea;  // the template matcher's trust bounds for a warp
using detail::kMaxWarpEntry;

using Mat8 = Eigen::Matrix<double, kParams, kParams>;
using Vec8 = Eigen::Matrix<double, kParams, 1>;

struct Params {
    Vec2 b = Vec2::Zero();
    Mat2 warp = Mat2::Identity();
    double gain = 1.0;
    double offset = 0.0;
};

using detail::sampleLinear;

// Whether centre + warp (u, v), |u|, |v| <= kHalf, widened by `margin`, lies inside the
// image's sample domain [0, w-1] x [0, h-1] (an affine image of a square: its extent is
// kHalf times the rows' absolute sums).
bool windowInside(const ImageView<const std::uint8_t>& img, const Vec2& centre, const Mat2& warp,
                  double margin) noexcept {
    const double half = static_cast<double>(kHalf);
    const double ex = half * (std::fabs(warp(0, 0)) + std::fabs(warp(0, 1))) + margin;
    const double ey = half * (std::fabs(warp(1, 0)) + std::fabs(warp(1, 1))) + margin;
    return img.width() >= 2 && img.height() >= 2 && centre.x() - ex >= 0.0 && centre.y() - ey >= 0.0 &&
           centre.x() + ex <= static_cast<double>(img.width() - 1) &&
           centre.y() + ey <= static_cast<double>(img.height() - 1);
}

bool warpUsable(const Mat2& w) noexcept {
    const double det = w(0, 0) * w(1, 1) - w(0, 1) * w(1, 0);
    const double biggest =
        std::max(std::max(std::fabs(w(0, 0)), std::fabs(w(0, 1))), std::max(std::fabs(w(1, 0)), std::fabs(w(1, 1))));
    return det >= 1.0 / kMaxWarpArea && det <= kMaxWarpArea && biggest <= kMaxWarpEntry;
}

// A's window around pixel_a (which windowInside has checked), row-major.
void sampleTemplate(const ImageView<const std::uint8_t>& img, const Vec2& a, double* values) noexcept {
    std::int32_t i = 0;
    for (std::int32_t v = -kHalf; v <= kHalf; ++v) {
        for (std::int32_t u = -kHalf; u <= kHalf; ++u) {
            values[i] = sampleLinear(img, a.x() + static_cast<double>(u), a.y() + static_cast<double>(v));
            ++i;
        }
    }
}

// Normal equations J^T J d = -J^T e of one Gauss-Newton step, e = B(b + W u) - gain A - offset,
// J = (gx, gy, gx u, gx v, gy u, gy v, -A, -1) at window offset (u, v). Its entries are
// sums of a few products per pixel times 1, u, v, u^2, u v, v^2: each row of the window
// (v fixed) sums the products times 1, u, u^2, and the row's sums enter the entries with
// v and v^2. A's own sums (A^2, A, the count) do not change between steps (TemplateSums).
struct TemplateSums {
    double aa = 0.0, a = 0.0, n = 0.0;
};

// One window row's sums over u (v fixed): the products times 1, u, u^2 (quadratic
// entries) or times 1, u (the entries linear in the window offset).
struct RowSums {
    double xx[3] = {}, xy[3] = {}, yy[3] = {};
    double xa[2] = {}, ya[2] = {}, gx[2] = {}, gy[2] = {}, xe[2] = {}, ye[2] = {};

    void add(double g_x, double g_y, double ia, double e, double du) noexcept {
        const double pxx = g_x * g_x, pxy = g_x * g_y, pyy = g_y * g_y;
        const double du2 = du * du;
        addQuadratic(xx, pxx, du, du2);
        addQuadratic(xy, pxy, du, du2);
        addQuadratic(yy, pyy, du, du2);
        addLinear(xa, g_x * ia, du);
        addLinear(ya, g_y * ia, du);
        addLinear(gx, g_x, du);
        addLinear(gy, g_y, du);
        addLinear(xe, g_x * e, du);
        addLinear(ye, g_y * e, du);
    }
    static void addQuadratic(double* acc, double value, double du, double du2) noexcept {
        acc[0] += value;
        acc[1] += value * du;
        acc[2] += value * du2;
    }
    static void addLinear(double* acc, double value, double du) noexcept {
        acc[0] += value;
        acc[1] += value * du;
    }
};

// The whole window's sums: quadratic entries times 1, u, v, u^2, u v, v^2; linear ones
// times 1, u, v; A e and e summed pixel by pixel.
struct WindowSums {
    double xx[6] = {}, xy[6] = {}, yy[6] = {};
    double xa[3] = {}, ya[3] = {}, gx[3] = {}, gy[3] = {}, xe[3] = {}, ye[3] = {};
    double ae = 0.0, e1 = 0.0;

    void addRow(const RowSums& r, double dv) noexcept {
        addQuadratic(xx, r.xx, dv);
        addQuadratic(xy, r.xy, dv);
        addQuadratic(yy, r.yy, dv);
        addLinear(xa, r.xa, dv);
        addLinear(ya, r.ya, dv);
        addLinear(gx, r.gx, dv);
        addLinear(gy, r.gy, dv);
        addLinear(xe, r.xe, dv);
        addLinear(ye, r.ye, dv);
    }
    static void addQuadratic(double* acc, const double* row, double dv) noexcept {
        acc[0] += row[0];
        acc[1] += row[1];
        acc[2] += row[0] * dv;
        acc[3] += row[2];
        acc[4] += row[1] * dv;
        acc[5] += row[0] * dv * dv;
    }
    static void addLinear(double* acc, const double* row, double dv) noexcept {
        acc[0] += row[0];
        acc[1] += row[1];
        acc[2] += row[0] * dv;
    }
    // J^T J and J^T e in the parameter order (bx, by, w00, w01, w10, w11, gain, offset).
    void normalEquations(const TemplateSums& ts, Mat8& jtj, Vec8& jtr) const noexcept {
        jtj << xx[0], xy[0], xx[1], xx[2], xy[1], xy[2], -xa[0], -gx[0],  //
            xy[0], yy[0], xy[1], xy[2], yy[1], yy[2], -ya[0], -gy[0],      //
            xx[1], xy[1], xx[3], xx[4], xy[3], xy[4], -xa[1], -gx[1],      //
            xx[2], xy[2], xx[4], xx[5], xy[4], xy[5], -xa[2], -gx[2],      //
            xy[1], yy[1], xy[3], xy[4], yy[3], yy[4], -ya[1], -gy[1],      //
            xy[2], yy[2], xy[4], xy[5], yy[4], yy[5], -ya[2], -gy[2],      //
            -xa[0], -ya[0], -xa[1], -xa[2], -ya[1], -ya[2], ts.aa, ts.a,  //
            -gx[0], -gy[0], -gx[1], -gx[2], -gy[1], -gy[2], ts.a, ts.n;
        jtr << xe[0], ye[0], xe[1], xe[2], ye[1], ye[2], -ae, -e1;
    }
};

void normalEquations(const ImageView<const std::uint8_t>& img_b, const double* values_a, const TemplateSums& ts,
                     const Params& p, Mat8& jtj, Vec8& jtr) noexcept {
    WindowSums w;
    std::int32_t i = 0;
    for (std::int32_t v = -kHalf; v <= kHalf; ++v) {
        RowSums r;
        const double dv = static_cast<double>(v);
        for (std::int32_t u = -kHalf; u <= kHalf; ++u) {
            const double du = static_cast<double>(u);
            const Vec2 q = p.b + p.warp * Vec2(du, dv);
            const detail::CrossSample cs = detail::sampleCross(img_b, q.x(), q.y(), kGradientStep_px);
            const double ib = cs.value, gx = cs.gx, gy = cs.gy;
            const double ia = values_a[i];
            ++i;
            const double e = ib - (p.gain * ia + p.offset);
            r.add(gx, gy, ia, e, du);
            w.ae += ia * e;
            w.e1 += e;
        }
        w.addRow(r, dv);
    }
    w.normalEquations(ts, jtj, jtr);
}

// NCC of A's window with B's warped window at p; -1 when either is flat.
double windowNcc(const ImageView<const std::uint8_t>& img_b, const double* values_a, const Params& p) noexcept {
    double sa = 0.0, sb = 0.0, saa = 0.0, sbb = 0.0, sab = 0.0;
    std::int32_t i = 0;
    for (std::int32_t v = -kHalf; v <= kHalf; ++v) {
        for (std::int32_t u = -kHalf; u <= kHalf; ++u) {
            const Vec2 q = p.b + p.warp * Vec2(static_cast<double>(u), static_cast<double>(v));
            const double ib = sampleLinear(img_b, q.x(), q.y());
            const double ia = values_a[i];
            ++i;
            sa += ia;
            sb += ib;
            saa += ia * ia;
            sbb += ib * ib;
            sab += ia * ib;
        }
    }
    const double n = static_cast<double>(kSamples);
    const double var_a = n * saa - sa * sa;
    const double var_b = n * sbb - sb * sb;
    if (!(var_a > 0.0 && var_b > 0.0)) {
        return -1.0;
    }
    return (n * sab - sa * sb) / math::sqrt(var_a * var_b);
}

// Solves m d = -r for a symmetric m by Cholesky (m = L L^T, in place in m's lower
// triangle). False when m is not positive definite (a pivot <= 1e-12 of the largest
// diagonal entry, or not finite) or d is not finite.
bool solveCholesky(Mat8& m, const Vec8& r, Vec8& d) noexcept {
    const double scale = m.diagonal().maxCoeff();
    if (!(scale > 0.0 && math::isFinite(scale))) {
        return false;
    }
    for (std::int32_t j = 0; j < kParams; ++j) {
        double pivot = m(j, j);
        for (std::int32_t k = 0; k < j; ++k) {
            pivot -= m(j, k) * m(j, k);
        }
        if (!(pivot > 1.0e-12 * scale)) {
            return false;
        }
        m(j, j) = math::sqrt(pivot);
        for (std::int32_t i = j + 1; i < kParams; ++i) {
            double v = m(i, j);
            for (std::int32_t k = 0; k < j; ++k) {
                v -= m(i, k) * m(j, k);
            }
            m(i, j) = v / m(j, j);
        }
    }
    for (std::int32_t i = 0; i < kParams; ++i) {  // L y = -r
        double v = -r(i);
        for (std::int32_t k = 0; k < i; ++k) {
            v -= m(i, k) * d(k);
        }
        d(i) = v / m(i, i);
    }
    for (std::int32_t i = kParams - 1; i >= 0; --i) {  // L^T d = y
        double v = d(i);
        for (std::int32_t k = i + 1; k < kParams; ++k) {
            v -= m(k, i) * d(k);
        }
        d(i) = v / m(i, i);
    }
    return math::isFinite(d.squaredNorm());
}

// Gauss-Newton on p; returns kAccepted when it ended with a usable warp inside image B
// (the acceptance tests on shift and score follow in refineAffine).
AffineOutcome fit(const ImageView<const std::uint8_t>& img_b, const double* values_a, const AffineRefineConfig& c,
                  Params& p, std::int32_t& steps) noexcept {
    TemplateSums ts;
    for (std::int32_t i = 0; i < kSamples; ++i) {
        ts.aa += values_a[i] * values_a[i];
        ts.a += values_a[i];
    }
    ts.n = static_cast<double>(kSamples);
    Mat8 jtj;
    Vec8 jtr;
    for (steps = 0; steps < c.max_steps;) {
        normalEquations(img_b, values_a, ts, p, jtj, jtr);
        Vec8 d;
        if (!solveCholesky(jtj, jtr, d)) {
            return AffineOutcome::kSingular;
        }
        ++steps;
        p.b += Vec2(d(0), d(1));
        p.warp(0, 0) += d(2);
        p.warp(0, 1) += d(3);
        p.warp(1, 0) += d(4);
        p.warp(1, 1) += d(5);
        p.gain += d(6);
        p.offset += d(7);
        if (!warpUsable(p.warp)) {
            return AffineOutcome::kBadWarp;
        }
        if (!windowInside(img_b, p.b, p.warp, kGradientStep_px)) {
            return AffineOutcome::kLeftImage;
        }
        if (d(0) * d(0) + d(1) * d(1) < kAffineConvergence_px * kAffineConvergence_px) {
            break;
        }
    }
    return AffineOutcome::kAccepted;
}

bool finite(const Vec2& v) noexcept { return math::isFinite(v.x()) && math::isFinite(v.y()); }

}  // namespace

Status AffineRefineConfig::validate() const noexcept {
    if (max_steps < 1 || max_steps > kAffineMaxSteps) {
        return Status(StatusCode::kInvalidConfig, "AffineRefineConfig.max_steps: must be 1..50", max_steps);
    }
    if (!(math::isFinite(max_shift_px) && max_shift_px > 0.0)) {
        return Status(StatusCode::kInvalidConfig, "AffineRefineConfig.max_shift_px: must be > 0 and finite");
    }
    if (!(min_score >= -1.f && min_score <= 1.f)) {
        return Status(StatusCode::kInvalidConfig, "AffineRefineConfig.min_score: must be in [-1, 1]");
    }
    return Status::ok();
}

Status refineAffine(const ImageView<const std::uint8_t>& image_a, const ImageView<const std::uint8_t>& image_b,
                    const Vec2& pixel_a, const Vec2& pixel_b, const Mat2& warp, const AffineRefineConfig& config,
                    AffineMatch& out) noexcept {
    out = AffineMatch{};
    out.pixel_b = pixel_b;
    VTM_RETURN_IF_ERROR(config.validate());
    if (!image_a.valid() || !image_b.valid()) {
        return Status(StatusCode::kInvalidArgument, "refineAffine: image_a or image_b is empty or malformed");
    }
    if (!finite(pixel_a) || !finite(pixel_b)) {
        return Status(StatusCode::kInvalidArgument, "refineAffine: pixel_a or pixel_b is not finite");
    }
    if (!math::isFinite(warp.squaredNorm())) {
        return Status(StatusCode::kInvalidArgument, "refineAffine: warp is not finite");
    }
    out.warp = warp;
    if (!windowInside(image_a, pixel_a, Mat2::Identity(), 0.0) ||
        !windowInside(image_b, pixel_b, warp, kGradientStep_px)) {
        out.outcome = AffineOutcome::kLeftImage;
        return Status::ok();
    }
    if (!warpUsable(warp)) {
        out.outcome = AffineOutcome::kBadWarp;
        return Status::ok();
    }
    double values_a[kSamples];
    sampleTemplate(image_a, pixel_a, values_a);
    Params p;
    p.b = pixel_b;
    p.warp = warp;
    out.outcome = fit(image_b, values_a, config, p, out.steps);
    if (out.outcome != AffineOutcome::kAccepted) {
        return Status::ok();
    }
    out.warp = p.warp;
    out.gain = p.gain;
    out.offset = p.offset;
    out.score = windowNcc(image_b, values_a, p);
    if ((p.b - pixel_b).squaredNorm() > config.max_shift_px * config.max_shift_px) {
        out.outcome = AffineOutcome::kMovedTooFar;
    } else if (out.score < static_cast<double>(config.min_score)) {
        out.outcome = AffineOutcome::kLowScore;
    } else {
        out.pixel_b = p.b;
    }
    return Status::ok();
}

}  // namespace vtm::features
