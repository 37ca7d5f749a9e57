// The pointing adjustment of a PDS panorama through fsw/bundle (pds_pointing.hpp).
#include "vtm/ground/pds_pointing.hpp"

#include <cmath>
#include <cstddef>
#include <string>

#include "vtm/core/arena.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::ground {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

Vec3 cameraCentreInRover(const PdsImage& frame) {
    const CameraModel& m = frame.camera_model;
    return Vec3(m.c[0], m.c[1], m.c[2]);
}

// The frame as a mono station: its model with C moved to the origin, the pose carrying C.
NetworkStation stationOf(const PdsImage& frame, double prior_sigma_rad, double centre_sigma_m) {
    NetworkStation s;
    s.rig.model_a = frame.camera_model;
    for (double& c : s.rig.model_a.c) c = 0.0;
    s.rig.model_b = s.rig.model_a;  // no right eye: never observed
    s.rig.b_from_a = RigidPose{};
    const RigidPose& p = frame.site_from_rover;
    s.site_from_a.R = p.R;
    s.site_from_a.t_m = p.t_m + p.R * cameraCentreInRover(frame);
    s.prior_covariance = Mat6::Zero();
    const double v = prior_sigma_rad * prior_sigma_rad;
    const double w = centre_sigma_m * centre_sigma_m;
    s.prior_covariance.diagonal() << v, v, v, w, w, w;  // the centre held when w is 0
    return s;
}

std::string checkInput(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                       const PdsPointingConfig& config) {
    if (frames.size() < 2U || frames.size() > static_cast<std::size_t>(bundle::kMaxStationsLimit)) {
        return "pointing adjustment: needs 2..64 frames, got " + std::to_string(frames.size());
    }
    for (const PdsImage& f : frames) {
        if (!f.has_camera_model || !f.has_rover_pose) {
            return f.info.product_id + ": the pointing adjustment needs a camera model and a rover pose";
        }
    }
    std::size_t ties = 0U;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const PdsTiePair& p = pairs[k];
        const auto n = static_cast<std::int32_t>(frames.size());
        if (p.frame_a < 0 || p.frame_a >= n || p.frame_b < 0 || p.frame_b >= n || p.frame_a == p.frame_b) {
            return "pointing adjustment: pair " + std::to_string(k) + " names frames " + std::to_string(p.frame_a) +
                   " and " + std::to_string(p.frame_b) + " (0.." + std::to_string(n - 1) + ", two different)";
        }
        ties += p.ties.size();
    }
    if (ties == 0U) return "pointing adjustment: no ties";
    if (ties > static_cast<std::size_t>(bundle::kMaxPointsLimit)) {
        return "pointing adjustment: " + std::to_string(ties) + " ties, at most 65536";
    }
    if (!(config.prior_sigma_deg > 0.0) || !std::isfinite(config.prior_sigma_deg)) {
        return "pointing adjustment: prior_sigma_deg must be > 0, got " + std::to_string(config.prior_sigma_deg);
    }
    if (!(config.centre_sigma_m >= 0.0) || !std::isfinite(config.centre_sigma_m)) {
        return "pointing adjustment: centre_sigma_m must be >= 0, got " + std::to_string(config.centre_sigma_m);
    }
    return std::string();
}

bundle::BundleConfig bundleConfig(const PdsPointingConfig& config, std::size_t frames, std::size_t ties) {
    bundle::BundleConfig c;
    c.max_stations = static_cast<std::int32_t>(frames);
    c.max_points = static_cast<std::int32_t>(ties);
    c.max_observations = static_cast<std::int32_t>(2U * ties);
    c.sigma_px = config.sigma_px;
    c.loss = config.loss;
    c.robust_k = config.robust_k;
    c.outlier_sigmas = config.outlier_sigmas;
    c.min_parallax_rad = config.min_parallax_rad;
    c.max_iterations = 200;  // per round: far ties' ranges converge slowly (about 50 per round here)
    return c;
}

