// Synthetic terrain clouds for the ICP tests: rolling hills plus rocks as a height field
// z(x, y) (site frame, z down, metres) from vtm::math sin/cos and integer hashing, sampled
// on a jittered grid, with Gaussian noise from vtm::Random, and moved into a data frame by
// a known rigid motion. Same bits on every target.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "vtm/core/math.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/random.hpp"

namespace vtm::icp::test {

struct Patch {
    double x0_m, x1_m, y0_m, y1_m;
};

inline std::uint64_t sceneHash(std::uint64_t v) {
    v += 0x9E3779B97F4A7C15ULL;
    v = (v ^ (v >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    v = (v ^ (v >> 27U)) * 0x94D049BB133111EBULL;
    return v ^ (v >> 31U);
}

// Rolling hills (wavelengths 5-20 m, up to ~1 m) and 60 rocks (radius 0.2-0.7 m) over
// x, y in [-30, 30] m. flat = true: the plane z = 0.
inline double terrainZ(double x, double y, bool flat = false) {
    if (flat) {
        return 0.0;
    }
    double z = -(0.8 * math::sin(0.31 * x + 0.5) * math::cos(0.23 * y - 0.3) +
                 0.35 * math::sin(0.67 * x + 0.52 * y + 1.0) + 0.12 * math::cos(1.3 * x - 0.9 * y));
    for (std::uint64_t k = 0; k < 60U; ++k) {
        const std::uint64_t h = sceneHash(k + 1000U);
        const double cx = -30.0 + static_cast<double>(h % 6000U) * 0.01;
        const double cy = -30.0 + static_cast<double>((h >> 16U) % 6000U) * 0.01;
        const double r = 0.2 + static_cast<double>((h >> 32U) % 50U) * 0.01;
        const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        if (d2 < r * r) {
            z -= 0.7 * std::sqrt(r * r - d2);
        }
    }
    return z;
}

// Points of `patch` on a grid of `spacing_m` jittered by up to 0.4 spacing, each with noise
// of `noise_m` (1 sigma, per axis), expressed in the data frame: X_data = R^T (X_site - t)
// for model_from_data = (R, t) (so the model is the site frame itself with the identity).
inline std::vector<Vec3> sampleCloud(const Patch& patch, double spacing_m, std::uint64_t seed, double noise_m,
                                     const RigidPose& model_from_data, bool flat = false) {
    std::vector<Vec3> out;
    Random rng(seed);
    const auto nx = static_cast<std::int32_t>((patch.x1_m - patch.x0_m) / spacing_m);
    const auto ny = static_cast<std::int32_t>((patch.y1_m - patch.y0_m) / spacing_m);
    for (std::int32_t j = 0; j < ny; ++j) {
        for (std::int32_t i = 0; i < nx; ++i) {
            const double jx = (rng.uniform01() - 0.5) * 0.8 * spacing_m;
            const double jy = (rng.uniform01() - 0.5) * 0.8 * spacing_m;
            const double x = patch.x0_m + (i + 0.5) * spacing_m + jx;
            const double y = patch.y0_m + (j + 0.5) * spacing_m + jy;
            const double nx0 = rng.normal(0.0, noise_m);
            const double ny0 = rng.normal(0.0, noise_m);
            const double nz0 = rng.normal(0.0, noise_m);
            const Vec3 site(x + nx0, y + ny0, terrainZ(x, y, flat) + nz0);
            out.push_back(model_from_data.R.transpose() * (site - model_from_data.t_m));
        }
    }
    return out;
}

// Rotation about the three site axes (degrees, applied x, then y, then z) and a translation.
inline RigidPose motion(double rx_deg, double ry_deg, double rz_deg, const Vec3& t_m) {
    const double k = 3.14159265358979323846 / 180.0;
    RigidPose p;
    p.R = (Eigen::AngleAxisd(rz_deg * k, Vec3::UnitZ()) * Eigen::AngleAxisd(ry_deg * k, Vec3::UnitY()) *
           Eigen::AngleAxisd(rx_deg * k, Vec3::UnitX()))
              .toRotationMatrix();
    p.t_m = t_m;
    return p;
}

// Angle of R_a R_b^T, degrees.
inline double rotationErrorDeg(const Mat3& a, const Mat3& b) {
    const Mat3 d = a * b.transpose();
    const Vec3 v(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
    return std::atan2(0.5 * v.norm(), 0.5 * (d.trace() - 1.0)) * 180.0 / 3.14159265358979323846;
}

// Small-angle vector w with R_est = Exp(w) R_true (the covariance's rotation parameters).
inline Vec3 rotationErrorVector(const Mat3& est, const Mat3& truth) {
    const Mat3 d = est * truth.transpose();
    return 0.5 * Vec3(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
}

}  // namespace vtm::icp::test
