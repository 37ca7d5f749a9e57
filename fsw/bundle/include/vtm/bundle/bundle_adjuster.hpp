// Bundle adjustment of a panorama's image network (paper §3; issue 23 item 3; docs/bundle.md).
//
// Unknowns: per station 6 parameters x = (dtheta [rad] about the site axes, dt [m]) of the
// left eye's pose, R = rotationExp(dtheta) R_approx, t = t_approx + dt (the convention of the
// pointing prior, vtm/core/image_network.hpp); the right eye follows through the calibrated
// b_from_a, which is how the rig constraint enters. Per tie point 3 (its site position, m).
// Observations: every TieObservation's pixel (sigma_px, robust Huber or Cauchy weights) and
// the pointing prior as pseudo-observations x ~ N(0, prior_covariance) (a zero variance holds
// that parameter fixed).
//
// Method: tie points triangulated from the approximate stations (linear least squares over
// all sightings; refused with a reason when they cannot be); Levenberg-Marquardt with the
// point blocks eliminated (Schur complement): the reduced camera system (6S x 6S, dense,
// filled only for station pairs that share points) is solved by Cholesky and the points are
// back-substituted; outliers (|r| > outlier_sigmas sigma_px) are flagged between rounds and
// the round repeated without them. Covariances from the inverse of the reduced system at the
// solution: per station 6x6 (about the adjusted pose, the prior's convention), per point 3x3.
//
// Memory: every array sized from the Config (workspaceBytes), carved from an Arena at init();
// adjust() never allocates. Loops bounded by the Config and the input sizes. Deterministic:
// + - * / sqrt and vtm::math, fixed-size Eigen, a fixed order of every sum.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::bundle {

constexpr std::int32_t kMaxStationsLimit = 64;       // 384 x 384 reduced system at most
constexpr std::int32_t kMaxPointsLimit = 65536;
constexpr std::int32_t kMaxObservationsLimit = 1 << 20;

enum class RobustLoss : std::uint8_t {
    kHuber = 0,   // rho(u) = u^2 for u <= k, 2 k u - k^2 beyond
    kCauchy = 1,  // rho(u) = k^2 log(1 + u^2 / k^2)
};

struct BundleConfig {
    // Static capacity. A station is one stereo exposure (two images): 32 stations = 64 images.
    std::int32_t max_stations = 32;         // 2..kMaxStationsLimit
    std::int32_t max_points = 4096;         // 1..kMaxPointsLimit
    std::int32_t max_observations = 16384;  // 2..kMaxObservationsLimit
    // Image measurement noise, pixels per axis (> 0), and the robust loss on u = |r| / sigma_px.
    double sigma_px = 0.3;
    RobustLoss loss = RobustLoss::kHuber;
    double robust_k = 3.0;        // > 0, in units of sigma_px
    // Between rounds an observation with u > outlier_sigmas (> robust_k) is flagged an outlier
    // and left out; at most max_rejection_rounds (0..10) such rounds after the first.
    double outlier_sigmas = 5.0;
    std::int32_t max_rejection_rounds = 3;
    // Datum: with the pointing prior every station is weighted by its prior_covariance (zero
    // variances hold parameters fixed). Without it (false) the priors are ignored and
    // datum_station must name a station, held fixed; the scale comes from the rigs' baselines.
    bool use_pointing_prior = true;
    std::int32_t datum_station = -1;  // -1 (none) or a station index held fixed
    // Levenberg-Marquardt: iterations per round (1..500), attempts per iteration (1..40),
    // the damping's start value (> 0; the diagonal is multiplied by 1 + lambda).
    std::int32_t max_iterations = 50;
    std::int32_t max_attempts = 20;
    double initial_lambda = 1e-3;
    // Converged when no station's step exceeds converge_rotation_rad and converge_translation_m
    // and no point's step converge_translation_m (> 0): far below the precision of a panorama
    // (1e-4 rad, millimetres), well above rounding.
    double converge_rotation_rad = 1e-8;
    double converge_translation_m = 1e-6;
    // Triangulation refusal: the largest angle between a point's rays below this (> 0, rad).
    double min_parallax_rad = 1e-3;

