// interpolatePose (hal/odometry.hpp): shared by every odometry driver (file, sim, link).
#include <cmath>
#include <cstdint>

#include "hal/odometry.hpp"

namespace vtm::hal {
namespace {

// s is resolved to 2^-52, the spacing of doubles just below 1: finer steps would not
// change the result.
constexpr int kFractionBits = 52;

// Hamilton product a b of quaternions (w, x, y, z).
void multiply(const double a[4], const double b[4], double out[4]) noexcept {
    const double w = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    const double x = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    const double y = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    const double z = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
    out[0] = w;
    out[1] = x;
    out[2] = y;
    out[3] = z;
}

// Callers pass quaternions of norm near 1 (or, in halveAngle, at least 1): no division by 0.
void normalize(double q[4]) noexcept {
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; ++i) {
        q[i] /= norm;
    }
}

// Principal square root of a unit quaternion with w >= 0 (rotation angle <= pi):
// 1 + (cos a, sin a n) = 2 cos(a/2) (cos(a/2), sin(a/2) n), so (1 + q) / |1 + q| is the
// rotation by half the angle about the same axis. |1 + q| >= 1 because w >= 0.
void halveAngle(double q[4]) noexcept {
    q[0] += 1.0;
    normalize(q);
}


void slerpBinary(const double q0[4], const double q1[4], std::uint64_t num, std::uint64_t den,
                 double out[4]) noexcept {
    // r = q0* q1, the rotation from q0 to q1; -r is the same rotation, and w >= 0 picks
    // the shorter arc.
    const double q0_conj[4] = {q0[0], -q0[1], -q0[2], -q0[3]};
    double r[4];
    multiply(q0_conj, q1, r);
    if (r[0] < 0.0) {
        for (double& c : r) {
            c = -c;
        }
    }
    // r^s = product over the binary digits b_k of s = num / den of r^(b_k 2^-k). Powers of
    // one rotation share its axis and commute, so the order of the product is free.
    double power[4] = {1.0, 0.0, 0.0, 0.0};
    std::uint64_t rem = num;
    for (int k = 1; k <= kFractionBits && rem != 0U; ++k) {
        halveAngle(r);  // r = (q0* q1)^(2^-k)
        // Next digit of num / den by long division: is 2 rem >= den? (no overflow form)
        if (rem >= den - rem) {
            double next[4];
            multiply(power, r, next);
            for (int i = 0; i < 4; ++i) {
                power[i] = next[i];
            }
            rem -= den - rem;
        } else {
            rem += rem;
        }
    }
    multiply(q0, power, out);
    normalize(out);
}

}  // namespace

PoseEstimate interpolatePose(const PoseEstimate& a, const PoseEstimate& b, std::uint64_t t) noexcept {
    const std::uint64_t num = t - a.timestamp_ns;
    const std::uint64_t den = b.timestamp_ns - a.timestamp_ns;
    const double s = static_cast<double>(num) / static_cast<double>(den);
    PoseEstimate p;
    p.timestamp_ns = t;
    for (int i = 0; i < 3; ++i) {
        p.position_m[i] = a.position_m[i] + s * (b.position_m[i] - a.position_m[i]);
    }
    for (int i = 0; i < 36; ++i) {
        p.covariance[i] = a.covariance[i] + s * (b.covariance[i] - a.covariance[i]);
    }
    slerpBinary(a.attitude_wxyz, b.attitude_wxyz, num, den, p.attitude_wxyz);
    return p;
}

}  // namespace vtm::hal
