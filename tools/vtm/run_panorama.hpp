// The panorama part of `vtm run` (run_command.cpp has the command): a panorama scenario
// (sim kind `panorama`) flown by app::PanoramaMapper, its products on disk and the
// report's section, every figure measured against the simulator's truth.
#pragma once

#include <string>

#include "vtm/ground/sim_world.hpp"

namespace vtm::tools {

// Renders every station's two eyes, hands them to the executive with the telemetry's
// stations and pointing priors (sim::buildPanorama's approximate stations) and maps once.
// Writes panorama_* products into out_dir and returns the report's Markdown section in
// `section`. Returns "" or the one-line error (rendering, init, a file that cannot be
// written); a request that fails in a stage is not an error here: `mapped` is false and
// the section says which stage and why.
std::string flyPanorama(const ground::SimWorld& world, const std::string& out_dir, std::string& section,
                        bool& mapped);

}  // namespace vtm::tools
