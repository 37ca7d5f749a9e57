// adjust()'s results: covariances from the reduced system's inverse at the solution, the
// residuals, the image RMS before and after, the counts.
#include <cmath>

#include "bundle_internal.hpp"
#include "vtm/core/math.hpp"

namespace vtm::bundle {
namespace {

Mat6 block6(const double* a, std::size_t n, std::size_t row, std::size_t col) noexcept {
    Mat6 m;
    for (std::size_t i = 0; i < 36U; ++i) {
        m(static_cast<Eigen::Index>(i / 6U), static_cast<Eigen::Index>(i % 6U)) = a[(6U * row + i / 6U) * n + 6U * col + i % 6U];
    }
    return m;
}

}  // namespace

// Per-axis RMS (px) over the final inliers: at the approximate stations with the initial
// triangulation (initial), or at the solution.
double BundleAdjuster::imageRms(bool initial) const noexcept {
    double sum = 0.0;
    std::size_t n = 0U;
    for (std::size_t k = 0; k < observations_.size(); ++k) {
        const ObservationWork& w = obsWork_[k];
        if (w.state != ObservationState::kInlier) {
            continue;
        }
        const StationWork& sw = stationWork_[w.station];
        const PointWork& pw = pointWork_[observations_[w.input].point];
        const NetworkStation& st = input_[w.station];
        const RigidPose pose = initial ? RigidPose{sw.R0, sw.t0_m} : RigidPose{sw.R, sw.t_m};
        Vec3 xc = pose.R.transpose() * ((initial ? pw.X_initial_m : pw.X_m) - pose.t_m);
        if (w.eye == Eye::kRight) {
            xc = st.rig.b_from_a.R * xc + st.rig.b_from_a.t_m;
        }
        Vec2 predicted;
        if (projectPoint(modelOfEye(st, w.eye), xc, predicted).isOk()) {
            sum += (predicted - observations_[w.input].pixel_px).squaredNorm();
            ++n;
        }
    }
    return n > 0U ? math::sqrt(sum / static_cast<double>(2U * n)) : 0.0;
}

void BundleAdjuster::publishResiduals(BundleResult& result) noexcept {
    for (std::size_t k = 0; k < observations_.size(); ++k) {
        const ObservationWork& w = obsWork_[k];
        ObservationResidual& out = obsOut_[w.input];
        out = ObservationResidual{};
        out.state = w.state;
        const PointState ps = pointWork_[observations_[w.input].point].state;
        Vec2 predicted;
        if ((ps == PointState::kAdjusted || ps == PointState::kTooFewInliers) && projectObservation(k, false, predicted, nullptr)) {
            out.residual_px = observations_[w.input].pixel_px - predicted;
            const double u = math::sqrt(out.residual_px.squaredNorm()) / config_.sigma_px;
            out.weight = w.state == ObservationState::kInlier ? robustWeight(config_, u) : 0.0;
        }
        result.inliers += w.state == ObservationState::kInlier ? 1 : 0;
        result.outliers += w.state == ObservationState::kOutlier ? 1 : 0;
    }
}

// Z = S^-1 column by column from the factor in reduced_; columns of fixed parameters zero.
void BundleAdjuster::invertReducedSystem() noexcept {
    const std::size_t n = dim_;
    for (std::size_t c = 0; c < n; ++c) {
        for (std::size_t i = 0; i < n; ++i) {
            step_[i] = i == c ? 1.0 : 0.0;
        }
        choleskySolve(reduced_.data(), n, step_.data());
        const bool fixedColumn = stationWork_[c / 6U].fixed[c % 6U] != 0U;
        for (std::size_t i = 0; i < n; ++i) {
            inverse_[i * n + c] = fixedColumn ? 0.0 : step_[i];
        }
    }
}

// Adjusted poses and covariances; the prior's share of the weighted SSR and redundancy.
void BundleAdjuster::publishStations(double& weighted, std::int64_t& redundancy) noexcept {
    for (std::size_t s = 0; s < stationCount_; ++s) {
        const StationWork& sw = stationWork_[s];
        StationSolution& out = stationOut_[s];
        out.site_from_a = RigidPose{sw.R, sw.t_m};
        out.correction = sw.x;
        Mat6 g = Mat6::Identity();  // covariance of x -> of the perturbation about the adjusted pose
        g.topLeftCorner<3, 3>() = leftJacobian(sw.x.head<3>());
        out.covariance = g * block6(inverse_.data(), dim_, s, s) * g.transpose();
        weighted += sw.x.dot(sw.prior_info * sw.x);
        for (int k = 0; k < 6; ++k) {
            const bool prior = config_.use_pointing_prior && sw.fixed[k] == 0U;
            redundancy += (prior ? 1 : 0) - (sw.fixed[k] == 0U ? 1 : 0);
        }
    }
}

// Positions, covariances (V^-1 + V^-1 W^T Z W V^-1) and inlier counts; the images' share of
// the weighted SSR and redundancy.
void BundleAdjuster::publishPoints(BundleResult& result, double& weighted, std::int64_t& redundancy) noexcept {
    for (std::size_t p = 0; p < pointCount_; ++p) {
        const PointWork& pw = pointWork_[p];
        PointSolution& out = pointOut_[p];
        out = PointSolution{};
        out.state = pw.state;
        out.position_m = pw.state == PointState::kAdjusted ? pw.X_m : pw.X_initial_m;
        if (pw.state != PointState::kAdjusted) {
            continue;
        }
        const std::size_t groups = stationGroups(p);
        Mat3 m = Mat3::Zero();
        for (std::size_t a = 0; a < groups; ++a) {
            for (std::size_t b = 0; b < groups; ++b) {
                m += groups_[a].W.transpose() * block6(inverse_.data(), dim_, groups_[a].station, groups_[b].station) * groups_[b].W;
            }
        }
        out.covariance = pw.V_inv + pw.V_inv * m * pw.V_inv;
        for (std::size_t k = pointFirst_[p]; k < pointFirst_[p + 1U]; ++k) {
            const ObservationWork& w = obsWork_[k];
            if (w.state == ObservationState::kInlier) {
                ++out.sightings;
                weighted += w.w * w.r.squaredNorm();
                redundancy += 2;
            }
        }
        redundancy -= 3;
        ++result.points_adjusted;
    }
}

Status BundleAdjuster::publish(BundleResult& result) noexcept {
    // The last linearisation, undamped: its reduced system's inverse is the stations'
    // covariance; the points' follows from it.
    result.cost_after = linearise();
    buildReducedSystem(0.0);
    const std::int64_t bad = choleskyInPlace(reduced_.data(), dim_, 1e-14);
    if (bad >= 0) {
        return Status(StatusCode::kDegenerate,
                      "bundle.adjust: reduced camera system singular at the solution (a station parameter that neither "
                      "points nor prior determine; detail 6 station + parameter)", bad);
    }
    invertReducedSystem();
    double weighted = 0.0;
    std::int64_t redundancy = 0;
    publishStations(weighted, redundancy);
    publishPoints(result, weighted, redundancy);
    publishResiduals(result);
    result.points_excluded = result.single_sighting + result.not_triangulated + result.behind_camera + result.too_few_inliers;
    result.sigma0 = redundancy > 0 ? math::sqrt(weighted / static_cast<double>(redundancy)) : 0.0;
    result.rms_before_px = imageRms(true);
    result.rms_after_px = imageRms(false);
    return Status::ok();
}

}  // namespace vtm::bundle