    // kOk, or kInvalidConfig naming the field ("bundle.sigma_px: ..."), value in detail.
    [[nodiscard]] Status validate() const noexcept;
};

enum class PointState : std::uint8_t {
    kUnused = 0,           // no sighting at all
    kAdjusted = 1,
    kSingleSighting = 2,   // seen in one image only
    kNotTriangulated = 3,  // rays (nearly) parallel, or a pixel without a ray
    kBehindCamera = 4,     // the triangulated point is behind one of its cameras
    kTooFewInliers = 5,    // fewer than two inlier sightings left after outlier rejection
};

enum class ObservationState : std::uint8_t {
    kInlier = 0,
    kOutlier = 1,        // |r| > outlier_sigmas sigma_px at the end of a round
    kPointExcluded = 2,  // its point is not adjusted (PointState says why)
};

enum class StopReason : std::uint8_t {
    kNone = 0,           // refused before iterating
    kConverged = 1,      // steps below the thresholds
    kNoDecrease = 2,     // no attempt reduced the cost (at the minimum to rounding)
    kMaxIterations = 3,  // max_iterations in the last round (the solution is still published)
};

struct StationSolution {
    RigidPose site_from_a{};         // adjusted left-eye pose
    Vec6 correction = Vec6::Zero();  // x = (dtheta, dt) from the approximate pose
    // Of (dtheta, dt) about the adjusted pose (R_true = Exp(dtheta) R_adjusted,
    // t_true = t_adjusted + dt); zero rows for fixed parameters.
    Mat6 covariance = Mat6::Zero();
};

struct PointSolution {
    Vec3 position_m = Vec3::Zero();  // site frame; the initial triangulation if not adjusted
    Mat3 covariance = Mat3::Zero();  // m^2; zero if not adjusted
    PointState state = PointState::kUnused;
    std::uint16_t sightings = 0U;    // inlier observations
};

struct ObservationResidual {
    Vec2 residual_px = Vec2::Zero();  // observed minus predicted at the solution
    double weight = 0.0;              // robust weight at the solution (0 for outliers)
    ObservationState state = ObservationState::kPointExcluded;
};

struct BundleResult {
    std::int32_t stations = 0;
    std::int32_t fixed_parameters = 0;
    std::int32_t points = 0;            // point ids in the input (point_count)
    std::int32_t points_adjusted = 0;
    std::int32_t points_excluded = 0;   // seen but not adjusted: the four counts below
    std::int32_t single_sighting = 0;
    std::int32_t not_triangulated = 0;
    std::int32_t behind_camera = 0;
    std::int32_t too_few_inliers = 0;
    std::int32_t observations = 0;
    std::int32_t inliers = 0;
    std::int32_t outliers = 0;
    std::int32_t iterations = 0;        // accepted steps, all rounds
    std::int32_t rounds = 0;
    StopReason stop = StopReason::kNone;
    // Image RMS (px, radial |r| over the final inliers) at the approximate stations with the
    // initial triangulation, and at the solution.
    double rms_before_px = 0.0;
    double rms_after_px = 0.0;
    // a-posteriori standard deviation of unit weight: sqrt(weighted SSR / redundancy).
    double sigma0 = 0.0;
    double cost_before = 0.0;  // sum rho(u) + prior terms, first round's start
    double cost_after = 0.0;
};

class BundleAdjuster {
public:
    // Bytes of arena for this configuration (every array and its padding), 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const BundleConfig& config) noexcept;

    // Validates the config and carves the workspace. kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const BundleConfig& config, Arena& arena) noexcept;

