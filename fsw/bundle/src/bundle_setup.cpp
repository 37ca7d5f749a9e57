// adjust()'s preparation: input checks, the stations' priors and fixed parameters, the
// observations grouped by point, the initial triangulation of the tie points.
#include <cmath>

#include "bundle_internal.hpp"
#include "vtm/core/math.hpp"

namespace vtm::bundle {
namespace {

Status badInput(const char* reason, std::size_t value) noexcept {
    return Status(StatusCode::kInvalidArgument, reason, static_cast<std::int64_t>(value));
}

// Information (inverse) of the prior covariance on the parameters not fixed; a zero variance
// fixes its parameter, whose correlations must then be zero. False when the free block is not
// positive definite (a singular covariance that is not a set of fixed parameters).
bool priorInformation(const Mat6& c, const std::uint8_t (&fixed)[6], Mat6& info) noexcept {
    Mat6 a = c;
    for (int i = 0; i < 6; ++i) {
        for (int k = 0; k < 6; ++k) {
            if (fixed[i] != 0U || fixed[k] != 0U) {
                if (c(i, k) != 0.0) {
                    return false;
                }
                a(i, k) = i == k ? 1.0 : 0.0;
            }
        }
    }
    double l[36];
    for (int i = 0; i < 36; ++i) {
        l[i] = a(i / 6, i % 6);
    }
    if (choleskyInPlace(l, 6U, 1e-12) >= 0) {
        return false;
    }
    Mat6 inverse;
    for (int col = 0; col < 6; ++col) {  // A^-1 column by column
        double e[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        e[col] = 1.0;
        choleskySolve(l, 6U, e);
        for (int row = 0; row < 6; ++row) {
            inverse(row, col) = (fixed[row] != 0U || fixed[col] != 0U) ? 0.0 : e[row];
        }
    }
    info = inverse;
    return true;
}

}  // namespace

Status BundleAdjuster::checkInput(Span<const NetworkStation> stations, Span<const TieObservation> observations,
                                  std::uint32_t point_count) const noexcept {
    if (stations.size() > static_cast<std::size_t>(config_.max_stations)) {
        return badInput("bundle.adjust: more stations than max_stations", stations.size());
    }
    if (stations.size() < 2U) {
        return badInput("bundle.adjust: fewer than two stations", stations.size());
    }
    if (point_count > static_cast<std::uint32_t>(config_.max_points)) {
        return badInput("bundle.adjust: more points than max_points", point_count);
    }
    if (observations.size() > static_cast<std::size_t>(config_.max_observations)) {
        return badInput("bundle.adjust: more observations than max_observations", observations.size());
    }
    if (config_.datum_station >= 0 && static_cast<std::size_t>(config_.datum_station) >= stations.size()) {
        return badInput("bundle.adjust: datum_station is not one of the stations", static_cast<std::size_t>(config_.datum_station));
    }
    for (std::size_t i = 0; i < stations.size(); ++i) {
        const Status s = validateNetworkStation(stations[i]);
        if (!s.isOk()) {
            return Status(s.code(), s.reason(), static_cast<std::int64_t>(i));
        }
    }
    for (std::size_t i = 0; i < observations.size(); ++i) {
        const TieObservation& o = observations[i];
        if (o.image.station >= stations.size() || (o.image.eye != Eye::kLeft && o.image.eye != Eye::kRight)) {
            return badInput("bundle.adjust: an observation names a station (or eye) out of range", i);
        }
        if (o.point >= point_count) {
            return badInput("bundle.adjust: an observation names a point out of range", i);
        }
        if (!math::isFinite(o.pixel_px.x()) || !math::isFinite(o.pixel_px.y())) {
            return badInput("bundle.adjust: an observation's pixel is not finite", i);
        }
    }
    return Status::ok();
}

Status BundleAdjuster::setUpStations(Span<const NetworkStation> stations, BundleResult& result) noexcept {
    result.fixed_parameters = 0;
    for (std::size_t s = 0; s < stations.size(); ++s) {
        StationWork& w = stationWork_[s];
        w = StationWork{};
        w.R0 = stations[s].site_from_a.R;
        w.t0_m = stations[s].site_from_a.t_m;
        w.R = w.R0;
        w.t_m = w.t0_m;
        const bool datum = static_cast<std::int32_t>(s) == config_.datum_station;
        for (int k = 0; k < 6; ++k) {
            const bool zeroVariance = config_.use_pointing_prior && stations[s].prior_covariance(k, k) == 0.0;
            w.fixed[k] = (datum || zeroVariance) ? 1U : 0U;
            result.fixed_parameters += w.fixed[k];
        }
        if (config_.use_pointing_prior && !datum && !priorInformation(stations[s].prior_covariance, w.fixed, w.prior_info)) {
            return badInput("bundle.adjust: a station's prior covariance is singular on its free parameters "
                            "(or a zero variance has a non-zero correlation)", s);
        }
    }
    return Status::ok();
}

// Counting sorts (stable): by eye, by station, then by point, so that each point's
// observations are contiguous and ordered by station and eye.
void BundleAdjuster::sortObservations(Span<const TieObservation> observations, std::uint32_t point_count) noexcept {
    const std::size_t n = observations.size();
    // pointFirst_ as counters, then prefix sums.
    for (std::size_t p = 0; p <= point_count; ++p) {
        pointFirst_[p] = 0U;
    }
    for (std::size_t i = 0; i < n; ++i) {
        ++pointFirst_[observations[i].point + 1U];
    }
    for (std::size_t p = 0; p < point_count; ++p) {
        pointFirst_[p + 1U] += pointFirst_[p];
    }
    // Scan the observations in (station, eye) order and place each after its point's
    // earlier ones: the result is sorted by (point, station, eye, input index).
    for (std::size_t p = 0; p < point_count; ++p) {
        pointWork_[p] = PointWork{};
    }
    std::size_t placed = 0U;
    for (std::size_t s = 0; s < stationCount_; ++s) {
        for (int eye = 0; eye < 2; ++eye) {
            for (std::size_t i = 0; i < n; ++i) {
                const TieObservation& o = observations[i];
                if (o.image.station != s || static_cast<int>(o.image.eye) != eye) {
                    continue;
                }
                // pointFirst_[point] counts up as its slots fill; restored below.
                order_[pointFirst_[o.point]++] = static_cast<std::uint32_t>(i);
                ++placed;
            }
        }
    }
    VTM_ASSERT(placed == n);
    for (std::size_t p = point_count; p > 0U; --p) {
        pointFirst_[p] = pointFirst_[p - 1U];
    }
    pointFirst_[0] = 0U;
    for (std::size_t k = 0; k < n; ++k) {
        const TieObservation& o = observations[order_[k]];
        ObservationWork& w = obsWork_[k];
        w = ObservationWork{};
        w.input = order_[k];
        w.station = o.image.station;
        w.eye = o.image.eye;
    }
}

// Linear least squares over all rays of a point: sum (I - d d^T) X = sum (I - d d^T) o.
void BundleAdjuster::triangulatePoints(BundleResult& result) noexcept {
    for (std::size_t p = 0; p < pointCount_; ++p) {
        PointWork& pw = pointWork_[p];
        const std::size_t first = pointFirst_[p];
        const std::size_t last = pointFirst_[p + 1U];
        if (last - first < 2U) {
            pw.state = last == first ? PointState::kUnused : PointState::kSingleSighting;
            continue;
        }
        Mat3 a = Mat3::Zero();
        Vec3 b = Vec3::Zero();
        Vec3 firstDirection = Vec3::Zero();
        double maxSin = 0.0;
        bool rays = true;
        for (std::size_t k = first; k < last && rays; ++k) {
            const ObservationWork& w = obsWork_[k];
            const NetworkStation& st = input_[w.station];
            CameraRay ray;
            rays = backProjectPixel(modelOfEye(st, w.eye), observations_[w.input].pixel_px, ray).isOk();
            const RigidPose pose = siteFromEye(st, w.eye);
            const Vec3 d = pose.R * ray.direction;
            const Vec3 o = pose.R * ray.origin_m + pose.t_m;
            const Mat3 m = Mat3::Identity() - d * d.transpose();
            a += m;
            b += m * o;
            if (k == first) {
                firstDirection = d;
            }
            maxSin = std::fmax(maxSin, math::sqrt(firstDirection.cross(d).squaredNorm()));
        }
        // The angle against the first ray: at least half the largest angle between any two.
        if (!rays || !(maxSin > config_.min_parallax_rad) || !(std::fabs(a.determinant()) > 1e-12)) {
            pw.state = PointState::kNotTriangulated;
            continue;
        }
        pw.X_m = a.inverse() * b;
        pw.X_initial_m = pw.X_m;
        pw.state = PointState::kAdjusted;
        for (std::size_t k = first; k < last; ++k) {
            Vec2 predicted;
            if (!projectObservation(k, false, predicted, nullptr)) {
                pw.state = PointState::kBehindCamera;
                break;
            }
        }
    }
    for (std::size_t p = 0; p < pointCount_; ++p) {
        const PointState s = pointWork_[p].state;
        result.single_sighting += s == PointState::kSingleSighting ? 1 : 0;
        result.not_triangulated += s == PointState::kNotTriangulated ? 1 : 0;
        result.behind_camera += s == PointState::kBehindCamera ? 1 : 0;
        if (s != PointState::kAdjusted) {
            for (std::size_t k = pointFirst_[p]; k < pointFirst_[p + 1U]; ++k) {
                obsWork_[k].state = ObservationState::kPointExcluded;
            }
        }
    }
}

}  // namespace vtm::bundle
