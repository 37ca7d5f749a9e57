// Relative-motion refinement (issue 5 item 3, docs/motion.md): the rotation and the
// translation direction between two views of one camera, refined by Levenberg-Marquardt
// from matched pixels, with one inverse range per match (Olson et al., ALGORITHMS.md
// "Motion refinement").
//
// Geometry (shared with fsw/features and fsw/rectify):
//  - A vtm::CameraPair (vtm/core/pose.hpp): cameras A and B, each a vtm::CameraModel in
//    its own camera reference frame, and b_from_a: X_b = R * X_a + t_m (metres).
//  - Match i: pixels_a[i] in A and pixels_b[i] in B. Its point lies on A's ray through
//    pixels_a[i]: X_a = origin + direction / rho_i, rho_i = 1 / range_i (1/m), range
//    measured along the unit ray from A's projection centre.
//  - Residual of match i: pixels_b[i] - project_B(R X_a(rho_i) + t) (2 values, pixels).
//  - The baseline length |t| is not observable from pixels: it stays at the input
//    (odometry) value. 5 motion parameters are refined: the rotation, updated on the
//    manifold as R <- Exp(omega) * R (omega a rotation vector in B's frame, "left
//    perturbation"), and the translation direction u = t / |t|, updated as
//    u <- normalise(u + beta_1 b1(u) + beta_2 b2(u)) with the tangent basis of
//    directionTangentBasis() below.
//
// Memory: a MotionRefiner holds fixed arrays for kMaxMotionMatches matches (about
// 200 KiB); declare instances static (never on a task stack). No Arena, no heap.
// Determinism: only + - * /, std::sqrt and vtm::math (sin, cos, atan2, log): the same
// bits on every target.
#pragma once

#include <cstdint>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/rotation.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::motion {

constexpr std::int32_t kMaxMotionMatches = 1024;
// Upper bounds on the configuration's loop counts (validate() enforces them).
constexpr std::int32_t kMaxMotionIterations = 200;
constexpr std::int32_t kMaxMotionPasses = 10;

// Robust kernel on the per-match residual norm e = |r_i| (pixels), scale c:
//   kNone    cost e^2/2,                             weight 1
//   kHuber   cost e^2/2 (e <= c), c (e - c/2) beyond, weight min(1, c/e)
//   kCauchy  cost c^2/2 ln(1 + e^2/c^2),              weight 1 / (1 + e^2/c^2)
enum class RobustKernel : std::uint8_t { kNone = 0, kHuber = 1, kCauchy = 2 };

struct Config {
    std::int32_t max_iterations = 30;     // LM trial steps per pass, 1..kMaxMotionIterations
    RobustKernel kernel = RobustKernel::kHuber;
    double robust_scale_px = 1.0;         // kernel scale c, (0, 1000] px
    double outlier_threshold_px = 2.0;    // after a pass, matches above this are dropped, (0, 1000] px
    std::int32_t max_passes = 3;          // solve / drop rounds, 1..kMaxMotionPasses
    std::int32_t min_inliers = 12;        // at least this many inliers, 6..kMaxMotionMatches
    // Prior on the rotation: the initial (odometry / IMU) rotation with this 1-sigma per
    // axis, radians; 0 = none. With it the solution is the MAP estimate: the images'
    // residuals (in units of robust_scale_px) plus |log(R R0^T)|^2 / sigma^2. Needed where
    // the images alone cannot tell rotation from translation direction (a narrow view of
    // near-planar ground along the optical axis: descent). [0, pi].
    double rotation_prior_sigma_rad = 0.0;
    double range_min_m = 0.3;             // plausible ranges along A's rays: depths are
    double range_max_m = 1000.0;          // initialised and clamped within [min, max]
    // kInvalidConfig naming the field ("max_iterations: must be 1..200").
    [[nodiscard]] Status validate() const noexcept;
};

