// Point-to-plane ICP (Chen and Medioni 1992) between a terrain model (the map, or a first
// model) and a new cloud (the data), as a flight module (issue 25 item 2, docs/icp.md).
//
// Frames and the answer: the model's points are in its frame M (site frame of the map),
// the data's in D (the new model's site frame, with the navigation's drift). The answer is
// the RigidPose model_from_data (vtm/core/pose.hpp): X_M = R X_D + t_m. The caller gives
// the navigation's guess of it; the module refines it.
//
// Method (docs/icp.md):
//  setModel(): the model points (relative to their bounding-box centre, float) in a k-d tree
//    (kd_tree.hpp); a normal per point from a plane fit to its k nearest neighbours within
//    normal_radius_m (smallest eigenvector of the 3x3 scatter, Jacobi); points whose
//    neighbourhood is not planar keep no normal and take no part in fits.
//  registerData(): a deterministic subsample of the data (at most max_data_points); per
//    iteration every data point, moved by the current pose, is paired with its nearest model
//    point within the gate (which shrinks from initial_gate_m by gate_shrink per iteration
//    to min_gate_m); point-to-plane residual r = n . (R q + t - m); robust scale
//    sigma = max(min_sigma_m, 1.4826 MAD(r)); Huber weights (huber_k sigma); one 6-DOF
//    Gauss-Newton step about the correspondences' centroid (6x6 LDLT); stop when the step
//    is below converge_rotation_rad and converge_translation_m with the gate at its minimum,
//    or at max_iterations. A last linearisation at the final pose gives the RMS, the
//    overlap, the conditioning and the covariance.
//
// Covariance: 6x6 of the pose error, parameters (w_x, w_y, w_z [rad], t_x, t_y, t_z [m]) in
// the model frame: true pose = (Exp(w) R, t_m + dt). C = s^2 (sum w_i J_i J_i^T)^-1 mapped
// from the centroid parameters, s^2 = sum w_i r_i^2 / (n - 6).
//
// Memory: the model (points, normals), the tree and per-data-point scratch, from an Arena
// at init() (workspaceBytes(config)); setModel() and registerData() never allocate. Work is
// bounded by the configuration: queries open at most max_leaves leaves of leaf_size points.
// Deterministic: + - * / and sqrt, vtm::math sin/cos, fixed-size Eigen.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/icp/kd_tree.hpp"

namespace vtm::icp {

constexpr std::int32_t kMaxModelPointsLimit = 1 << 20;  // max_model_points, at most
constexpr std::int32_t kMaxDataPointsLimit = 1 << 18;   // max_data_points, at most

struct IcpConfig {
    // Static capacity: a larger model is refused; a larger data cloud is subsampled.
    std::int32_t max_model_points = 65536;  // 16..kMaxModelPointsLimit
    std::int32_t max_data_points = 16384;   // 16..kMaxDataPointsLimit
    // k-d tree: points per leaf (2..64) and leaves one query may open (1..4096).
    std::int32_t leaf_size = 8;
    std::int32_t max_leaves = 64;
    // Model normals: k nearest neighbours (6..kMaxNeighbours) within normal_radius_m (> 0);
    // the fit is planar when lambda_min / (sum of lambdas) <= max_surface_variation (0, 1/3]
    // and lambda_mid >= 4 lambda_min (otherwise the normal's direction is not defined).
    std::int32_t normal_neighbours = 12;
    double normal_radius_m = 0.75;
    double max_surface_variation = 0.05;
    // Correspondence gate on the 3-D distance to the nearest model point, metres:
    // initial_gate_m, times gate_shrink (0, 1] per iteration, never below min_gate_m.
    double initial_gate_m = 1.5;
    double min_gate_m = 0.4;
    double gate_shrink = 0.75;
    // Robust weights: Huber with threshold huber_k * sigma (> 0); sigma >= min_sigma_m (> 0).
    double huber_k = 1.345;
    double min_sigma_m = 0.001;
    // Iterations at most (1..200); convergence when the step is below both (> 0).
    std::int32_t max_iterations = 50;
    double converge_rotation_rad = 1e-5;
    double converge_translation_m = 1e-4;
    // Refusals: overlap (fraction of the data points used that have a correspondence
    // within min_gate_m at the final pose) below min_overlap (0, 1] -> kDegenerate;
    // fewer correspondences than min_correspondences (>= 12) -> kNoData; the normal matrix,
    // rotations scaled to metres at the data's extent, with lambda_min / lambda_max below
    // min_eigen_ratio (0, 1) -> kDegenerate (a direction the surface does not constrain).
    double min_overlap = 0.3;
    std::int32_t min_correspondences = 100;
    double min_eigen_ratio = 1e-3;

