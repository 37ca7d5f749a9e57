// adjust(): the Levenberg-Marquardt rounds with the points eliminated (Schur complement),
// outlier rejection between rounds.
#include <cmath>

#include "bundle_internal.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::bundle {
namespace {

// Step of the differences of the projection, relative to the point's distance (below).
constexpr double kDiffStep = 1e-4;
constexpr double kMinLambda = 1e-12;
constexpr double kMaxLambda = 1e12;

double maxAbs3(const Vec3& v) noexcept { return std::fmax(std::fabs(v.x()), std::fmax(std::fabs(v.y()), std::fabs(v.z()))); }

// d pixel / d X_cam of any camera model from projectPoint alone: central differences at h
// and h/2 combined by Richardson's extrapolation, (4 D(h/2) - D(h)) / 3, whose error is of
// order h^4 (truncation, relative (h/|X|)^4 ~ 1e-16) and eps / h (rounding, ~1e-13 relative).
bool projectionJacobian(const CameraModel& model, const Vec3& xc, Mat23& j) noexcept {
    const double h = kDiffStep * (math::sqrt(xc.squaredNorm()) + 1.0);
    for (int c = 0; c < 3; ++c) {
        Vec2 d[4];
        const double steps[4] = {h, -h, 0.5 * h, -0.5 * h};
        for (int k = 0; k < 4; ++k) {
            if (!projectPoint(model, xc + steps[k] * Vec3::Unit(c), d[k]).isOk()) {
                return false;
            }
        }
        const Vec2 wide = (d[0] - d[1]) / (2.0 * h);
        const Vec2 narrow = (d[2] - d[3]) / h;
        j.col(c) = (4.0 * narrow - wide) / 3.0;
    }
    return true;
}

}  // namespace

bool BundleAdjuster::projectObservation(std::size_t sorted, bool trial, Vec2& predicted, Vec3* x_cam) const noexcept {
    const ObservationWork& w = obsWork_[sorted];
    const StationWork& s = stationWork_[w.station];
    const PointWork& p = pointWork_[observations_[w.input].point];
    const Mat3& R = trial ? s.R_trial : s.R;
    const Vec3& t = trial ? s.t_trial_m : s.t_m;
    const Vec3& X = trial ? p.X_trial_m : p.X_m;
    const NetworkStation& st = input_[w.station];
    Vec3 xc = R.transpose() * (X - t);
    if (w.eye == Eye::kRight) {
        xc = st.rig.b_from_a.R * xc + st.rig.b_from_a.t_m;
    }
    if (x_cam != nullptr) {
        *x_cam = xc;
    }
    return projectPoint(modelOfEye(st, w.eye), xc, predicted).isOk();
}

double BundleAdjuster::evaluateCost(bool trial, bool& ok) const noexcept {
    ok = true;
    double cost = 0.0;
    for (std::size_t k = 0; k < observations_.size(); ++k) {
        if (obsWork_[k].state != ObservationState::kInlier) {
            continue;
        }
        Vec2 predicted;
        if (!projectObservation(k, trial, predicted, nullptr)) {
            ok = false;
            return 0.0;
        }
        const Vec2 r = predicted - observations_[obsWork_[k].input].pixel_px;
        cost += robustRho(config_, math::sqrt(r.squaredNorm()) / config_.sigma_px);
    }
    for (std::size_t s = 0; s < stationCount_; ++s) {
        const Vec6& x = trial ? stationWork_[s].x_trial : stationWork_[s].x;
        cost += x.dot(stationWork_[s].prior_info * x);
    }
    return cost;
}

