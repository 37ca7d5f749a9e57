// Camera model geometry (vtm/core/camera_model.hpp, docs/camera-models.md).
// Only + - * / and sqrt on doubles (built with -ffp-contract=off): the same bits on
// every target. No heap, no recursion, every loop has a fixed bound.
#include "vtm/core/camera_model.hpp"

#include <cmath>
#include <cstddef>

#include "vtm/core/assert.hpp"
#include "vtm/core/math.hpp"

namespace vtm {
namespace {

// Newton is stopped when the re-distorted point matches the target within this
// (relative to 1 + |target|): a few ulp, reached in 3..6 steps for real lenses.
constexpr double kConvergedTolerance = 1e-15;
// A point that never got below kConvergedTolerance (rounding noise near a root) is still
// accepted if within this; the round trip then is still far below 1e-9 px.
constexpr double kAcceptTolerance = 1e-12;
// |v|^2 within 2e-6 of 1: |v| within about 1e-6 of 1 (calibration files give 6-7 digits).
constexpr double kUnitTolerance = 2e-6;
// Sines below this count as parallel (H, V against A): 1e-9 rad.
constexpr double kParallelSine = 1e-9;
// Fold scan: steps per maximum corner radius, and how far beyond the corners it must reach.
constexpr int kFoldScanStepsPerRadius = 256;
constexpr int kFoldScanMaxSteps = 4 * kFoldScanStepsPerRadius;
constexpr double kFoldScanMargin = 1.05;

Vec3 vec(const double (&v)[3]) noexcept { return Vec3(v[0], v[1], v[2]); }

bool isUnit(const Vec3& v) noexcept {
    const double n2 = v.dot(v);
    return n2 >= 1.0 - kUnitTolerance && n2 <= 1.0 + kUnitTolerance;
}

Vec3 normalised(const Vec3& v) noexcept { return v / math::sqrt(v.dot(v)); }

// ----------------------------------------------------------------- radial polynomial --
// The radial part of both distortion models as a function of the undistorted radius k
// (normalised-plane radius for Brown, tan of the angle to O for CAHVOR):
//   f(k) = k (q0 + q1 k^2 + q2 k^4 + q3 k^6),  f'(k) = q0 + 3 q1 k^2 + 5 q2 k^4 + 7 q3 k^6.
struct RadialPolynomial {
    double q0 = 1.0, q1 = 0.0, q2 = 0.0, q3 = 0.0;

