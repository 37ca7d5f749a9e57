// The traverse's stop maps and the descent map (traverse_world.hpp), each in its own
// navigation frame, registered and fused by the flight TerrainIntegrator (docs/integrator.md
// "The traverse and the descent, fused"). Flown by `vtm run` (the main job's last part) and
// measured by tests/integrate. Ground side (heap).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "traverse_world.hpp"
#include "vtm/app/terrain_integrator.hpp"

namespace vtm::traverse {

// The descent's navigation error E: its map is the truth moved by E (map = E site):
// 0.1, -0.1, 0.3 deg about x, y, z and (0.35, -0.25, 0.15) m.
[[nodiscard]] const RigidPose& descentError();

// 64 m cube (x -24..40, y -24..40), finest 0.125 m; products 2 m, 0.5 m, 0.25 m (the mean);
// registration on the 0.125 m grid (level 9) with the ICP's gate and normal radius scaled
// to it; min_overlap 0.2 (the descent map is 3-4 times the rover map's area).
[[nodiscard]] app::IntegratorConfig fusionConfig();

enum class Mode { kRegistered, kNavigation, kTruePoses };
[[nodiscard]] const char* modeName(Mode m);

struct Fusion {
    std::vector<std::byte> pool;
    hal::ManualClock clock;
    hal::EventLog events;
    std::unique_ptr<app::TerrainIntegrator> integrator = std::make_unique<app::TerrainIntegrator>();
    std::vector<app::AddResult> results;  // stops 0..n-1, then the descent
    std::vector<double> seconds;          // per addModel
    std::vector<std::string> refusals;    // one per model the integrator refused: "descent: <reason> (detail)"
    std::string error;                    // init or extractProducts failed: no products; "" otherwise
};

// The map frame is stop 0's navigation frame (the odometry starts at the true first pose,
// so it is the site frame). Stop 0 is the reference; stops 1.. are registered in order
// (guess: their odometry pose); then the descent map, in its own navigation frame (cells
// moved by E), is registered to the rover map (guess: the identity, what its navigation
// believed). kNavigation: the same guesses, no registration; kTruePoses: the true poses.
// A refused model leaves the map as it was (docs/integrator.md); the later ones are still
// added, and the products are extracted from what was accepted.
[[nodiscard]] std::unique_ptr<Fusion> fuse(const World& world, Mode mode);

}  // namespace vtm::traverse
