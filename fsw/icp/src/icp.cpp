// registerData(): the point-to-plane iterations, the checks and the published fit.
#include <algorithm>
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/core/rotation.hpp"
#include "vtm/icp/icp.hpp"
#include "vtm/icp/symmetric_eigen.hpp"

namespace vtm::icp {

// One linearisation of the fit at a pose: correspondences, robust scale and the weighted
// normal equations in the centroid parameters (w about centroid, translation of it).
struct PointToPlaneIcp::Linearisation {
    double gate_m = 0.0;
    std::int32_t correspondences = 0;
    std::int32_t inliers = 0;
    std::int32_t truncated = 0;
    double sigma_m = 0.0;
    double sum_w_r2 = 0.0;
    double sum_inlier_r2 = 0.0;
    double extent_m = 0.0;  // RMS distance of the matched points from their centroid
    Vec3 centroid_m = Vec3::Zero();  // model frame (absolute)
    Mat6 A = Mat6::Zero();
    Vec6 b = Vec6::Zero();
};

namespace {

Vec3 toVec(const TreePoint& p) noexcept {
    return Vec3(static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z));
}

Mat3 orthonormalised(const Mat3& r) noexcept {
    Quat q(r);
    q.normalize();
    return q.toRotationMatrix();
}

}  // namespace

std::size_t PointToPlaneIcp::dataIndex(std::size_t i) const noexcept {
    // Evenly spread over the input, integer arithmetic (dataUsed_ <= dataCount_).
    return dataUsed_ == dataCount_ ? i : (i * dataCount_) / dataUsed_;
}

void PointToPlaneIcp::linearise(Span<const Vec3> data_m, const RigidPose& pose, double gate_m,
                                Linearisation& lin) noexcept {
    lin = Linearisation{};
    lin.gate_m = gate_m;
    const double gate2 = gate_m * gate_m;
    Vec3 sum = Vec3::Zero();
    Neighbours nb;
    std::size_t matched = 0U;
    for (std::size_t i = 0; i < dataUsed_; ++i) {
        match_[i] = -1;
        const Vec3 p = pose.R * data_m[dataIndex(i)] + pose.t_m - origin_m_;
        tree_.nearest(p.x(), p.y(), p.z(), 1, gate2, nb);
        lin.truncated += nb.truncated ? 1 : 0;
        if (nb.count == 0) {
            continue;
        }
        const auto m = static_cast<std::size_t>(nb.index[0]);
        const Vec3 n = toVec(normals_[m]);
        if (n.squaredNorm() == 0.0) {
            continue;
        }
        match_[i] = nb.index[0];
        residual_[i] = n.dot(p - toVec(model_[m]));
        scratch_[matched++] = std::fabs(residual_[i]);
        sum += p;
    }
    lin.correspondences = static_cast<std::int32_t>(matched);
    if (matched == 0U) {
        return;
    }
    lin.centroid_m = sum / static_cast<double>(matched) + origin_m_;
    // Median of |r| by selection: its value is unique, whatever the algorithm's order.
    double* s = scratch_.data();
    std::nth_element(s, s + matched / 2, s + matched);
    lin.sigma_m = std::max(config_.min_sigma_m, 1.4826 * s[matched / 2]);
    accumulate(data_m, pose, lin);
}

void PointToPlaneIcp::accumulate(Span<const Vec3> data_m, const RigidPose& pose, Linearisation& lin) const noexcept {
    const double huber = config_.huber_k * lin.sigma_m;
    const double inlierLimit = 3.0 * lin.sigma_m;
    const Vec3 c = lin.centroid_m - origin_m_;
    double spread2 = 0.0;
    for (std::size_t i = 0; i < dataUsed_; ++i) {
        if (match_[i] < 0) {
            continue;
        }
        const Vec3 p = pose.R * data_m[dataIndex(i)] + pose.t_m - origin_m_ - c;
        const Vec3 n = toVec(normals_[static_cast<std::size_t>(match_[i])]);
        const double r = residual_[i];
        const double ar = std::fabs(r);
        const double w = ar <= huber ? 1.0 : huber / ar;
        Vec6 j;
        j.head<3>() = p.cross(n);
        j.tail<3>() = n;
        lin.A += (w * j) * j.transpose();
        lin.b -= (w * r) * j;
        lin.sum_w_r2 += w * r * r;
        spread2 += p.squaredNorm();
        if (ar <= inlierLimit) {
            ++lin.inliers;
            lin.sum_inlier_r2 += r * r;
        }
    }
    lin.extent_m = std::sqrt(spread2 / static_cast<double>(lin.correspondences));
}

