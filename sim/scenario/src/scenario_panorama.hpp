// The panorama kind inside sim/scenario (private): its frames for buildScenarioFrames and
// the coverage check of validateScenario. Public API: sim/panorama.hpp.
#pragma once

#include "sim/scenario.hpp"

namespace vtm::sim::detail {

// Frames 2k (left eye) and 2k + 1 (right eye) of every station k, at the true poses;
// true_pose = the rover, odometry_pose = its attitude telemetry with covariance.
[[nodiscard]] Status panoramaFrames(const Scenario& scenario, const Terrain& terrain, ScenarioFrames& out) noexcept;

// kInvalidConfig when neighbouring exposures would not overlap (panorama kinds only).
[[nodiscard]] Status validatePanoramaCoverage(const Scenario& scenario) noexcept;

}  // namespace vtm::sim::detail
