// The traverse part of `vtm run` (run_command.cpp has the command): a traverse scenario
// (sim kind `traverse`) and a descent over its terrain, each map in its own navigation
// frame, registered and fused by app::TerrainIntegrator into height maps at three
// resolutions (traverse_fusion.hpp); the products on disk and the report's section, every
// figure measured against the simulator's truth.
#pragma once

#include <cstdint>
#include <string>

namespace vtm::tools {

// Builds the world from the traverse scenario's text (stereo and nadir frames of side_px,
// 64..2048), fuses it registered and, for comparison, by the navigation alone, writes
// traverse_* products into out_dir and returns the report's Markdown section in `section`.
// Returns "" or the one-line error (the world, a file that cannot be written). `models`:
// the models added (the stops and the descent map); `refused`: those the integrator
// refused, which the section names with the reason (not an error here: the products hold
// the others).
std::string flyTraverse(const std::string& text, std::int32_t side_px, const std::string& out_dir, std::string& section,
                        int& models, int& refused);

}  // namespace vtm::tools