Status PointToPlaneIcp::checkFit(const Linearisation& lin, IcpResult& result) const noexcept {
    result.correspondences = lin.correspondences;
    result.overlap = static_cast<double>(lin.correspondences) / static_cast<double>(dataUsed_);
    result.sigma_m = lin.sigma_m;
    result.centroid_m = lin.centroid_m;
    result.truncated_queries = lin.truncated;
    if (result.overlap < config_.min_overlap) {
        return Status(StatusCode::kDegenerate, "icp.registerData: overlap of data and model below min_overlap",
                      static_cast<std::int64_t>(result.overlap * 1000.0));
    }
    if (lin.correspondences < config_.min_correspondences) {
        return Status(StatusCode::kNoData, "icp.registerData: fewer correspondences than min_correspondences",
                      lin.correspondences);
    }
    // Rotations in metres of motion at the data's extent, so the six parameters compare.
    Vec6 scale;
    scale << 1.0 / lin.extent_m, 1.0 / lin.extent_m, 1.0 / lin.extent_m, 1.0, 1.0, 1.0;
    const Mat6 scaled = scale.asDiagonal() * lin.A * scale.asDiagonal();
    Vec6 values;
    Mat6 vectors;
    symmetricEigen<6>(scaled, values, vectors);
    result.eigen_ratio = values(5) > 0.0 ? std::max(0.0, values(0)) / values(5) : 0.0;
    result.weakest_direction = vectors.col(0);
    if (!(result.eigen_ratio >= config_.min_eigen_ratio)) {
        Eigen::Index dominant = 0;
        (void)result.weakest_direction.cwiseAbs().maxCoeff(&dominant);
        return Status(StatusCode::kDegenerate,
                      "icp.registerData: fit ambiguous, the surface leaves a direction unconstrained (detail: "
                      "0-2 rotation x-z, 3-5 translation x-z)",
                      static_cast<std::int64_t>(dominant));
    }
    return Status::ok();
}

void PointToPlaneIcp::publish(const Linearisation& lin, const RigidPose& pose, IcpResult& result) const noexcept {
    result.model_from_data = pose;
    result.inliers = lin.inliers;
    result.rms_residual_m = lin.inliers > 0 ? std::sqrt(lin.sum_inlier_r2 / static_cast<double>(lin.inliers)) : 0.0;
    const double s2 = lin.sum_w_r2 / static_cast<double>(lin.correspondences - 6);
    // A^-1 column by column: a vector right-hand side keeps Eigen on its fixed-size path
    // (a matrix one references the blocked triangular solver, which can allocate).
    const Eigen::LDLT<Mat6> ldlt(lin.A);
    Mat6 centroidCovariance;
    for (int i = 0; i < 6; ++i) {
        centroidCovariance.col(i) = s2 * ldlt.solve(Vec6::Unit(i));
    }
    // Centroid parameters (w, dc) to the pose's (w, dt_m): dt_m = dc - (t_m - c) x w.
    Mat6 g = Mat6::Identity();
    g.block<3, 3>(3, 0) = -skew(pose.t_m - lin.centroid_m);
    result.covariance = g * centroidCovariance * g.transpose();
}

Status PointToPlaneIcp::registerData(Span<const Vec3> data_m, const RigidPose& model_from_data_guess,
                                     IcpResult& result) noexcept {
    result = IcpResult{};
    result.model_from_data = model_from_data_guess;
    if (!hasModel_) {
        return Status(StatusCode::kNotInitialized, "icp.registerData: no model (init() and setModel() first)");
    }
    if (data_m.empty()) {
        return Status(StatusCode::kInvalidArgument, "icp.registerData: data cloud is empty");
    }
    VTM_RETURN_IF_ERROR(checkRigidPose(model_from_data_guess, 1e-6, "icp.registerData: model_from_data_guess"));
    for (std::size_t i = 0; i < data_m.size(); ++i) {
        const Vec3& p = data_m[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()) || p.cwiseAbs().maxCoeff() > 1e7) {
            return Status(StatusCode::kCorruptData, "icp.registerData: data point not finite (or beyond 1e7 m)",
                          static_cast<std::int64_t>(i));
        }
    }
    dataCount_ = data_m.size();
    dataUsed_ = std::min(dataCount_, static_cast<std::size_t>(config_.max_data_points));
    result.data_points_used = static_cast<std::int32_t>(dataUsed_);
    RigidPose pose = model_from_data_guess;
    Linearisation lin;
    double gate = config_.initial_gate_m;
    for (std::int32_t it = 0; it < config_.max_iterations; ++it) {
        linearise(data_m, pose, gate, lin);
        const Status fit = checkFit(lin, result);
        if (!fit.isOk()) {
            result.stop = StopReason::kRefused;
            return fit;
        }
        const Vec6 x = lin.A.ldlt().solve(lin.b);
        const Mat3 dR = rotationExp(x.head<3>());
        const Vec3 c = lin.centroid_m;
        pose.t_m = dR * (pose.t_m - c) + c + x.tail<3>();
        pose.R = orthonormalised(dR * pose.R);
        result.iterations = it + 1;
        const bool small = std::sqrt(x.head<3>().squaredNorm()) < config_.converge_rotation_rad &&
                           std::sqrt(x.tail<3>().squaredNorm()) < config_.converge_translation_m;
        if (small && gate == config_.min_gate_m) {
            result.stop = StopReason::kConverged;
            break;
        }
        gate = std::max(config_.min_gate_m, gate * config_.gate_shrink);
        result.stop = StopReason::kMaxIterations;
    }
    linearise(data_m, pose, config_.min_gate_m, lin);
    const Status fit = checkFit(lin, result);
    if (!fit.isOk()) {
        result.stop = StopReason::kRefused;
        return fit;
    }
    publish(lin, pose, result);
    return Status::ok();
}

}  // namespace vtm::icp