struct MotionInput {
    // Models and the initial (odometry) b_from_a: R a rotation within 1e-6, t_m's norm is kept.
    CameraPair pair{};
    Span<const Vec2> pixels_a;            // match i: pixels_a[i] <-> pixels_b[i]
    Span<const Vec2> pixels_b;
};

struct MotionResult {
    Mat3 R_b_from_a = Mat3::Identity();
    Vec3 t_b_from_a_m = Vec3::Zero();     // refined direction times the input's |t|
    // 5x5 covariance, row-major, of (omega_x, omega_y, omega_z [rad], left perturbation
    // in B's frame: R_true = Exp(omega) R; beta_1, beta_2 [rad], translation direction
    // tangent in the basis directionTangentBasis(t_b_from_a_m / |t|) of the RESULT).
    // It is the inverse of the Schur-reduced (unweighted) normal matrix over the final
    // inliers, times sigma^2 = sum |r_i|^2 / (2n - n - 5) (n inliers).
    double covariance[25] = {};
    // sqrt of the trace of the rotation block (the RMS length of the rotation error
    // vector: the expected rotation angle error), and of the direction block (the
    // expected angle between the refined and the true direction), radians.
    double rotation_sigma_rad = 0.0;
    double direction_sigma_rad = 0.0;
    // The covariance seen in B's image: the RMS over the final inliers of the 1-sigma
    // distance by which the motion's uncertainty moves each inlier across its epipolar
    // line (the direction its range cannot absorb), pixels. Rectification turns that
    // distance into vertical disparity, so it predicts the RMS vertical disparity of the
    // rectified pair from the refiner's own statistics (docs/motion.md).
    double epipolar_sigma_px = 0.0;
    std::int32_t matches = 0;             // input matches
    std::int32_t inliers = 0;             // final inliers (see refine())
    std::int32_t iterations = 0;          // LM trial steps, all passes
    std::int32_t passes = 0;              // solve / drop rounds done
    double initial_rms_px = 0.0;          // usable matches, initial motion, best depths
    double rms_px = 0.0;                  // final inliers, final motion and depths
};

class MotionRefiner {
public:
    // Refines input's motion from its matches.
    //  1. Every match is triangulated with the initial motion (midpoint of the two rays),
    //     its range clamped to [range_min_m, range_max_m]. A match whose pixel does not
    //     back-project, or whose point does not project into B, is unusable (outlier).
    //  2. Pass: LM (at most max_iterations trial steps) on the current inliers with the
    //     robust kernel (IRLS weights recomputed every step; a step is kept only if the
    //     robust cost falls). Then every usable match gets its best range under the new
    //     motion (1-D Gauss-Newton) and is an inlier iff its residual norm is
    //     <= outlier_threshold_px (outliers may come back). Passes stop when the inlier
    //     set no longer changes or after max_passes.
    //  3. The result (covariance, rms_px, inlier_flags, ranges_m) describes the final
    //     motion and the inliers classified at it.
    // Errors:
    //  kInvalidArgument: a pair model failing validateCameraModel (its reason),
    //    pixels_a / pixels_b of different sizes, more than kMaxMotionMatches, a
    //    non-finite or non-rotation pair.b_from_a.R, a non-finite or zero pair.b_from_a.t_m, a non-finite pixel (detail = match index),
    //    inlier_flags / ranges_m not empty and not of the matches' size.
    //  kInvalidConfig: config.validate().
    //  kDegenerate: fewer than min_inliers usable matches or inliers after a pass
    //    (detail = the count), or normal equations that do not determine the motion.
    // Reaching max_iterations is not an error (result.iterations tells).
    // inlier_flags (optional, size == matches): 1 inlier, 0 outlier.
    // ranges_m (optional, size == matches): refined range of each match along A's ray,
    // metres (NaN if outlier).
    // On an error, result, inlier_flags and ranges_m are left unspecified.
    [[nodiscard]] Status refine(const MotionInput& input, const Config& config, MotionResult& result,
                                Span<std::uint8_t> inlier_flags = {}, Span<double> ranges_m = {}) noexcept;

private:
    struct Motion {
        Mat3 R = Mat3::Identity();
        Vec3 u = Vec3::UnitZ();   // unit translation direction
        double baseline_m = 0.0;
    };
    struct Normal;  // normal equations (defined in the .cpp)