// Residuals, weights and Jacobians of every inlier at the current state; U, g of the stations
// (the prior's gradient included), V, g of the points. Returns the cost.
double BundleAdjuster::linearise() noexcept {
    for (std::size_t s = 0; s < stationCount_; ++s) {
        StationWork& sw = stationWork_[s];
        sw.U.setZero();
        sw.g = sw.prior_info * sw.x;
    }
    for (std::size_t p = 0; p < pointCount_; ++p) {
        pointWork_[p].V.setZero();
        pointWork_[p].g.setZero();
    }
    const double inv_var = 1.0 / (config_.sigma_px * config_.sigma_px);
    double cost = 0.0;
    for (std::size_t k = 0; k < observations_.size(); ++k) {
        ObservationWork& w = obsWork_[k];
        w.w = 0.0;
        Vec2 predicted;
        Vec3 xc;
        if (w.state != ObservationState::kInlier || !projectObservation(k, false, predicted, &xc)) {
            continue;
        }
        const NetworkStation& st = input_[w.station];
        const CameraModel& model = modelOfEye(st, w.eye);
        Mat23 jproj;
        if (!projectionJacobian(model, xc, jproj)) {
            continue;
        }
        StationWork& sw = stationWork_[w.station];
        PointWork& pw = pointWork_[observations_[w.input].point];
        // d X_cam: X_a = R^T (X - t), X_b = R_ba X_a + t_ba; d X_a / d theta = R^T [X - t]x J_l.
        const Mat3 camFromA = w.eye == Eye::kRight ? st.rig.b_from_a.R : Mat3::Identity();
        const Mat3 camFromSite = camFromA * sw.R.transpose();
        const Mat23 jcp = jproj * camFromSite;  // 2 x 3: d pixel / d X (site)
        w.jp = jcp;
        w.jc.leftCols<3>() = jcp * skew(pw.X_m - sw.t_m) * leftJacobian(sw.x.head<3>());
        w.jc.rightCols<3>() = -jcp;
        for (int c = 0; c < 6; ++c) {
            if (sw.fixed[c] != 0U) {
                w.jc.col(c).setZero();
            }
        }
        w.r = predicted - observations_[w.input].pixel_px;
        const double u = math::sqrt(w.r.squaredNorm()) / config_.sigma_px;
        w.w = robustWeight(config_, u) * inv_var;
        cost += robustRho(config_, u);
        sw.U += (w.w * w.jc.transpose()) * w.jc;
        sw.g += (w.w * w.jc.transpose()) * w.r;
        pw.V += (w.w * w.jp.transpose()) * w.jp;
        pw.g += (w.w * w.jp.transpose()) * w.r;
    }
    for (std::size_t s = 0; s < stationCount_; ++s) {
        cost += stationWork_[s].x.dot(stationWork_[s].prior_info * stationWork_[s].x);
    }
    return cost;
}

// groups_[0..n): the stations seeing `point` in ascending order, W = sum w Jc^T Jp each.
std::size_t BundleAdjuster::stationGroups(std::size_t point) noexcept {
    std::size_t n = 0U;
    for (std::size_t k = pointFirst_[point]; k < pointFirst_[point + 1U]; ++k) {
        const ObservationWork& w = obsWork_[k];
        if (w.w == 0.0) {
            continue;
        }
        if (n == 0U || groups_[n - 1U].station != w.station) {
            groups_[n].W.setZero();
            groups_[n].station = w.station;
            ++n;
        }
        groups_[n - 1U].W += (w.w * w.jc.transpose()) * w.jp;
    }
    return n;
}

// S = U + prior - sum_p W_p V_p*^-1 W_p^T (lower blocks), rhs = -g_c + sum_p W_p V_p*^-1 g_p;
// the diagonal of U + prior and of V multiplied by 1 + lambda; fixed parameters decoupled.
void BundleAdjuster::buildReducedSystem(double lambda) noexcept {
    const std::size_t n = dim_;
    for (std::size_t i = 0; i < n * n; ++i) {
        reduced_[i] = 0.0;
    }
    for (std::size_t s = 0; s < stationCount_; ++s) {
        const StationWork& sw = stationWork_[s];
        Mat6 a = sw.U + sw.prior_info;
        a.diagonal() *= 1.0 + lambda;
        for (std::size_t i = 0; i < 36U; ++i) {
            reduced_[(6U * s + i / 6U) * n + 6U * s + i % 6U] = a(static_cast<Eigen::Index>(i / 6U), static_cast<Eigen::Index>(i % 6U));
        }
        for (std::size_t i = 0; i < 6U; ++i) {
            rhs_[6U * s + i] = -sw.g(static_cast<Eigen::Index>(i));
        }
    }
    for (std::size_t p = 0; p < pointCount_; ++p) {
        PointWork& pw = pointWork_[p];
        if (pw.state != PointState::kAdjusted) {
            continue;
        }
        Mat3 v = pw.V;
        v.diagonal() *= 1.0 + lambda;
        pw.V_inv = v.inverse();
        const std::size_t groups = stationGroups(p);
        for (std::size_t a = 0; a < groups; ++a) {
            StationGroup& ga = groups_[a];
            ga.Y = ga.W * pw.V_inv;
            const Vec6 add = ga.Y * pw.g;
            for (std::size_t i = 0; i < 6U; ++i) {
                rhs_[6U * ga.station + i] += add(static_cast<Eigen::Index>(i));
            }
            for (std::size_t b = 0; b <= a; ++b) {
                const Mat6 block = ga.Y * groups_[b].W.transpose();
                double* row0 = reduced_.data() + 6U * ga.station * n + 6U * groups_[b].station;
                for (std::size_t i = 0; i < 36U; ++i) {
                    row0[(i / 6U) * n + i % 6U] -= block(static_cast<Eigen::Index>(i / 6U), static_cast<Eigen::Index>(i % 6U));
                }
            }
        }
    }
    for (std::size_t s = 0; s < stationCount_; ++s) {
        for (std::size_t k = 0; k < 6U; ++k) {
            if (stationWork_[s].fixed[k] == 0U) {
                continue;
            }
            const std::size_t i = 6U * s + k;
            for (std::size_t j = 0; j < n; ++j) {
                reduced_[i * n + j] = 0.0;
                reduced_[j * n + i] = 0.0;
            }
            reduced_[i * n + i] = 1.0;
            rhs_[i] = 0.0;
        }
    }
}

