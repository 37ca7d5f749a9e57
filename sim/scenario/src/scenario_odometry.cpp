// The odometry error model (sim/scenario.hpp OdometryErrorModel, docs/sim-scenarios.md).
#include <cstring>

#include "rotation.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {
namespace {

using detail::kRadPerDeg;

// The error of one run: drawn once per seed.
struct RunErrors {
    double scale = 0.0;           // fraction
    double heading_rate = 0.0;    // rad/m
    double pitch_rate = 0.0;      // rad/m
    double roll_rate = 0.0;       // rad/m
    double walk_m_per_sqrt_m = 0.0;
};

RunErrors drawRunErrors(const OdometryErrorModel& m, Random& rng) noexcept {
    // One draw per statement: argument evaluation order differs between targets.
    const double n_scale = rng.normal();
    const double n_heading = rng.normal();
    const double n_pitch = rng.normal();
    const double n_roll = rng.normal();
    RunErrors e;
    e.scale = (m.scale_error_percent + m.scale_error_sigma_percent * n_scale) / 100.0;
    e.heading_rate = (m.heading_drift_deg_per_m + m.heading_drift_sigma_deg_per_m * n_heading) * kRadPerDeg;
    e.pitch_rate = m.tilt_drift_sigma_deg_per_m * n_pitch * kRadPerDeg;
    e.roll_rate = m.tilt_drift_sigma_deg_per_m * n_roll * kRadPerDeg;
    e.walk_m_per_sqrt_m = m.random_walk_m_per_sqrt_m;
    return e;
}

// Attitude error after `distance_m` of travel, applied on the left (site frame).
Mat3 attitudeError(const RunErrors& e, double distance_m) noexcept {
    return detail::rotationZ(e.heading_rate * distance_m) * detail::rotationY(e.pitch_rate * distance_m) *
           detail::rotationX(e.roll_rate * distance_m);
}

// Diagonal covariance: the model's second moments (bias included) at distance d.
void modelCovariance(const OdometryErrorModel& m, double d, double* covariance) noexcept {
    std::memset(covariance, 0, 36U * sizeof(double));
    const double walk2 = m.random_walk_m_per_sqrt_m * m.random_walk_m_per_sqrt_m;
    const double scale2 = (m.scale_error_percent * m.scale_error_percent +
                           m.scale_error_sigma_percent * m.scale_error_sigma_percent) / 1e4;
    const double heading2 = (m.heading_drift_deg_per_m * m.heading_drift_deg_per_m +
                             m.heading_drift_sigma_deg_per_m * m.heading_drift_sigma_deg_per_m) *
                            (kRadPerDeg * kRadPerDeg);
    const double tilt2 = m.tilt_drift_sigma_deg_per_m * m.tilt_drift_sigma_deg_per_m * (kRadPerDeg * kRadPerDeg);
    const double d2 = d * d;
    const double d4_4 = d2 * d2 / 4.0;  // cross-track error of a constant drift: rate d^2 / 2
    covariance[0] = walk2 * d + scale2 * d2 + heading2 * d4_4;
    covariance[7] = covariance[0];
    covariance[14] = walk2 * d + tilt2 * d4_4;
    covariance[21] = tilt2 * d2;
    covariance[28] = tilt2 * d2;
    covariance[35] = heading2 * d2;
}

Vec3 positionOf(const VehiclePose& p) noexcept { return Vec3(p.position_m[0], p.position_m[1], p.position_m[2]); }

Quat attitudeOf(const VehiclePose& p) noexcept {
    return Quat(p.attitude_wxyz[0], p.attitude_wxyz[1], p.attitude_wxyz[2], p.attitude_wxyz[3]);
}

// Position and attitude as truth plus error. With a zero model the error terms are exact
// zeros and identities, so the odometry equals the truth bit for bit.
void setPose(const Vec3& position, const Quat& attitude, VehiclePose& out) noexcept {
    out.position_m[0] = position.x();
    out.position_m[1] = position.y();
    out.position_m[2] = position.z();
    out.attitude_wxyz[0] = attitude.w();
    out.attitude_wxyz[1] = attitude.x();
    out.attitude_wxyz[2] = attitude.y();
    out.attitude_wxyz[3] = attitude.z();
}

}  // namespace

void applyOdometryErrors(const OdometryErrorModel& model, std::uint64_t seed, const VehiclePose* truth,
                         VehiclePose* odometry, std::int32_t count) noexcept {
    VTM_ASSERT(truth != nullptr && odometry != nullptr && count >= 1, count);
    if (truth == nullptr || odometry == nullptr || count < 1) {
        return;
    }
    Random rng(seed);
    const RunErrors e = drawRunErrors(model, rng);
    odometry[0] = truth[0];  // the odometry starts from the true pose, with zero covariance
    std::memset(odometry[0].covariance, 0, sizeof(odometry[0].covariance));
    Vec3 position_error = Vec3::Zero();
    double distance_m = 0.0;
    for (std::int32_t k = 1; k < count; ++k) {  // bound: count poses
        const Vec3 step = positionOf(truth[k]) - positionOf(truth[k - 1]);
        const double length_m = math::sqrt(step.squaredNorm());
        // The attitude error at the middle of the step rotates it (a constant drift rate).
        const Mat3 error_mid = attitudeError(e, distance_m + 0.5 * length_m);
        const double walk_sigma = e.walk_m_per_sqrt_m * math::sqrt(length_m);
        const double walk_x = rng.normal(0.0, walk_sigma);
        const double walk_y = rng.normal(0.0, walk_sigma);
        const double walk_z = rng.normal(0.0, walk_sigma);
        position_error += ((1.0 + e.scale) * (error_mid * step) - step) + Vec3(walk_x, walk_y, walk_z);
        distance_m += length_m;
        odometry[k].timestamp_ns = truth[k].timestamp_ns;
        const Quat attitude = detail::quaternionOf(attitudeError(e, distance_m)) * attitudeOf(truth[k]);
        setPose(positionOf(truth[k]) + position_error, attitude, odometry[k]);
        modelCovariance(model, distance_m, odometry[k].covariance);
    }
}

}  // namespace vtm::sim