    [[nodiscard]] std::int32_t prepare(const MotionInput& input, const Config& config, const Motion& m) noexcept;
    [[nodiscard]] bool residual(const Motion& m, std::int32_t i, double rho, Vec2& r) const noexcept;
    [[nodiscard]] bool residualAndJacobian(const Motion& m, std::int32_t i, double rho, Vec2& r,
                                           Eigen::Matrix<double, 2, 5>& j_motion, Vec2& j_rho) const noexcept;
    [[nodiscard]] double robustCost(const Motion& m, const double* rho) const noexcept;
    [[nodiscard]] bool buildNormal(const Motion& m, bool robust, Normal& n) noexcept;
    [[nodiscard]] bool solveStep(const Normal& n, double lambda, Eigen::Matrix<double, 5, 1>& dx) noexcept;
    [[nodiscard]] std::int32_t runPass(Motion& m) noexcept;
    [[nodiscard]] double triangulate(const Motion& m, std::int32_t i) const noexcept;
    [[nodiscard]] double bestInverseRange(const Motion& m, std::int32_t i, double rho) const noexcept;
    [[nodiscard]] std::int32_t classify(const Motion& m, bool& changed) noexcept;
    [[nodiscard]] Status finish(const Motion& m, MotionResult& result) noexcept;
    [[nodiscard]] double inlierRms(const Motion& m) const noexcept;
    [[nodiscard]] double epipolarSigma(const Motion& m, const Eigen::Matrix<double, 5, 5>& cov) const noexcept;

    [[nodiscard]] double priorWeight() const noexcept;
    const CameraModel* model_b_ = nullptr;
    Config config_{};
    Mat3 R_prior_ = Mat3::Identity();  // the input rotation (rotation_prior_sigma_rad > 0)
    std::int32_t count_ = 0;
    double rho_min_ = 0.0;   // 1 / range_max_m
    double rho_max_ = 0.0;   // 1 / range_min_m
    // Per match: A's ray, B's pixel, inverse range, usable/inlier flags, and the
    // Schur terms of the current normal equations (W_i: 5, V_i, g_i).
    Vec3 origin_a_[kMaxMotionMatches];
    Vec3 direction_a_[kMaxMotionMatches];
    Vec2 pixel_b_[kMaxMotionMatches];
    Vec3 origin_b_[kMaxMotionMatches];      // B's ray through pixel_b_, in B's frame
    Vec3 direction_b_[kMaxMotionMatches];
    double rho_[kMaxMotionMatches] = {};
    double rho_trial_[kMaxMotionMatches] = {};
    std::uint8_t usable_[kMaxMotionMatches] = {};
    std::uint8_t inlier_[kMaxMotionMatches] = {};
    Eigen::Matrix<double, 5, 1> w_[kMaxMotionMatches];
    double v_[kMaxMotionMatches] = {};
    double g_rho_[kMaxMotionMatches] = {};
};

// Tangent basis of the unit sphere at unit vector u, used for the translation-direction
// parameters: k = index of the smallest |u_k| (first on ties), b1 = unit(e_k x u),
// b2 = u x b1. (b1, b2, u) is right-handed and orthonormal.
void directionTangentBasis(const Vec3& u, Vec3& b1, Vec3& b2) noexcept;

// The rotation helpers live in vtm/core/rotation.hpp; named here for existing callers.
using ::vtm::rotationAngleRad;
using ::vtm::rotationExp;
using ::vtm::rotationLog;

// Angle between two translation directions, radians in [0, pi]: atan2(|a x b|, a.b).
// NaN if either vector is zero or not finite.
[[nodiscard]] double directionAngleRad(const Vec3& a, const Vec3& b) noexcept;

}  // namespace vtm::motion