// One damped step: the reduced system solved, the points back-substituted, the trial state.
Status BundleAdjuster::solveStep(double lambda, double& max_rot, double& max_trans) noexcept {
    buildReducedSystem(lambda);
    const std::int64_t bad = choleskyInPlace(reduced_.data(), dim_, 1e-14);
    if (bad >= 0) {
        return Status(StatusCode::kDegenerate,
                      "bundle.adjust: reduced camera system not positive definite (a station parameter that neither "
                      "points nor prior determine; detail 6 station + parameter)", bad);
    }
    for (std::size_t i = 0; i < dim_; ++i) {
        step_[i] = rhs_[i];
    }
    choleskySolve(reduced_.data(), dim_, step_.data());
    max_rot = 0.0;
    max_trans = 0.0;
    for (std::size_t s = 0; s < stationCount_; ++s) {
        StationWork& sw = stationWork_[s];
        Vec6 d;
        for (std::size_t i = 0; i < 6U; ++i) {
            d(static_cast<Eigen::Index>(i)) = step_[6U * s + i];
        }
        sw.x_trial = sw.x + d;
        sw.R_trial = rotationExp(sw.x_trial.head<3>()) * sw.R0;
        sw.t_trial_m = sw.t0_m + sw.x_trial.tail<3>();
        max_rot = std::fmax(max_rot, maxAbs3(d.head<3>()));
        max_trans = std::fmax(max_trans, maxAbs3(d.tail<3>()));
    }
    for (std::size_t p = 0; p < pointCount_; ++p) {
        PointWork& pw = pointWork_[p];
        if (pw.state != PointState::kAdjusted) {
            continue;
        }
        Vec3 rhs = -pw.g;
        const std::size_t groups = stationGroups(p);
        for (std::size_t a = 0; a < groups; ++a) {
            Vec6 dc;
            for (std::size_t i = 0; i < 6U; ++i) {
                dc(static_cast<Eigen::Index>(i)) = step_[6U * groups_[a].station + i];
            }
            rhs -= groups_[a].W.transpose() * dc;
        }
        const Vec3 dp = pw.V_inv * rhs;
        pw.X_trial_m = pw.X_m + dp;
        max_trans = std::fmax(max_trans, maxAbs3(dp));
    }
    return Status::ok();
}

void BundleAdjuster::acceptTrial() noexcept {
    for (std::size_t s = 0; s < stationCount_; ++s) {
        StationWork& sw = stationWork_[s];
        sw.x = sw.x_trial;
        sw.R = sw.R_trial;
        sw.t_m = sw.t_trial_m;
    }
    for (std::size_t p = 0; p < pointCount_; ++p) {
        if (pointWork_[p].state == PointState::kAdjusted) {
            pointWork_[p].X_m = pointWork_[p].X_trial_m;
        }
    }
}