PdsTieUse useOf(const bundle::PointSolution& point, const bundle::ObservationResidual& a,
                const bundle::ObservationResidual& b) {
    switch (point.state) {
        case bundle::PointState::kAdjusted:
            return a.state == bundle::ObservationState::kInlier && b.state == bundle::ObservationState::kInlier
                       ? PdsTieUse::kUsed
                       : PdsTieUse::kOutlier;
        case bundle::PointState::kBehindCamera: return PdsTieUse::kBehindCamera;
        case bundle::PointState::kTooFewInliers: return PdsTieUse::kOutlier;
        default: return PdsTieUse::kNotTriangulated;
    }
}

}  // namespace

RigidPose pdsTurnedRoverPose(const PdsImage& frame, const Vec3& correction_rad, const Vec3& shift_m) {
    const RigidPose& p = frame.site_from_rover;
    const Vec3 c = cameraCentreInRover(frame);
    RigidPose out;
    out.R = rotationExp(correction_rad) * p.R;
    out.t_m = (p.R * c + p.t_m + shift_m) - out.R * c;
    return out;
}

Result<PdsPointingResult> adjustPdsPointing(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                                            const PdsPointingConfig& config) {
    const std::string bad = checkInput(frames, pairs, config);
    if (!bad.empty()) return Result<PdsPointingResult>::failure(bad);
    std::vector<NetworkStation> stations;
    for (const PdsImage& f : frames) stations.push_back(stationOf(f, config.prior_sigma_deg * kRadPerDeg, config.centre_sigma_m));
    std::vector<TieObservation> obs;
    for (const PdsTiePair& p : pairs) {
        for (const PdsTie& t : p.ties) {
            const auto point = static_cast<std::uint32_t>(obs.size() / 2U);
            obs.push_back(TieObservation{ImageRef{static_cast<std::uint16_t>(p.frame_a), Eye::kLeft}, point, t.pixel_a});
            obs.push_back(TieObservation{ImageRef{static_cast<std::uint16_t>(p.frame_b), Eye::kLeft}, point, t.pixel_b});
        }
    }
    const std::size_t ties = obs.size() / 2U;
    const bundle::BundleConfig bc = bundleConfig(config, frames.size(), ties);
    const Status valid = bc.validate();
    if (!valid.isOk()) return Result<PdsPointingResult>::failure(std::string("pointing adjustment: ") + valid.reason());
    std::vector<std::byte> pool(bundle::BundleAdjuster::workspaceBytes(bc));
    Arena arena(pool.data(), pool.size());
    bundle::BundleAdjuster adjuster;
    const Status init = adjuster.init(bc, arena);
    if (!init.isOk()) return Result<PdsPointingResult>::failure(std::string("pointing adjustment: ") + init.reason());
    PdsPointingResult out;
    const Status s = adjuster.adjust(Span<const NetworkStation>(stations.data(), stations.size()),
                                     Span<const TieObservation>(obs.data(), obs.size()),
                                     static_cast<std::uint32_t>(ties), out.bundle);
    if (!s.isOk()) return Result<PdsPointingResult>::failure(std::string("pointing adjustment: ") + s.reason());
    for (const bundle::StationSolution& st : adjuster.stations()) {
        out.correction_rad.push_back(st.correction.head<3>());
        out.covariance_rad2.push_back(st.covariance.topLeftCorner<3, 3>());
        out.shift_m.push_back(st.correction.tail<3>());
    }
    std::size_t point = 0U;
    for (const PdsTiePair& p : pairs) {
        out.use.emplace_back();
        out.residual_a_px.emplace_back();
        out.residual_b_px.emplace_back();
        out.range_m.emplace_back();
        for (std::size_t k = 0; k < p.ties.size(); ++k, ++point) {
            const bundle::ObservationResidual& ra = adjuster.residuals()[2U * point];
            const bundle::ObservationResidual& rb = adjuster.residuals()[2U * point + 1U];
            out.use.back().push_back(useOf(adjuster.points()[point], ra, rb));
            out.residual_a_px.back().push_back(ra.residual_px);
            out.residual_b_px.back().push_back(rb.residual_px);
            const RigidPose& a = adjuster.stations()[static_cast<std::size_t>(p.frame_a)].site_from_a;
            out.range_m.back().push_back((adjuster.points()[point].position_m - a.t_m).norm());
        }
    }
    return Result<PdsPointingResult>::success(std::move(out));
}

}  // namespace vtm::ground
