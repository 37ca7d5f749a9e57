// MotionRefiner: Levenberg-Marquardt over 5 motion parameters plus one inverse range per
// match, reduced to a 5x5 system by the Schur complement (docs/motion.md).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "vtm/core/math.hpp"
#include "vtm/motion/motion_refiner.hpp"

namespace vtm::motion {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;
using Mat25 = Eigen::Matrix<double, 2, 5>;

struct MotionRefiner::Normal {
    Mat5 U = Mat5::Zero();   // sum w J_m^T J_m
    Vec5 g = Vec5::Zero();   // sum w J_m^T r
};

namespace {

constexpr double kInfiniteCost = 1e300;
constexpr double kLambdaInitial = 1e-3;
constexpr double kLambdaMax = 1e12;
constexpr double kLambdaMin = 1e-12;
// Relative cost decrease below which LM has converged.
constexpr double kCostTolerance = 1e-12;
// 1-D Gauss-Newton steps of a single inverse range (quadratic convergence: a handful).
constexpr int kRangeSteps = 8;
// Relative step of the central differences of the projection (metres per metre of
// distance): truncation error ~ h^2, rounding ~ eps / h; 1e-6 balances both near 1e-12.
constexpr double kDiffStep = 1e-6;

bool finite2(const Vec2& v) noexcept { return math::isFinite(v.x()) && math::isFinite(v.y()); }

// Tolerance of the input rotation's orthonormality (max |R^T R - I| element).
constexpr double kRotationTolerance = 1e-6;

double kernelWeight(RobustKernel kernel, double scale, double e) noexcept {
    if (kernel == RobustKernel::kHuber) {
        return (e <= scale) ? 1.0 : scale / e;
    }
    if (kernel == RobustKernel::kCauchy) {
        const double q = e / scale;
        return 1.0 / (1.0 + q * q);
    }
    return 1.0;
}

double kernelCost(RobustKernel kernel, double scale, double e) noexcept {
    if (kernel == RobustKernel::kHuber) {
        return (e <= scale) ? 0.5 * e * e : scale * (e - 0.5 * scale);
    }
    if (kernel == RobustKernel::kCauchy) {
        const double q = e / scale;
        return 0.5 * scale * scale * math::log1p(q * q);
    }
    return 0.5 * e * e;
}

Status checkInput(const MotionInput& in, std::size_t flags, std::size_t ranges) noexcept {
    VTM_RETURN_IF_ERROR(validateCameraModel(in.pair.model_a));
    VTM_RETURN_IF_ERROR(validateCameraModel(in.pair.model_b));
    const std::size_t n = in.pixels_a.size();
    if (in.pixels_b.size() != n) {
        return Status(StatusCode::kInvalidArgument, "pixels_b: size differs from pixels_a",
                      static_cast<std::int64_t>(in.pixels_b.size()));
    }
    if (n > static_cast<std::size_t>(kMaxMotionMatches)) {
        return Status(StatusCode::kInvalidArgument, "pixels_a: more than kMaxMotionMatches (1024) matches",
                      static_cast<std::int64_t>(n));
    }
    if ((flags != 0U && flags != n) || (ranges != 0U && ranges != n)) {
        return Status(StatusCode::kInvalidArgument, "inlier_flags / ranges_m: must be empty or one per match",
                      static_cast<std::int64_t>(flags != 0U && flags != n ? flags : ranges));
    }
    if (!isRotation(in.pair.b_from_a.R, kRotationTolerance)) {
        return Status(StatusCode::kInvalidArgument, "pair.b_from_a.R: not a finite rotation (within 1e-6)");
    }
    const Vec3& t = in.pair.b_from_a.t_m;
    if (!math::isFinite(t.x()) || !math::isFinite(t.y()) || !math::isFinite(t.z())) {
        return Status(StatusCode::kInvalidArgument, "pair.b_from_a.t_m: not finite");
    }
    if (t.dot(t) == 0.0) {
        return Status(StatusCode::kInvalidArgument, "pair.b_from_a.t_m: zero baseline (direction undefined)");
    }
    for (std::size_t i = 0U; i < n; ++i) {
        if (!finite2(in.pixels_a[i]) || !finite2(in.pixels_b[i])) {
            return Status(StatusCode::kInvalidArgument, "pixels_a / pixels_b: non-finite pixel",
                          static_cast<std::int64_t>(i));
        }
    }
    return Status::ok();
}

}  // namespace

// ------------------------------------------------------------------ residual model --

bool MotionRefiner::residual(const Motion& m, std::int32_t i, double rho, Vec2& r) const noexcept {
    const Vec3 x_b = m.R * (origin_a_[i] + direction_a_[i] / rho) + m.baseline_m * m.u;
    Vec2 p;
    if (!projectPoint(*model_b_, x_b, p).isOk()) {
        return false;
    }
    r = pixel_b_[i] - p;
    return true;
}

bool MotionRefiner::residualAndJacobian(const Motion& m, std::int32_t i, double rho, Vec2& r, Mat25& j_motion,
                                        Vec2& j_rho) const noexcept {
    const Vec3 p_rot = m.R * (origin_a_[i] + direction_a_[i] / rho);
    const Vec3 x_b = p_rot + m.baseline_m * m.u;
    Vec2 p;
    if (!projectPoint(*model_b_, x_b, p).isOk()) {
        return false;
    }
    r = pixel_b_[i] - p;
    // d pixel / d X_b by central differences: works for every camera model, and uses
    // only the deterministic projectPoint.
    Eigen::Matrix<double, 2, 3> jp;
    const double h = kDiffStep * (math::sqrt(x_b.dot(x_b)) + 1.0);
    for (int k = 0; k < 3; ++k) {
        Vec2 plus;
        Vec2 minus;
        const Vec3 e = h * Vec3::Unit(k);
        if (!projectPoint(*model_b_, x_b + e, plus).isOk() || !projectPoint(*model_b_, x_b - e, minus).isOk()) {
            return false;
        }
        jp.col(k) = (plus - minus) / (2.0 * h);
    }
    Vec3 b1;
    Vec3 b2;
    directionTangentBasis(m.u, b1, b2);
    // Exp(omega) R X_a ~ P + omega x P: d/d omega = -[P]x. u + beta1 b1 + beta2 b2.
    j_motion.leftCols<3>() = jp * (-skew(p_rot));
    j_motion.col(3) = m.baseline_m * (jp * b1);
    j_motion.col(4) = m.baseline_m * (jp * b2);
    j_rho = jp * (m.R * direction_a_[i]) * (-1.0 / (rho * rho));
    return true;
}

// Weight of the rotation prior in the cost (pixels^2 per rad^2), 0 without one.
double MotionRefiner::priorWeight() const noexcept {
    const double sigma = config_.rotation_prior_sigma_rad;
    return sigma > 0.0 ? (config_.robust_scale_px * config_.robust_scale_px) / (sigma * sigma) : 0.0;
}

double MotionRefiner::robustCost(const Motion& m, const double* rho) const noexcept {
    double cost = 0.0;
    const double prior = priorWeight();
    if (prior > 0.0) {
        const Vec3 d = rotationLog(m.R * R_prior_.transpose());
        cost += 0.5 * prior * d.dot(d);
    }
    for (std::int32_t i = 0; i < count_; ++i) {
        if (inlier_[i] == 0U) {
            continue;
        }
        Vec2 r;
        if (!residual(m, i, rho[i], r)) {
            return kInfiniteCost;   // a step that moves a point behind B is refused
        }
        cost += kernelCost(config_.kernel, config_.robust_scale_px, math::sqrt(r.dot(r)));
    }
    return cost;
}

// ------------------------------------------------------------------ initial depths --

double MotionRefiner::triangulate(const Motion& m, std::int32_t i) const noexcept {
    // B's ray in A's frame: X_a = R^T (X_b - t). Midpoint of the common perpendicular.
    const Vec3 t = m.baseline_m * m.u;
    const Vec3 ob = m.R.transpose() * (origin_b_[i] - t);
    const Vec3 db = m.R.transpose() * direction_b_[i];
    const Vec3& da = direction_a_[i];
    const Vec3 w0 = origin_a_[i] - ob;
    const double b = da.dot(db);
    const double d = da.dot(w0);
    const double e = db.dot(w0);
    const double denom = 1.0 - b * b;
    double range_m = config_.range_max_m;   // parallel rays: as far as plausible
    if (denom > 1e-12) {
        const double lambda = (b * e - d) / denom;
        if (lambda > 0.0) {
            range_m = lambda;
        }
    }
    return std::clamp(1.0 / range_m, rho_min_, rho_max_);
}

double MotionRefiner::bestInverseRange(const Motion& m, std::int32_t i, double rho) const noexcept {
    Vec2 r;
    Mat25 jm;
    Vec2 jr;
    if (!residualAndJacobian(m, i, rho, r, jm, jr)) {
        return rho;
    }
    double err2 = r.dot(r);
    for (int step = 0; step < kRangeSteps; ++step) {
        const double jj = jr.dot(jr);
        if (!(jj > 0.0)) {
            break;
        }
        const double next = std::clamp(rho + jr.dot(r) / jj, rho_min_, rho_max_);
        Vec2 r_next;
        if (!residualAndJacobian(m, i, next, r_next, jm, jr) || !(r_next.dot(r_next) < err2)) {
            break;   // no further decrease: rho is the 1-D optimum (or a clamp)
        }
        rho = next;
        r = r_next;
        err2 = r.dot(r);
    }
    return rho;
}

std::int32_t MotionRefiner::prepare(const MotionInput& input, const Config& config, const Motion& m) noexcept {
    model_b_ = &input.pair.model_b;
    config_ = config;
    count_ = static_cast<std::int32_t>(input.pixels_a.size());
    rho_min_ = 1.0 / config.range_max_m;
    rho_max_ = 1.0 / config.range_min_m;
    std::int32_t usable = 0;
    for (std::int32_t i = 0; i < count_; ++i) {
        const auto k = static_cast<std::size_t>(i);
        CameraRay ray_a;
        CameraRay ray_b;
        bool ok = backProjectPixel(input.pair.model_a, input.pixels_a[k], ray_a).isOk() &&
                  backProjectPixel(input.pair.model_b, input.pixels_b[k], ray_b).isOk();
        origin_a_[i] = ray_a.origin_m;
        direction_a_[i] = ray_a.direction;
        origin_b_[i] = ray_b.origin_m;
        direction_b_[i] = ray_b.direction;
        pixel_b_[i] = input.pixels_b[k];
        rho_[i] = rho_min_;
        if (ok) {
            // Best range under the initial motion; unusable if its point misses B.
            rho_[i] = bestInverseRange(m, i, triangulate(m, i));
            Vec2 r;
            ok = residual(m, i, rho_[i], r);
        }
        usable_[i] = ok ? 1U : 0U;
        inlier_[i] = usable_[i];   // the first pass starts from every usable match
        usable += usable_[i];
    }
    return usable;
}

// -------------------------------------------------------------- normal equations --

bool MotionRefiner::buildNormal(const Motion& m, bool robust, Normal& n) noexcept {
    n = Normal{};
    for (std::int32_t i = 0; i < count_; ++i) {
        if (inlier_[i] == 0U) {
            continue;
        }
        Vec2 r;
        Mat25 jm;
        Vec2 jr;
        if (!residualAndJacobian(m, i, rho_[i], r, jm, jr)) {
            return false;
        }
        const double w = robust ? kernelWeight(config_.kernel, config_.robust_scale_px, math::sqrt(r.dot(r))) : 1.0;
        n.U += w * (jm.transpose() * jm);
        n.g += w * (jm.transpose() * r);
        w_[i] = w * (jm.transpose() * jr);
        v_[i] = w * jr.dot(jr);
        g_rho_[i] = w * jr.dot(r);
    }
    // Rotation prior: "observation" 0 of d = log(R R0^T), whose derivative with respect to
    // the left update Exp(omega) R is the identity to first order.
    const double prior = priorWeight();
    if (prior > 0.0) {
        const Vec3 d = rotationLog(m.R * R_prior_.transpose());
        n.U.topLeftCorner<3, 3>() += prior * Mat3::Identity();
        n.g.head<3>() -= prior * d;
    }
    return true;
}

bool MotionRefiner::solveStep(const Normal& n, double lambda, Vec5& dx) noexcept {
    // Marquardt damping: the diagonal scaled by (1 + lambda), for U and every V_i.
    Mat5 s = n.U;
    s.diagonal() *= (1.0 + lambda);
    Vec5 b = n.g;
    for (std::int32_t i = 0; i < count_; ++i) {
        if (inlier_[i] == 0U) {
            continue;
        }
        const double vd = std::max(v_[i] * (1.0 + lambda), 1e-30);
        s -= (w_[i] * w_[i].transpose()) / vd;
        b -= w_[i] * (g_rho_[i] / vd);
    }
    const Eigen::LLT<Mat5> llt(s);
    if (llt.info() != Eigen::Success) {
        return false;
    }
    dx = llt.solve(b);
    for (int k = 0; k < 5; ++k) {
        if (!math::isFinite(dx[k])) {
            return false;
        }
    }
    for (std::int32_t i = 0; i < count_; ++i) {
        if (inlier_[i] != 0U) {
            const double vd = std::max(v_[i] * (1.0 + lambda), 1e-30);
            rho_trial_[i] = std::clamp(rho_[i] + (g_rho_[i] - w_[i].dot(dx)) / vd, rho_min_, rho_max_);
        }
    }
    return true;
}

// ----------------------------------------------------------------- LM, one pass --

std::int32_t MotionRefiner::runPass(Motion& m) noexcept {
    double lambda = kLambdaInitial;
    double cost = robustCost(m, rho_);
    Normal normal;
    bool have_normal = buildNormal(m, true, normal);
    std::int32_t iter = 0;
    // bound: config_.max_iterations (<= kMaxMotionIterations) trial steps.
    for (; iter < config_.max_iterations && have_normal && lambda <= kLambdaMax; ++iter) {
        Vec5 dx;
        if (!solveStep(normal, lambda, dx)) {
            lambda *= 10.0;
            continue;
        }
        Motion trial = m;
        trial.R = rotationExp(dx.head<3>()) * m.R;
        Vec3 b1;
        Vec3 b2;
        directionTangentBasis(m.u, b1, b2);
        const Vec3 u = m.u + dx[3] * b1 + dx[4] * b2;
        trial.u = u / math::sqrt(u.dot(u));
        const double trial_cost = robustCost(trial, rho_trial_);
        if (!(trial_cost < cost)) {
            lambda *= 10.0;
            continue;
        }
        m = trial;
        for (std::int32_t i = 0; i < count_; ++i) {
            rho_[i] = (inlier_[i] != 0U) ? rho_trial_[i] : rho_[i];
        }
        lambda = std::max(lambda * 0.1, kLambdaMin);
        const bool converged = (cost - trial_cost) <= kCostTolerance * cost;
        cost = trial_cost;
        if (converged) {
            ++iter;
            break;
        }
        have_normal = buildNormal(m, true, normal);
    }
    return iter;
}

std::int32_t MotionRefiner::classify(const Motion& m, bool& changed) noexcept {
    changed = false;
    std::int32_t inliers = 0;
    const double limit2 = config_.outlier_threshold_px * config_.outlier_threshold_px;
    for (std::int32_t i = 0; i < count_; ++i) {
        std::uint8_t flag = 0U;
        if (usable_[i] != 0U) {
            // Outliers had no share in the solve: start them from a fresh triangulation.
            const double start = (inlier_[i] != 0U) ? rho_[i] : triangulate(m, i);
            rho_[i] = bestInverseRange(m, i, start);
            Vec2 r;
            flag = (residual(m, i, rho_[i], r) && r.dot(r) <= limit2) ? 1U : 0U;
        }
        changed = changed || (flag != inlier_[i]);
        inlier_[i] = flag;
        inliers += flag;
    }
    return inliers;
}

double MotionRefiner::inlierRms(const Motion& m) const noexcept {
    double sum2 = 0.0;
    std::int32_t n = 0;
    for (std::int32_t i = 0; i < count_; ++i) {
        Vec2 r;
        if (inlier_[i] != 0U && residual(m, i, rho_[i], r)) {
            sum2 += r.dot(r);
            ++n;
        }
    }
    return (n > 0) ? math::sqrt(sum2 / static_cast<double>(n)) : 0.0;
}

// -------------------------------------------------------------------- the result --

// The motion's uncertainty seen across the epipolar lines: for each inlier, the part of
// its B pixel's motion Jacobian perpendicular to the direction in which its range moves
// it (that part a range cannot absorb: it is what rectification turns into vertical
// disparity), n^T J_m C J_m^T n; the root of the mean over the inliers.
double MotionRefiner::epipolarSigma(const Motion& m, const Mat5& cov) const noexcept {
    double sum2 = 0.0;
    std::int32_t n = 0;
    for (std::int32_t i = 0; i < count_; ++i) {
        Vec2 r;
        Mat25 jm;
        Vec2 jr;
        if (inlier_[i] == 0U || !residualAndJacobian(m, i, rho_[i], r, jm, jr)) {
            continue;
        }
        const double len = math::sqrt(jr.dot(jr));
        if (!(len > 0.0)) {
            continue;  // a range that does not move the pixel: no epipolar direction
        }
        const Vec2 normal(-jr.y() / len, jr.x() / len);
        const Vec5 a = jm.transpose() * normal;
        sum2 += a.dot(cov * a);
        ++n;
    }
    return (n > 0) ? math::sqrt(sum2 / static_cast<double>(n)) : 0.0;
}

Status MotionRefiner::finish(const Motion& m, MotionResult& result) noexcept {
    Normal normal;
    if (!buildNormal(m, false, normal)) {
        return Status(StatusCode::kDegenerate, "motion: an inlier does not project into B at the solution");
    }
    Mat5 s = normal.U;
    for (std::int32_t i = 0; i < count_; ++i) {
        if (inlier_[i] != 0U) {
            s -= (w_[i] * w_[i].transpose()) / std::max(v_[i], 1e-30);
        }
    }
    const Eigen::LLT<Mat5> llt(s);
    if (llt.info() != Eigen::Success) {
        return Status(StatusCode::kDegenerate, "motion: normal equations singular (matches do not fix the motion)");
    }
    result.inliers = 0;
    for (std::int32_t i = 0; i < count_; ++i) {
        result.inliers += inlier_[i];
    }
    result.rms_px = inlierRms(m);
    // sigma^2 = sum r^2 / (2n - n - 5): 2 residuals per inlier, n ranges + 5 motion.
    const double n = static_cast<double>(result.inliers);
    const double sigma2 = result.rms_px * result.rms_px * n / (n - 5.0);
    // Column by column: a matrix right-hand side would take Eigen's blocked (level-3)
    // triangular solver, whose workspace may come from the heap.
    Mat5 cov;
    for (int c = 0; c < 5; ++c) {
        cov.col(c) = sigma2 * llt.solve(Vec5::Unit(c));
    }
    for (int r = 0; r < 5; ++r) {
        for (int c = 0; c < 5; ++c) {
            result.covariance[r * 5 + c] = cov(r, c);
        }
    }
    result.rotation_sigma_rad = math::sqrt(cov(0, 0) + cov(1, 1) + cov(2, 2));
    result.direction_sigma_rad = math::sqrt(cov(3, 3) + cov(4, 4));
    result.epipolar_sigma_px = epipolarSigma(m, cov);
    result.R_b_from_a = m.R;
    result.t_b_from_a_m = m.baseline_m * m.u;
    return Status::ok();
}

Status MotionRefiner::refine(const MotionInput& input, const Config& config, MotionResult& result,
                             Span<std::uint8_t> inlier_flags, Span<double> ranges_m) noexcept {
    VTM_RETURN_IF_ERROR(checkInput(input, inlier_flags.size(), ranges_m.size()));
    VTM_RETURN_IF_ERROR(config.validate());
    result = MotionResult{};
    result.matches = static_cast<std::int32_t>(input.pixels_a.size());
    Motion m;
    m.R = input.pair.b_from_a.R;
    R_prior_ = input.pair.b_from_a.R;
    m.baseline_m = math::sqrt(input.pair.b_from_a.t_m.dot(input.pair.b_from_a.t_m));
    m.u = input.pair.b_from_a.t_m / m.baseline_m;
    const std::int32_t usable = prepare(input, config, m);
    if (usable < config.min_inliers) {
        return Status(StatusCode::kDegenerate, "matches: fewer usable matches than min_inliers", usable);
    }
    result.initial_rms_px = inlierRms(m);
    // bound: config.max_passes (<= kMaxMotionPasses) passes.
    for (std::int32_t pass = 0; pass < config.max_passes; ++pass) {
        result.iterations += runPass(m);
        result.passes += 1;
        bool changed = false;
        const std::int32_t inliers = classify(m, changed);
        if (inliers < config.min_inliers) {
            return Status(StatusCode::kDegenerate, "matches: fewer inliers than min_inliers", inliers);
        }
        if (!changed) {
            break;
        }
    }
    VTM_RETURN_IF_ERROR(finish(m, result));
    for (std::int32_t i = 0; i < count_; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (!inlier_flags.empty()) {
            inlier_flags[k] = inlier_[i];
        }
        if (!ranges_m.empty()) {
            ranges_m[k] = (inlier_[i] != 0U) ? 1.0 / rho_[i] : math::kNaN;
        }
    }
    return Status::ok();
}

}  // namespace vtm::motion