Status BundleAdjuster::runRound(BundleResult& result) noexcept {
    double lambda = config_.initial_lambda;
    result.stop = StopReason::kMaxIterations;
    for (std::int32_t it = 0; it < config_.max_iterations; ++it) {
        const double cost = linearise();
        bool accepted = false;
        bool small = false;
        double max_rot = 0.0;
        double max_trans = 0.0;
        for (std::int32_t attempt = 0; attempt < config_.max_attempts && !accepted && !small; ++attempt) {
            VTM_RETURN_IF_ERROR(solveStep(lambda, max_rot, max_trans));
            // A step below the thresholds ends the round whether or not it lowers the cost
            // (at the minimum, rounding decides that).
            small = max_rot <= config_.converge_rotation_rad && max_trans <= config_.converge_translation_m;
            bool ok = false;
            const double trial = evaluateCost(true, ok);
            accepted = ok && trial < cost;
            lambda = accepted ? std::fmax(kMinLambda, 0.1 * lambda) : std::fmin(kMaxLambda, 10.0 * lambda);
        }
        if (accepted) {
            acceptTrial();
            ++result.iterations;
        }
        if (small || !accepted) {
            result.stop = small ? StopReason::kConverged : StopReason::kNoDecrease;
            return Status::ok();
        }
    }
    return Status::ok();
}

// Re-judges every observation of the adjusted points at the current state: beyond
// outlier_sigmas it is an outlier, within it an inlier again (a good sighting flagged while an
// outlier still pulled its point comes back). A point left with fewer than two inliers is
// excluded. True when anything changed.
bool BundleAdjuster::rejectOutliers(BundleResult& result) noexcept {
    bool changed = false;
    for (std::size_t p = 0; p < pointCount_; ++p) {
        PointWork& pw = pointWork_[p];
        if (pw.state != PointState::kAdjusted) {
            continue;
        }
        std::size_t inliers = 0U;
        for (std::size_t k = pointFirst_[p]; k < pointFirst_[p + 1U]; ++k) {
            ObservationWork& w = obsWork_[k];
            Vec2 predicted;
            const bool ok = projectObservation(k, false, predicted, nullptr);
            const double u = ok ? math::sqrt((predicted - observations_[w.input].pixel_px).squaredNorm()) / config_.sigma_px : 0.0;
            const ObservationState state = (!ok || u > config_.outlier_sigmas) ? ObservationState::kOutlier : ObservationState::kInlier;
            changed = changed || state != w.state;
            w.state = state;
            inliers += state == ObservationState::kInlier ? 1U : 0U;
        }
        if (inliers < 2U) {
            pw.state = PointState::kTooFewInliers;
            ++result.too_few_inliers;
            for (std::size_t k = pointFirst_[p]; k < pointFirst_[p + 1U]; ++k) {
                if (obsWork_[k].state == ObservationState::kInlier) {
                    obsWork_[k].state = ObservationState::kPointExcluded;
                }
            }
        }
    }
    return changed;
}

Status BundleAdjuster::adjust(Span<const NetworkStation> stations, Span<const TieObservation> observations,
                              std::uint32_t point_count, BundleResult& result) noexcept {
    result = BundleResult{};
    stationCount_ = 0U;
    pointCount_ = 0U;
    observations_ = Span<const TieObservation>();
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "bundle.adjust: init() first");
    }
    VTM_RETURN_IF_ERROR(checkInput(stations, observations, point_count));
    input_ = stations;
    observations_ = observations;
    stationCount_ = stations.size();
    pointCount_ = point_count;
    dim_ = 6U * stationCount_;
    result.stations = static_cast<std::int32_t>(stationCount_);
    result.points = static_cast<std::int32_t>(point_count);
    result.observations = static_cast<std::int32_t>(observations.size());
    Status status = setUpStations(stations, result);
    if (status.isOk()) {
        sortObservations(observations, point_count);
        triangulatePoints(result);
        bool ok = false;
        result.cost_before = evaluateCost(false, ok);
        std::int32_t adjusted = 0;
        for (std::size_t p = 0; p < pointCount_; ++p) {
            adjusted += pointWork_[p].state == PointState::kAdjusted ? 1 : 0;
        }
        if (adjusted == 0 || !ok) {
            status = Status(StatusCode::kNoData, "bundle.adjust: no tie point could be triangulated (detail: those refused)",
                            result.single_sighting + result.not_triangulated + result.behind_camera);
        }
    }
    for (std::int32_t round = 0; status.isOk() && round <= config_.max_rejection_rounds; ++round) {
        status = runRound(result);
        ++result.rounds;
        if (!status.isOk() || round == config_.max_rejection_rounds || !rejectOutliers(result)) {
            break;
        }
    }
    if (status.isOk()) {
        status = publish(result);
    }
    if (!status.isOk()) {
        stationCount_ = 0U;
        pointCount_ = 0U;
        observations_ = Span<const TieObservation>();
        result.stop = StopReason::kNone;
    }
    return status;
}

}  // namespace vtm::bundle