    [[nodiscard]] double factor(double k2) const noexcept { return q0 + k2 * (q1 + k2 * (q2 + k2 * q3)); }
    [[nodiscard]] double slope(double k2) const noexcept {
        return q0 + k2 * (3.0 * q1 + k2 * (5.0 * q2 + k2 * 7.0 * q3));
    }
};

RadialPolynomial brownRadial(const CameraModel& m) noexcept { return {1.0, m.k1, m.k2, m.k3}; }
RadialPolynomial cahvorRadial(const CameraModel& m) noexcept { return {1.0 + m.r[0], m.r[1], m.r[2], 0.0}; }

// True when f is strictly increasing from 0 until it exceeds the largest distorted
// radius of the image (times a margin): every distorted radius up to the corners then
// has exactly one undistorted radius.
bool radialIsMonotonic(const RadialPolynomial& p, double max_distorted) noexcept {
    const double target = kFoldScanMargin * max_distorted;
    const double step = max_distorted / static_cast<double>(kFoldScanStepsPerRadius);
    for (int i = 0; i <= kFoldScanMaxSteps; ++i) {  // bound: kFoldScanMaxSteps + 1
        const double k = step * static_cast<double>(i);
        const double k2 = k * k;
        if (!(p.slope(k2) > 0.0)) {
            return false;
        }
        if (k * p.factor(k2) > target) {
            return true;
        }
    }
    return false;  // compresses the corners by more than 4x: not a lens we model
}

// Solves k f-factor(k^2) = target (target >= 0) by Newton from k = target.
bool invertRadial(const RadialPolynomial& p, double target, double& k) noexcept {
    k = target;
    double residual = 0.0;
    for (int i = 0; i < kMaxUndistortIterations; ++i) {  // bound: kMaxUndistortIterations
        const double k2 = k * k;
        residual = k * p.factor(k2) - target;
        if (std::fabs(residual) <= kConvergedTolerance * (1.0 + target)) {
            return true;
        }
        const double slope = p.slope(k2);
        if (!(slope > 0.0)) {
            return false;  // beyond the fold: no unique inverse
        }
        k -= residual / slope;
    }
    return std::fabs(residual) <= kAcceptTolerance * (1.0 + target);
}

// ---------------------------------------------------------------------- pinhole+Brown --
struct BrownJacobian {
    Vec2 distorted = Vec2::Zero();
    double dxa = 0.0, dxb = 0.0, dya = 0.0, dyb = 0.0;  // d(distorted)/d(a, b)
};

Vec2 distortBrown(const CameraModel& m, double a, double b) noexcept {
    const double r2 = a * a + b * b;
    const double radial = brownRadial(m).factor(r2);
    return {a * radial + 2.0 * m.p1 * a * b + m.p2 * (r2 + 2.0 * a * a),
            b * radial + m.p1 * (r2 + 2.0 * b * b) + 2.0 * m.p2 * a * b};
}

BrownJacobian distortBrownWithJacobian(const CameraModel& m, double a, double b) noexcept {
    BrownJacobian j;
    const double r2 = a * a + b * b;
    const double radial = brownRadial(m).factor(r2);
    const double dradial = m.k1 + r2 * (2.0 * m.k2 + r2 * 3.0 * m.k3);  // d(radial)/d(r2)
    j.distorted = distortBrown(m, a, b);
    j.dxa = radial + 2.0 * a * a * dradial + 2.0 * m.p1 * b + 6.0 * m.p2 * a;
    j.dxb = 2.0 * a * b * dradial + 2.0 * m.p1 * a + 2.0 * m.p2 * b;
    j.dya = j.dxb;
    j.dyb = radial + 2.0 * b * b * dradial + 6.0 * m.p1 * b + 2.0 * m.p2 * a;
    return j;
}

Status projectBrown(const CameraModel& m, const Vec3& p, Vec2& pixel) noexcept {
    if (!(p.z() > 0.0)) {
        return Status(StatusCode::kDegenerate, "projectPoint: point at or behind the camera (Z <= 0)");
    }
    const double a = p.x() / p.z();
    const double b = p.y() / p.z();
    if (!(brownRadial(m).slope(a * a + b * b) > 0.0)) {
        return Status(StatusCode::kDegenerate, "projectPoint: point beyond the radius where k1 k2 k3 fold back");
    }
    const Vec2 d = distortBrown(m, a, b);
    pixel = Vec2(m.fx_px * d.x() + m.cx_px, m.fy_px * d.y() + m.cy_px);
    return Status::ok();
}

// Newton on the 2D distortion, started at the distorted point itself.
Status backProjectBrown(const CameraModel& m, const Vec2& pixel, CameraRay& ray) noexcept {
    const Vec2 target((pixel.x() - m.cx_px) / m.fx_px, (pixel.y() - m.cy_px) / m.fy_px);
    const double scale = 1.0 + std::fabs(target.x()) + std::fabs(target.y());
    double a = target.x();
    double b = target.y();
    double error = 0.0;
    bool converged = false;
    for (int i = 0; i < kMaxUndistortIterations && !converged; ++i) {  // bound: kMaxUndistortIterations
        const BrownJacobian j = distortBrownWithJacobian(m, a, b);
        const double ex = j.distorted.x() - target.x();
        const double ey = j.distorted.y() - target.y();
        error = std::fabs(ex) + std::fabs(ey);
        converged = error <= kConvergedTolerance * scale;
        const double det = j.dxa * j.dyb - j.dxb * j.dya;
        if (!converged && !(det > 0.0)) {
            return Status(StatusCode::kDegenerate, "backProjectPixel: distortion folds over at this pixel");
        }
        if (!converged) {
            a -= (j.dyb * ex - j.dxb * ey) / det;
            b -= (j.dxa * ey - j.dya * ex) / det;
        }
    }
    if (!converged && !(error <= kAcceptTolerance * scale)) {
        return Status(StatusCode::kDegenerate, "backProjectPixel: distortion inversion did not converge");
    }
    ray.origin_m = Vec3::Zero();
    ray.direction = normalised(Vec3(a, b, 1.0));
    return Status::ok();
}

// ---------------------------------------------------------------------------- CAHV(OR) --
Status projectCahvLinear(const CameraModel& m, const Vec3& d, Vec2& pixel) noexcept {
    const double alpha = d.dot(vec(m.a));
    if (!(alpha > 0.0)) {
        return Status(StatusCode::kDegenerate, "projectPoint: point at or behind the camera ((P - C).A <= 0)");
    }
    pixel = Vec2(d.dot(vec(m.h)) / alpha, d.dot(vec(m.v)) / alpha);
    return Status::ok();
}

Status projectCahvor(const CameraModel& m, const Vec3& d, Vec2& pixel) noexcept {
    const Vec3 o = normalised(vec(m.o));
    const double zeta = d.dot(o);
    if (!(zeta > 0.0)) {
        return Status(StatusCode::kDegenerate, "projectPoint: point at or behind the camera ((P - C).O <= 0)");
    }
    const Vec3 lambda = d - zeta * o;
    const double tau = lambda.dot(lambda) / (zeta * zeta);
    const RadialPolynomial radial = cahvorRadial(m);
    if (!(radial.slope(tau) > 0.0)) {
        return Status(StatusCode::kDegenerate, "projectPoint: point beyond the radius where R folds back");
    }
    const double mu = radial.factor(tau) - 1.0;  // r0 + r1 tau + r2 tau^2
    return projectCahvLinear(m, d + mu * lambda, pixel);
}

// Unit direction of the CAHV ray through (x, y): perpendicular to H - xA and V - yA,
// on the side of A.
Status cahvDirection(const CameraModel& m, const Vec2& pixel, Vec3& direction) noexcept {
    const Vec3 a = vec(m.a);
    Vec3 w = (vec(m.v) - pixel.y() * a).cross(vec(m.h) - pixel.x() * a);
    const double n2 = w.dot(w);
    if (!(n2 > 0.0) || !math::isFinite(n2)) {
        return Status(StatusCode::kDegenerate, "backProjectPixel: no ray through this pixel");
    }
    w /= math::sqrt(n2);
    direction = (w.dot(a) < 0.0) ? Vec3(-w) : w;
    return Status::ok();
}

// Undoes the CAHVOR radial move: the distorted direction w = zeta' O + lambda' gives the
// undistorted one zeta' O + lambda' / (1 + mu), where k = |lambda| / zeta solves
// k (1 + mu(k^2)) = |lambda'| / zeta' (Gennery 2001; JPL's cahvor_2d_to_3d).
Status undistortCahvor(const CameraModel& m, Vec3& direction) noexcept {
    const Vec3 o = normalised(vec(m.o));
    const double zeta = direction.dot(o);
    if (!(zeta > 0.0)) {
        return Status(StatusCode::kDegenerate, "backProjectPixel: ray 90 degrees or more from O");
    }
    const Vec3 lambda = direction - zeta * o;
    const double distorted = math::sqrt(lambda.dot(lambda)) / zeta;
    const RadialPolynomial radial = cahvorRadial(m);
    double k = 0.0;
    if (!invertRadial(radial, distorted, k)) {
        return Status(StatusCode::kDegenerate, "backProjectPixel: distortion inversion did not converge");
    }
    const double one_plus_mu = radial.factor(k * k);
    direction = normalised(zeta * o + lambda / one_plus_mu);
    return Status::ok();
}

}  // namespace

Status projectPoint(const CameraModel& model, const Vec3& point_m, Vec2& pixel) noexcept {
    switch (model.kind) {
        case CameraModelKind::kPinholeBrown:
            return projectBrown(model, point_m, pixel);
        case CameraModelKind::kCahv:
            return projectCahvLinear(model, point_m - vec(model.c), pixel);
        case CameraModelKind::kCahvor:
            return projectCahvor(model, point_m - vec(model.c), pixel);
        case CameraModelKind::kNone:
            break;
    }
    VTM_ASSERT(false);  // projectPoint: model kind is kNone
    return Status(StatusCode::kInvalidArgument, "projectPoint: camera model kind is none");
}

Status backProjectPixel(const CameraModel& model, const Vec2& pixel, CameraRay& ray) noexcept {
    if (model.kind == CameraModelKind::kPinholeBrown) {
        return backProjectBrown(model, pixel, ray);
    }
    VTM_ASSERT(model.kind == CameraModelKind::kCahv || model.kind == CameraModelKind::kCahvor);
    Vec3 direction = Vec3::UnitZ();
    VTM_RETURN_IF_ERROR(cahvDirection(model, pixel, direction));
    if (model.kind == CameraModelKind::kCahvor) {
        VTM_RETURN_IF_ERROR(undistortCahvor(model, direction));
    }
    ray.origin_m = vec(model.c);
    ray.direction = direction;
    return Status::ok();
}

CameraModel makePinhole(std::uint16_t width_px, std::uint16_t height_px, double hfov_deg) noexcept {
    VTM_ASSERT(width_px > 0U && height_px > 0U);
    VTM_ASSERT(hfov_deg > 0.0 && hfov_deg < 180.0);
    const double half_rad = 0.5 * hfov_deg * (math::kPi / 180.0);
    const double tan_half = math::sin(half_rad) / math::cos(half_rad);
    CameraModel m;
    m.kind = CameraModelKind::kPinholeBrown;
    m.width_px = width_px;
    m.height_px = height_px;
    m.fx_px = 0.5 * static_cast<double>(width_px) / tan_half;
    m.fy_px = m.fx_px;
    m.cx_px = 0.5 * (static_cast<double>(width_px) - 1.0);
    m.cy_px = 0.5 * (static_cast<double>(height_px) - 1.0);
    return m;
}

CameraModel cahvFromPinhole(const CameraModel& pinhole) noexcept {
    VTM_ASSERT(pinhole.kind == CameraModelKind::kPinholeBrown);
    CameraModel m;
    m.kind = CameraModelKind::kCahv;
    m.width_px = pinhole.width_px;
    m.height_px = pinhole.height_px;
    // x = (fx X + cx Z) / Z: H = fx x^ + cx A, V = fy y^ + cy A, A = z^, C = 0.
    m.a[2] = 1.0;
    m.h[0] = pinhole.fx_px;
    m.h[2] = pinhole.cx_px;
    m.v[1] = pinhole.fy_px;
    m.v[2] = pinhole.cy_px;
    return m;
}

// ------------------------------------------------------------------------- validation --
namespace {

struct NamedField {
    const double* value;
    std::size_t count;
    const char* not_finite;
};

Status checkFinite(const NamedField* fields, std::size_t n) noexcept {
    for (std::size_t f = 0U; f < n; ++f) {
        for (std::size_t i = 0U; i < fields[f].count; ++i) {
            if (!math::isFinite(fields[f].value[i])) {
                return Status(StatusCode::kInvalidArgument, fields[f].not_finite);
            }
        }
    }
    return Status::ok();
}

// The four outer corners of the image (pixel edges, not centres).
void imageCorners(const CameraModel& m, Vec2 (&corners)[4]) noexcept {
    const double right = static_cast<double>(m.width_px) - 0.5;
    const double bottom = static_cast<double>(m.height_px) - 0.5;
    corners[0] = Vec2(-0.5, -0.5);
    corners[1] = Vec2(right, -0.5);
    corners[2] = Vec2(-0.5, bottom);
    corners[3] = Vec2(right, bottom);
}

Status validatePinhole(const CameraModel& m) noexcept {
    const NamedField fields[] = {
        {&m.fx_px, 1U, "camera model: fx_px is not finite"}, {&m.fy_px, 1U, "camera model: fy_px is not finite"},
        {&m.cx_px, 1U, "camera model: cx_px is not finite"}, {&m.cy_px, 1U, "camera model: cy_px is not finite"},
        {&m.k1, 1U, "camera model: k1 is not finite"},       {&m.k2, 1U, "camera model: k2 is not finite"},
        {&m.k3, 1U, "camera model: k3 is not finite"},       {&m.p1, 1U, "camera model: p1 is not finite"},
        {&m.p2, 1U, "camera model: p2 is not finite"},
    };
    VTM_RETURN_IF_ERROR(checkFinite(fields, sizeof fields / sizeof fields[0]));
    if (!(m.fx_px > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "camera model: fx_px must be positive");
    }
    if (!(m.fy_px > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "camera model: fy_px must be positive");
    }
    Vec2 corners[4];
    imageCorners(m, corners);
    double max_radius = 0.0;
    for (const Vec2& c : corners) {
        const Vec2 n((c.x() - m.cx_px) / m.fx_px, (c.y() - m.cy_px) / m.fy_px);
        max_radius = std::fmax(max_radius, math::sqrt(n.dot(n)));
    }
    if (!radialIsMonotonic(brownRadial(m), max_radius)) {
        return Status(StatusCode::kInvalidArgument,
                      "camera model: k1 k2 k3 fold the image over (radial distortion not invertible to the corners)");
    }
    return Status::ok();
}

Status validateCahvAxes(const CameraModel& m) noexcept {
    const Vec3 a = vec(m.a);
    const Vec3 h = vec(m.h);
    const Vec3 v = vec(m.v);
    if (!isUnit(a)) {
        return Status(StatusCode::kInvalidArgument, "camera model: A is not a unit vector");
    }
    if (!(h.cross(a).norm() > kParallelSine * h.norm())) {
        return Status(StatusCode::kInvalidArgument, "camera model: H is parallel to A");
    }
    if (!(v.cross(a).norm() > kParallelSine * v.norm())) {
        return Status(StatusCode::kInvalidArgument, "camera model: V is parallel to A");
    }
    if (!(std::fabs(h.cross(v).dot(a)) > kParallelSine * h.norm() * v.norm())) {
        return Status(StatusCode::kInvalidArgument, "camera model: H and V are coplanar with A");
    }
    return Status::ok();
}

Status validateCahvorDistortion(const CameraModel& m) noexcept {
    if (!isUnit(vec(m.o))) {
        return Status(StatusCode::kInvalidArgument, "camera model: O is not a unit vector");
    }
    const Vec3 o = normalised(vec(m.o));
    Vec2 corners[4];
    imageCorners(m, corners);
    double max_radius = 0.0;
    for (const Vec2& c : corners) {
        Vec3 w = Vec3::UnitZ();
        if (!cahvDirection(m, c, w).isOk() || !(w.dot(o) > 0.0)) {
            return Status(StatusCode::kInvalidArgument, "camera model: O is 90 degrees or more from a corner's ray");
        }
        const double zeta = w.dot(o);
        const Vec3 lambda = w - zeta * o;
        max_radius = std::fmax(max_radius, math::sqrt(lambda.dot(lambda)) / zeta);
    }
    if (!radialIsMonotonic(cahvorRadial(m), max_radius)) {
        return Status(StatusCode::kInvalidArgument,
                      "camera model: R folds the image over (radial distortion not invertible to the corners)");
    }
    return Status::ok();
}

Status validateCahv(const CameraModel& m) noexcept {
    const bool cahvor = m.kind == CameraModelKind::kCahvor;
    const NamedField fields[] = {
        {m.c, 3U, "camera model: C is not finite"}, {m.a, 3U, "camera model: A is not finite"},
        {m.h, 3U, "camera model: H is not finite"}, {m.v, 3U, "camera model: V is not finite"},
        {m.o, 3U, "camera model: O is not finite"}, {m.r, 3U, "camera model: R is not finite"},
    };
    VTM_RETURN_IF_ERROR(checkFinite(fields, cahvor ? 6U : 4U));
    VTM_RETURN_IF_ERROR(validateCahvAxes(m));
    return cahvor ? validateCahvorDistortion(m) : Status::ok();
}

}  // namespace

Status validateCameraModel(const CameraModel& model) noexcept {
    const bool known = model.kind == CameraModelKind::kPinholeBrown || model.kind == CameraModelKind::kCahv ||
                       model.kind == CameraModelKind::kCahvor;
    if (!known) {
        return Status(StatusCode::kInvalidArgument, "camera model: kind is not pinhole, cahv or cahvor",
                      static_cast<std::int64_t>(model.kind));
    }
    if (model.width_px == 0U) {
        return Status(StatusCode::kInvalidArgument, "camera model: width_px is zero");
    }
    if (model.height_px == 0U) {
        return Status(StatusCode::kInvalidArgument, "camera model: height_px is zero");
    }
    return (model.kind == CameraModelKind::kPinholeBrown) ? validatePinhole(model) : validateCahv(model);
}

}  // namespace vtm
