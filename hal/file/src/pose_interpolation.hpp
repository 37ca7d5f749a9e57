// Pose interpolation between two logged poses, deterministic on every target: only
// + - * / and std::sqrt (correctly rounded by IEEE 754), no transcendental function.
#pragma once

#include <cstdint>

#include "hal/odometry.hpp"

namespace vtm::hal::detail {

// The pose at time t with a.timestamp_ns < t < b.timestamp_ns:
//  - position and covariance: a + s (b - a), s = (t - ta) / (tb - ta); a convex
//    combination of two covariances stays symmetric and positive semi-definite;
//  - attitude: slerp, q = qa (qa* qb)^s along the shorter arc, with the power computed
//    from the binary digits of s by repeated quaternion square roots (slerpBinary).
[[nodiscard]] PoseEstimate interpolatePose(const PoseEstimate& a, const PoseEstimate& b, std::uint64_t t) noexcept;

// q0 (q0* q1)^(num/den), 0 <= num < den, shorter arc; unit quaternions (w, x, y, z).
void slerpBinary(const double q0[4], const double q1[4], std::uint64_t num, std::uint64_t den, double out[4]) noexcept;

}  // namespace vtm::hal::detail
