// A simulated mast panorama (docs/sim-scenarios.md "Panorama"; paper §3): a Navcam-like
// stereo pair on a pan/tilt head turned through 360 deg of pan in 2 or 3 tiers of tilt.
// Each exposure is one vtm::NetworkStation (vtm/core/image_network.hpp): rig = the
// [camera] model for both eyes, b_from_a = the calibrated baseline along the left eye's
// +x; site_from_a = the left eye's pose. The scenario keeps the TRUE stations and gives
// the APPROXIMATE ones (what the rover's telemetry says) with the 6x6 prior covariance of
// (dtheta, dt) (R_true = rotationExp(dtheta) R_approx, t_true = t_approx + dt) from
// first-order propagation of the seeded pointing error model (PointingErrorModel).
//
// Geometry (vehicle frame x forward, y right, z down; the rover stands level on the
// terrain at motion.start_m, heading motion.heading_deg):
//   head  = camera.mount_position_m: the point where the pan and tilt axes cross;
//           the mast pivots at (head.x, head.y, 0), so the mast height is -head.z.
//   station k = tier * columns + column: pan = column * 360 / columns (from the rover's
//           heading, positive to the right), tilt = tier_tilts_deg[tier];
//           R_vehicle_from_cam = mount rotation (pan, tilt, roll 0) as for the other kinds.
//   left eye = head + R (-b/2, 0, 0), right eye = head + R (+b/2, 0, 0) (camera frame).
// Errors: truth = the commanded angles on a flexed mast, R = R_v Exp(f) M(pan, tilt),
// head = head + (Exp(f) - I)(0, 0, head.z) + d; telemetry = rover attitude
// R_v Exp(rover error), a rigid mast, the encoder angles (commanded + encoder error).
// The rover-attitude and mast errors are drawn once per panorama and so are shared by
// all stations (correlated between stations); each station's prior covariance is the
// marginal of its own (dtheta, dt).
//
// Determinism: vtm::math only, one draw per statement, one stream ("pointing") seeded
// from the scenario seed. No heap; a Panorama is about 60 KiB: declare it static.
#pragma once

#include <cstdint>

#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/status.hpp"

namespace vtm::sim {

// Every random quantity of one panorama (radians, metres).
struct PanoramaErrors {
    // Telemetry roll, pitch, heading error e about the vehicle axes: R_telemetry = R_true Exp(e).
    Vec3 rover_attitude_rad = Vec3::Zero();
    Vec2 mast_tilt_rad = Vec2::Zero();       // true mast axis tilt f = (fx, fy, 0) about the vehicle x and y axes
    Vec3 head_offset_m = Vec3::Zero();       // true head position offset d, vehicle frame
    double pan_error_rad[kMaxPanoramaStations] = {};   // encoder reading - true angle, per station
    double tilt_error_rad[kMaxPanoramaStations] = {};
};

// The rover of a panorama: where it stands and how its telemetry sees it.
struct PanoramaRover {
    Vec3 position_site_m = Vec3::Zero();           // ground contact point (known exactly)
    Mat3 R_site_from_vehicle = Mat3::Identity();   // true attitude (level, the heading)
    Mat3 R_telemetry = Mat3::Identity();           // reported attitude
};

// One exposure.
struct PanoramaStation {
    NetworkStation truth{};      // true left-eye pose; prior_covariance zero
    NetworkStation approx{};     // telemetry pose and the prior covariance of (dtheta, dt)
    std::int32_t tier = 0;       // index into motion.tier_tilts_deg
    std::int32_t column = 0;     // 0 .. columns - 1
    double pan_deg = 0.0;        // commanded, from the rover's heading
    double tilt_deg = 0.0;       // commanded (the tier's elevation)
    double time_s = 0.0;         // start_time_s + k * station_interval_s
};

struct Panorama {
    PanoramaStation stations[kMaxPanoramaStations];
    std::int32_t count = 0;      // tiers * columns
    std::int32_t tiers = 0;
    std::int32_t columns = 0;
    PanoramaRover rover{};
    PanoramaErrors errors{};
};

// Station index of (tier, column).
[[nodiscard]] constexpr std::int32_t panoramaStationIndex(std::int32_t tier, std::int32_t column,
                                                          std::int32_t columns) noexcept {
    return tier * columns + column;
}

// The errors of a panorama scenario, drawn from the "pointing" stream of its seed: the
// rover attitude (roll, pitch, heading), the mast tilt (x, y), the head offset (x, y, z),
// then pan and tilt of each station in station order.
[[nodiscard]] PanoramaErrors drawPanoramaErrors(const Scenario& scenario) noexcept;

// The rover standing on `terrain` at motion.start_m with those errors.
[[nodiscard]] PanoramaRover panoramaRover(const Scenario& scenario, const Terrain& terrain,
                                          const PanoramaErrors& errors) noexcept;

// Station k (0 <= k < tiers * columns) of a valid panorama scenario.
[[nodiscard]] PanoramaStation panoramaStation(const Scenario& scenario, const PanoramaRover& rover,
                                              const PanoramaErrors& errors, std::int32_t k) noexcept;

// Every station. kInvalidConfig (validateScenario's reasons) for an invalid scenario or one
// of another kind; kInvalidArgument for a terrain not built.
[[nodiscard]] Status buildPanorama(const Scenario& scenario, const Terrain& terrain, Panorama& out) noexcept;

// E[e_k e_l^T] of the errors e = (dtheta, dt) of stations k and l of a panorama built from
// `scenario` (first order, like the priors): through the per-panorama errors (rover
// attitude, mast tilt, head offset) that they share; k == l gives the station's prior.
[[nodiscard]] Mat6 panoramaCrossCovariance(const Scenario& scenario, const Panorama& panorama, std::int32_t k,
                                           std::int32_t l) noexcept;

// Angular overlap of neighbouring exposures, degrees, measured on the eye model's rays
// through the middle of opposite image edges: horizontal (same tier, pan neighbours) at the
// image's middle row, per tier; vertical (same column, tier neighbours) along the middle
// column, between tier t and t + 1 (count - 1 entries).
struct PanoramaOverlap {
    double horizontal_deg[kMaxPanoramaTiers] = {};
    double vertical_deg[kMaxPanoramaTiers] = {};
};
[[nodiscard]] Status panoramaOverlap(const Scenario& scenario, PanoramaOverlap& out) noexcept;

// The ground point (site frame) a pixel of one eye sees: a terrain ray cast from the
// eye's projection centre through the pixel. kNoData for sky (no hit within max_range_m),
// kDegenerate when the pixel has no ray.
[[nodiscard]] Status panoramaGroundPoint(const Terrain& terrain, const NetworkStation& station, Eye eye,
                                         const Vec2& pixel_px, Vec3& point_site_m,
                                         double max_range_m = 1.0e5) noexcept;

}  // namespace vtm::sim
