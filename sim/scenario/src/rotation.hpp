// Rotations from angles with vtm::math (same bits on every target; Eigen's AngleAxis
// would call the C library's sin/cos). Site and vehicle frames: z down, so a positive
// rotation about z turns north towards east (a right turn).
#pragma once

#include "vtm/core/eigen.hpp"
#include "vtm/core/math.hpp"

namespace vtm::sim::detail {

constexpr double kRadPerDeg = math::kPi / 180.0;

// Rotation by `angle_rad` about the x, y or z axis (right-handed).
[[nodiscard]] inline Mat3 rotationX(double angle_rad) noexcept {
    const double c = math::cos(angle_rad);
    const double s = math::sin(angle_rad);
    Mat3 r;
    r << 1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c;
    return r;
}
[[nodiscard]] inline Mat3 rotationY(double angle_rad) noexcept {
    const double c = math::cos(angle_rad);
    const double s = math::sin(angle_rad);
    Mat3 r;
    r << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
    return r;
}
[[nodiscard]] inline Mat3 rotationZ(double angle_rad) noexcept {
    const double c = math::cos(angle_rad);
    const double s = math::sin(angle_rad);
    Mat3 r;
    r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
    return r;
}

// Rotation by the rotation vector v (axis v / |v|, angle |v| radians), Rodrigues' formula.
[[nodiscard]] inline Mat3 rotationFromVector(const Vec3& v) noexcept {
    const double angle = math::sqrt(v.squaredNorm());
    if (angle == 0.0) {
        return Mat3::Identity();
    }
    const Vec3 k = v / angle;
    Mat3 kx;
    kx << 0.0, -k.z(), k.y(), k.z(), 0.0, -k.x(), -k.y(), k.x(), 0.0;
    return Mat3::Identity() + math::sin(angle) * kx + (1.0 - math::cos(angle)) * (kx * kx);
}

// Unit quaternion (w >= 0) of a rotation matrix; Eigen's conversion uses only sqrt and
// + - * /, so it is deterministic.
[[nodiscard]] inline Quat quaternionOf(const Mat3& r) noexcept {
    Quat q(r);
    q.normalize();
    if (q.w() < 0.0) {
        q.coeffs() = -q.coeffs();
    }
    return q;
}

}  // namespace vtm::sim::detail
