// `vtm integrate INPUT... --out-dir DIR [--cells C1,C2,...] [--reducer highest|mean]
// [--site LAT:LON] [--no-register]`: terrain models (PLY point clouds, PFM elevation maps)
// registered to the first one and fused by the flight TerrainIntegrator (fsw/app,
// docs/integrator.md); height maps as GeoTIFF, a mesh of the finest as PLY, the registered
// poses and a one-line-per-model report (docs/tools.md "vtm integrate"). Host only (GDAL).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace vtm::tools {

struct IntegrateOptions {
    std::vector<std::string> inputs;  // "PATH[,pose=SPEC][,geo=FILE][,footprint=M][,source=N]"; the first is the reference
    std::string out_dir;
    std::string cells = "0.25,1,4";   // product cells, metres: the finest times powers of two
    std::string reducer = "highest";  // highest (the paper's largest z) or mean
    std::string site = "0:0";         // site origin, planetocentric latitude:east longitude, degrees
    bool no_register = false;         // insert every model with its pose (for comparison)
};

CLI::App* addIntegrateCommand(CLI::App& app, IntegrateOptions& options);
// Returns the exit code (exit_codes.hpp): 0 fused, 1 an input error or a refused model
// (named), 2 a malformed option.
int runIntegrate(const IntegrateOptions& options);

}  // namespace vtm::tools
