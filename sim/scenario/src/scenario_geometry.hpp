// Geometry shared by the scenario kinds (private to sim/scenario): the seeded random
// streams, the camera mount rotation and the vehicle pose record. Defined in
// scenario_frames.cpp; the panorama (scenario_panorama.cpp) builds on the same ones.
#pragma once

#include <cstdint>

#include "sim/scenario.hpp"

namespace vtm::sim::detail {

// Seeds of the scenario's random streams (one generator per purpose).
constexpr std::uint64_t kOdometryStream = 0x6F646F6D65747279ULL;  // "odometry"
constexpr std::uint64_t kSensorStream = 0x73656E736F727631ULL;
constexpr std::uint64_t kAttitudeStream = 0x6174746974756465ULL;
constexpr std::uint64_t kPointingStream = 0x706F696E74696E67ULL;  // "pointing"

// The generator seed of one stream of a scenario seed.
[[nodiscard]] std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t stream) noexcept;

// The camera's reference frame in the vehicle frame (docs: pan, then tilt, then roll):
// R_vehicle_from_ref = Rz(pan) Ry(tilt) base Rz(roll).
[[nodiscard]] Mat3 mountRotation(const CameraMount& mount) noexcept;

[[nodiscard]] std::uint64_t toNanoseconds(double t_s) noexcept;

// A VehiclePose (zero covariance) of a vehicle at `position_site_m`, turned by
// `R_site_from_vehicle`, at time `time_s`.
[[nodiscard]] VehiclePose vehiclePose(const Vec3& position_site_m, const Mat3& R_site_from_vehicle,
                                      double time_s) noexcept;

}  // namespace vtm::sim::detail
