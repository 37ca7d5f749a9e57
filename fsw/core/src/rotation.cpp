#include "vtm/core/rotation.hpp"

#include "vtm/core/math.hpp"

namespace vtm {

Mat3 skew(const Vec3& w) noexcept {
    Mat3 k;
    k << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
    return k;
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

double rotationAngleRad(const Mat3& a, const Mat3& b) noexcept {
    const Mat3 m = a.transpose() * b;
    const Vec3 axis(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
    const double s = 0.5 * math::sqrt(axis.dot(axis));
    const double c = 0.5 * (m.trace() - 1.0);
    return math::atan2(s, c);
}

}  // namespace vtm