    // kOk, or kInvalidConfig naming the field ("icp.min_gate_m: ..."), value in detail.
    [[nodiscard]] Status validate() const noexcept;
};

enum class StopReason : std::uint8_t {
    kNone = 0,           // no fit (refused before iterating)
    kConverged = 1,      // step below the convergence thresholds with the gate at its minimum
    kMaxIterations = 2,  // max_iterations reached (the fit is still checked and published)
    kRefused = 3,        // a refusal ended the fit (Status says which)
};

struct IcpResult {
    RigidPose model_from_data{};  // refined; the initial guess when refused
    Mat6 covariance = Mat6::Zero();  // (w [rad], t_m [m]) in the model frame; zero when refused
    double rms_residual_m = 0.0;  // point-to-plane, over the inliers (|r| <= 3 sigma)
    double sigma_m = 0.0;         // robust scale of the residuals (1.4826 MAD)
    double overlap = 0.0;         // correspondences / data points used
    double eigen_ratio = 0.0;     // lambda_min / lambda_max of the scaled normal matrix
    Vec6 weakest_direction = Vec6::Zero();  // its eigenvector (rotations scaled to metres)
    Vec3 centroid_m = Vec3::Zero();         // of the matched data points, model frame
    std::int32_t data_points_used = 0;
    std::int32_t correspondences = 0;
    std::int32_t inliers = 0;
    std::int32_t iterations = 0;
    std::int32_t truncated_queries = 0;  // queries that reached max_leaves (last linearisation)
    StopReason stop = StopReason::kNone;
};

class PointToPlaneIcp {
public:
    // Bytes of arena for this configuration (every array and its padding), 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const IcpConfig& config) noexcept;

    // Validates the config and carves the workspace. kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const IcpConfig& config, Arena& arena) noexcept;

    // Takes a model (metres, its frame M; copied): builds the tree and the normals.
    // kNotInitialized; kInvalidArgument (more than max_model_points: the count in detail;
    // fewer than min_correspondences); kCorruptData (a non-finite point: its index);
    // kDegenerate (fewer planar normals than min_correspondences: their count).
    [[nodiscard]] Status setModel(Span<const Vec3> model_m) noexcept;

    // Registers data (metres, its frame D) to the model from the guess model_from_data.
    // kNotInitialized (no model); kInvalidArgument (empty data, a pose that is not a
    // rotation); kCorruptData (a non-finite point: its index); kNoData (too few
    // correspondences: their count); kDegenerate (overlap below min_overlap: per mille in
    // detail; ill-conditioned: the weakest direction's dominant parameter 0..5 in detail).
    // On a refusal `result` carries the diagnostics but model_from_data is the guess and the
    // covariance is zero. Never allocates.
    [[nodiscard]] Status registerData(Span<const Vec3> data_m, const RigidPose& model_from_data_guess,
                                      IcpResult& result) noexcept;

    // Model points with a planar normal (after setModel()).
    [[nodiscard]] std::int32_t modelNormalCount() const noexcept { return normalCount_; }
    [[nodiscard]] const IcpConfig& config() const noexcept { return config_; }

private:
    struct Linearisation;

    [[nodiscard]] std::size_t dataIndex(std::size_t i) const noexcept;
    void computeNormals() noexcept;
    void linearise(Span<const Vec3> data_m, const RigidPose& pose, double gate_m, Linearisation& lin) noexcept;
    void accumulate(Span<const Vec3> data_m, const RigidPose& pose, Linearisation& lin) const noexcept;
    [[nodiscard]] Status checkFit(const Linearisation& lin, IcpResult& result) const noexcept;
    void publish(const Linearisation& lin, const RigidPose& pose, IcpResult& result) const noexcept;

    IcpConfig config_{};
    bool initialized_ = false;
    bool hasModel_ = false;
    Vec3 origin_m_ = Vec3::Zero();   // model points are stored relative to it
    Span<TreePoint> model_{};        // model points relative to origin_m_
    Span<TreePoint> normals_{};      // unit normals; (0, 0, 0) where not planar
    KdTree tree_{};
    Span<std::int32_t> match_{};     // per data point used: model index or -1
    Span<double> residual_{};        // per data point used: point-to-plane residual, m
    Span<double> scratch_{};         // |r| for the median
    std::size_t dataCount_ = 0U;     // data points of the registration in progress
    std::size_t dataUsed_ = 0U;
    std::int32_t normalCount_ = 0;
};

}  // namespace vtm::icp
