// Configuration checks, the workspace formula and init() of the bundle adjuster.
#include <cmath>

#include "bundle_internal.hpp"
#include "vtm/core/config_check.hpp"

namespace vtm::bundle {
namespace {

// `count` objects of T constructed in the arena (Arena::construct), as a span; empty when
// the pool cannot hold them.
template <typename T>
Span<T> construct(Arena& arena, std::size_t count) noexcept {
    T* objects = arena.construct<T>(count);
    return objects != nullptr ? Span<T>(objects, count) : Span<T>();
}

Status validateCapacities(const BundleConfig& c) noexcept {
    if (c.max_stations < 2 || c.max_stations > kMaxStationsLimit) {
        return invalidConfig("bundle.max_stations: must be 2..64", c.max_stations);
    }
    if (c.max_points < 1 || c.max_points > kMaxPointsLimit) {
        return invalidConfig("bundle.max_points: must be 1..65536", c.max_points);
    }
    if (c.max_observations < 2 || c.max_observations > kMaxObservationsLimit) {
        return invalidConfig("bundle.max_observations: must be 2..1048576", c.max_observations);
    }
    if (c.datum_station < -1 || c.datum_station >= c.max_stations) {
        return invalidConfig("bundle.datum_station: must be -1 or 0..max_stations - 1", c.datum_station);
    }
    if (!c.use_pointing_prior && c.datum_station < 0) {
        return invalidConfig("bundle.datum_station: needed (>= 0) when use_pointing_prior is false", c.datum_station);
    }
    return Status::ok();
}

Status validateWeights(const BundleConfig& c) noexcept {
    if (!isPositiveFinite(c.sigma_px)) {
        return invalidConfig("bundle.sigma_px: must be > 0 (milli-pixels in detail)", milliUnits(c.sigma_px));
    }
    if (c.loss != RobustLoss::kHuber && c.loss != RobustLoss::kCauchy) {
        return invalidConfig("bundle.loss: must be kHuber or kCauchy", static_cast<std::int64_t>(c.loss));
    }
    if (!isPositiveFinite(c.robust_k)) {
        return invalidConfig("bundle.robust_k: must be > 0 (milli in detail)", milliUnits(c.robust_k));
    }
    if (!isPositiveFinite(c.outlier_sigmas) || c.outlier_sigmas <= c.robust_k) {
        return invalidConfig("bundle.outlier_sigmas: must be > robust_k (milli in detail)", milliUnits(c.outlier_sigmas));
    }
    if (c.max_rejection_rounds < 0 || c.max_rejection_rounds > 10) {
        return invalidConfig("bundle.max_rejection_rounds: must be 0..10", c.max_rejection_rounds);
    }
    return Status::ok();
}

Status validateSolver(const BundleConfig& c) noexcept {
    if (c.max_iterations < 1 || c.max_iterations > 500) {
        return invalidConfig("bundle.max_iterations: must be 1..500", c.max_iterations);
    }
    if (c.max_attempts < 1 || c.max_attempts > 40) {
        return invalidConfig("bundle.max_attempts: must be 1..40", c.max_attempts);
    }
    if (!isPositiveFinite(c.initial_lambda) || c.initial_lambda > 1e6) {
        return invalidConfig("bundle.initial_lambda: must be in (0, 1e6] (milli in detail)", milliUnits(c.initial_lambda));
    }
    if (!isPositiveFinite(c.converge_rotation_rad)) {
        return invalidConfig("bundle.converge_rotation_rad: must be > 0", milliUnits(c.converge_rotation_rad));
    }
    if (!isPositiveFinite(c.converge_translation_m)) {
        return invalidConfig("bundle.converge_translation_m: must be > 0", milliUnits(c.converge_translation_m));
    }
    if (!isPositiveFinite(c.min_parallax_rad) || c.min_parallax_rad >= 1.0) {
        return invalidConfig("bundle.min_parallax_rad: must be in (0, 1) (milli in detail)", milliUnits(c.min_parallax_rad));
    }
    return Status::ok();
}

}  // namespace

Status BundleConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(validateCapacities(*this));
    VTM_RETURN_IF_ERROR(validateWeights(*this));
    return validateSolver(*this);
}

std::size_t BundleAdjuster::workspaceBytes(const BundleConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const auto s = static_cast<std::size_t>(config.max_stations);
    const auto p = static_cast<std::size_t>(config.max_points);
    const auto o = static_cast<std::size_t>(config.max_observations);
    const std::size_t dim = 6U * s;
    // Term by term, in the order init() carves them.
    return Arena::constructBytes<StationWork>(s)             // stations: poses, prior information, U, g
           + Arena::constructBytes<StationSolution>(s)       // stations published
           + Arena::constructBytes<PointWork>(p)             // points: positions, V, g
           + Arena::constructBytes<PointSolution>(p)         // points published
           + Arena::arrayBytes<std::uint32_t>(o)         // observation order by point
           + Arena::arrayBytes<std::uint32_t>(p + 1U)    // first observation of each point
           + Arena::constructBytes<ObservationWork>(o)       // linearisation per observation
           + Arena::constructBytes<ObservationResidual>(o)   // residuals published
           + Arena::constructBytes<StationGroup>(s)          // one point's stations (scratch)
           + Arena::arrayBytes<double>(dim * dim)        // reduced system / its Cholesky factor
           + Arena::arrayBytes<double>(dim * dim)        // its inverse (covariances)
           + Arena::arrayBytes<double>(dim)              // right-hand side
           + Arena::arrayBytes<double>(dim);             // step
}

Status BundleAdjuster::init(const BundleConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    config_ = config;
    const auto s = static_cast<std::size_t>(config.max_stations);
    const auto p = static_cast<std::size_t>(config.max_points);
    const auto o = static_cast<std::size_t>(config.max_observations);
    const std::size_t dim = 6U * s;
    stationWork_ = construct<StationWork>(arena, s);
    stationOut_ = construct<StationSolution>(arena, s);
    pointWork_ = construct<PointWork>(arena, p);
    pointOut_ = construct<PointSolution>(arena, p);
    order_ = arena.allocateArray<std::uint32_t>(o);
    pointFirst_ = arena.allocateArray<std::uint32_t>(p + 1U);
    obsWork_ = construct<ObservationWork>(arena, o);
    obsOut_ = construct<ObservationResidual>(arena, o);
    groups_ = construct<StationGroup>(arena, s);
    reduced_ = arena.allocateArray<double>(dim * dim);
    inverse_ = arena.allocateArray<double>(dim * dim);
    rhs_ = arena.allocateArray<double>(dim);
    step_ = arena.allocateArray<double>(dim);
    if (stationWork_.size() != s || stationOut_.size() != s || pointWork_.size() != p || pointOut_.size() != p ||
        order_.size() != o || pointFirst_.size() != p + 1U || obsWork_.size() != o || obsOut_.size() != o ||
        groups_.size() != s || reduced_.size() != dim * dim || inverse_.size() != dim * dim || rhs_.size() != dim ||
        step_.size() != dim) {
        return Status(StatusCode::kOutOfMemory, "BundleAdjuster::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    initialized_ = true;
    return Status::ok();
}

Span<const StationSolution> BundleAdjuster::stations() const noexcept {
    return Span<const StationSolution>(stationOut_.data(), stationCount_);
}

Span<const PointSolution> BundleAdjuster::points() const noexcept {
    return Span<const PointSolution>(pointOut_.data(), pointCount_);
}

Span<const ObservationResidual> BundleAdjuster::residuals() const noexcept {
    return Span<const ObservationResidual>(obsOut_.data(), observations_.size());
}

}  // namespace vtm::bundle