    // Adjusts the network: stations (approximate poses, rigs, priors), the tie observations
    // (point ids 0 .. point_count - 1). Refusals (nothing published): kNotInitialized;
    // kInvalidArgument (more stations / points / observations than the capacity: the count;
    // an observation naming a station or point out of range, a non-finite pixel: its index;
    // an invalid station (validateNetworkStation) or a prior singular on its free
    // parameters: the station; no datum without priors); kNoData (no point triangulated);
    // kDegenerate (the reduced system is not positive definite: 6 station + parameter).
    // Never allocates. The solutions stay valid until the next adjust().
    [[nodiscard]] Status adjust(Span<const NetworkStation> stations, Span<const TieObservation> observations,
                                std::uint32_t point_count, BundleResult& result) noexcept;

    [[nodiscard]] Span<const StationSolution> stations() const noexcept;
    [[nodiscard]] Span<const PointSolution> points() const noexcept;
    // In the order of the observations given.
    [[nodiscard]] Span<const ObservationResidual> residuals() const noexcept;
    [[nodiscard]] const BundleConfig& config() const noexcept { return config_; }

private:
    struct StationWork;
    struct PointWork;
    struct ObservationWork;
    struct StationGroup;

    [[nodiscard]] Status checkInput(Span<const NetworkStation> stations, Span<const TieObservation> observations,
                                    std::uint32_t point_count) const noexcept;
    [[nodiscard]] Status setUpStations(Span<const NetworkStation> stations, BundleResult& result) noexcept;
    void sortObservations(Span<const TieObservation> observations, std::uint32_t point_count) noexcept;
    void triangulatePoints(BundleResult& result) noexcept;
    [[nodiscard]] bool projectObservation(std::size_t sorted, bool trial, Vec2& predicted, Vec3* x_cam) const noexcept;
    [[nodiscard]] double evaluateCost(bool trial, bool& ok) const noexcept;
    [[nodiscard]] double linearise() noexcept;
    [[nodiscard]] Status solveStep(double lambda, double& max_rot, double& max_trans) noexcept;
    void buildReducedSystem(double lambda) noexcept;
    [[nodiscard]] std::size_t stationGroups(std::size_t point) noexcept;
    void acceptTrial() noexcept;
    [[nodiscard]] Status runRound(BundleResult& result) noexcept;
    [[nodiscard]] bool rejectOutliers(BundleResult& result) noexcept;
    [[nodiscard]] Status publish(BundleResult& result) noexcept;
    void invertReducedSystem() noexcept;
    void publishStations(double& weighted, std::int64_t& redundancy) noexcept;
    void publishPoints(BundleResult& result, double& weighted, std::int64_t& redundancy) noexcept;
    void publishResiduals(BundleResult& result) noexcept;
    [[nodiscard]] double imageRms(bool initial) const noexcept;

    BundleConfig config_{};
    bool initialized_ = false;
    Span<const NetworkStation> input_{};
    Span<const TieObservation> observations_{};
    std::size_t stationCount_ = 0U;
    std::size_t pointCount_ = 0U;
    std::size_t dim_ = 0U;  // 6 x stations
    Span<StationWork> stationWork_{};
    Span<StationSolution> stationOut_{};
    Span<PointWork> pointWork_{};
    Span<PointSolution> pointOut_{};
    Span<std::uint32_t> order_{};      // observation indices sorted by (point, station, eye)
    Span<std::uint32_t> pointFirst_{}; // first sorted index of each point (point_count + 1)
    Span<ObservationWork> obsWork_{};  // by sorted index
    Span<ObservationResidual> obsOut_{};  // by input index
    Span<StationGroup> groups_{};      // one point's observing stations (scratch)
    Span<double> reduced_{};           // dim x dim, row-major: the reduced system, then its factor
    Span<double> inverse_{};           // dim x dim: the reduced system's inverse (covariances)
    Span<double> rhs_{};               // dim
    Span<double> step_{};              // dim
};

}  // namespace vtm::bundle
