// Rotations as every module parameterises them (docs/core.md "Rotations"): the skew
// matrix, the exponential of a rotation vector and its inverse, and the angle between two
// rotations. Only + - * / and vtm::math: the same bits on every target.
#pragma once

#include "vtm/core/eigen.hpp"

namespace vtm {

// [w]x: skew(w) * v = w x v.
[[nodiscard]] Mat3 skew(const Vec3& w) noexcept;

// Exp of a rotation vector (axis times angle, radians) by Rodrigues' formula with
// vtm::math::sin/cos; the second-order series below 1e-8 rad.
[[nodiscard]] Mat3 rotationExp(const Vec3& omega_rad) noexcept;

// Rotation vector of a rotation: the inverse of rotationExp for angles below pi.
[[nodiscard]] Vec3 rotationLog(const Mat3& r) noexcept;

// Angle of the rotation a^T b (the rotation taking a to b), radians in [0, pi], by atan2
// of its sine and cosine parts (accurate at small angles).
[[nodiscard]] double rotationAngleRad(const Mat3& a, const Mat3& b) noexcept;

}  // namespace vtm
