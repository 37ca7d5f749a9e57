// Small rotation / direction helpers of the motion refinement: the tangent basis of the
// translation direction, the rotation exponential, and the angle metrics used by the
// evaluation. Only + - * / and vtm::math: the same bits on every target.
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/motion/motion_refiner.hpp"

namespace vtm::motion {
namespace {

Mat3 skew(const Vec3& w) noexcept {
    Mat3 k;
    k << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
    return k;
}

bool finite3(const Vec3& v) noexcept {
    return math::isFinite(v.x()) && math::isFinite(v.y()) && math::isFinite(v.z());
}

}  // namespace

void directionTangentBasis(const Vec3& u, Vec3& b1, Vec3& b2) noexcept {
    // The axis least aligned with u gives the best-conditioned cross product.
    int k = 0;
    if (std::fabs(u.y()) < std::fabs(u.x())) {
        k = 1;
    }
    if (std::fabs(u.z()) < std::fabs(u[k])) {
        k = 2;
    }
    const Vec3 e = Vec3::Unit(k);
    const Vec3 c = e.cross(u);
    b1 = c / math::sqrt(c.dot(c));
    b2 = u.cross(b1);
}

Mat3 rotationExp(const Vec3& omega_rad) noexcept {
    const double theta2 = omega_rad.dot(omega_rad);
    const Mat3 k = skew(omega_rad);
    if (theta2 < 1e-16) {
        // Series to second order: the remainder is below 1e-24, far below rounding.
        return Mat3::Identity() + k + 0.5 * (k * k);
    }
    const double theta = math::sqrt(theta2);
    const double a = math::sin(theta) / theta;
    const double b = (1.0 - math::cos(theta)) / theta2;
    return Mat3::Identity() + a * k + b * (k * k);
}

double rotationAngleRad(const Mat3& a, const Mat3& b) noexcept {
    const Mat3 m = a.transpose() * b;
    const Vec3 axis(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
    const double s = 0.5 * math::sqrt(axis.dot(axis));
    const double c = 0.5 * (m.trace() - 1.0);
    return math::atan2(s, c);
}

Vec3 rotationLog(const Mat3& r) noexcept {
    const Vec3 axis(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));  // 2 sin(theta) n
    const double s = 0.5 * math::sqrt(axis.dot(axis));
    const double c = 0.5 * (r.trace() - 1.0);
    const double theta = math::atan2(s, c);
    if (s < 1e-12) {
        return 0.5 * axis;  // theta ~ sin(theta): the small-angle limit
    }
    return (0.5 * theta / s) * axis;
}

double directionAngleRad(const Vec3& a, const Vec3& b) noexcept {
    if (!finite3(a) || !finite3(b) || a.dot(a) == 0.0 || b.dot(b) == 0.0) {
        return math::kNaN;
    }
    const Vec3 c = a.cross(b);
    return math::atan2(math::sqrt(c.dot(c)), a.dot(b));
}

}  // namespace vtm::motion
