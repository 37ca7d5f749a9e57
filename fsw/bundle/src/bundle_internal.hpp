// The bundle adjuster's working records and the small numerical pieces its files share
// (private to fsw/bundle).
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/bundle/bundle_adjuster.hpp"

namespace vtm::bundle {

using Mat26 = Eigen::Matrix<double, 2, 6>;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat63 = Eigen::Matrix<double, 6, 3>;

struct BundleAdjuster::StationWork {
    Mat3 R0 = Mat3::Identity();  // approximate left-eye pose
    Vec3 t0_m = Vec3::Zero();
    Vec6 x = Vec6::Zero();       // current correction (dtheta, dt)
    Vec6 x_trial = Vec6::Zero();
    Mat3 R = Mat3::Identity();   // pose at x (R = Exp(dtheta) R0, t = t0 + dt)
    Vec3 t_m = Vec3::Zero();
    Mat3 R_trial = Mat3::Identity();
    Vec3 t_trial_m = Vec3::Zero();
    Mat6 prior_info = Mat6::Zero();  // inverse of the free block of the prior covariance
    Mat6 U = Mat6::Zero();           // sum w Jc^T Jc of the current linearisation
    Vec6 g = Vec6::Zero();           // sum w Jc^T r
    std::uint8_t fixed[6] = {0U, 0U, 0U, 0U, 0U, 0U};
};

struct BundleAdjuster::PointWork {
    Vec3 X_m = Vec3::Zero();
    Vec3 X_trial_m = Vec3::Zero();
    Vec3 X_initial_m = Vec3::Zero();
    Mat3 V = Mat3::Zero();       // sum w Jp^T Jp
    Vec3 g = Vec3::Zero();       // sum w Jp^T r
    Mat3 V_inv = Mat3::Zero();   // inverse of the damped V of the last system built
    PointState state = PointState::kUnused;
};

struct BundleAdjuster::ObservationWork {
    Mat26 jc = Mat26::Zero();  // d predicted pixel / d station x (fixed columns zero)
    Mat23 jp = Mat23::Zero();  // d predicted pixel / d point
    Vec2 r = Vec2::Zero();     // predicted minus observed, px
    double w = 0.0;            // robust weight / sigma_px^2 (0: not used)
    std::uint32_t input = 0U;  // index in the caller's observations
    std::uint16_t station = 0U;
    Eye eye = Eye::kLeft;
    ObservationState state = ObservationState::kInlier;
};

// One station's part of one point's equations: W = sum w Jc^T Jp over its eyes.
struct BundleAdjuster::StationGroup {
    Mat63 W = Mat63::Zero();
    Mat63 Y = Mat63::Zero();  // W V*^-1
    std::size_t station = 0U;
};

// Left Jacobian of SO(3): Exp(theta + e) = Exp(J_l(theta) e) Exp(theta) to first order.
[[nodiscard]] Mat3 leftJacobian(const Vec3& theta) noexcept;

// rho(u) and the IRLS weight rho'(u) / (2 u) of the configured loss (u = |r| / sigma).
[[nodiscard]] double robustRho(const BundleConfig& c, double u) noexcept;
[[nodiscard]] double robustWeight(const BundleConfig& c, double u) noexcept;

// In-place Cholesky A = L L^T of a symmetric positive definite n x n row-major matrix (the
// lower triangle is read and replaced by L; the upper is left alone). Returns -1, or the
// first row whose pivot is not above `relative_floor` times its diagonal before.
[[nodiscard]] std::int64_t choleskyInPlace(double* a, std::size_t n, double relative_floor) noexcept;
// Solves L L^T x = b in place (b becomes x) with the factor choleskyInPlace left.
void choleskySolve(const double* l, std::size_t n, double* b) noexcept;

}  // namespace vtm::bundle
