// `vtm descent IMG1 IMG2 --camera CAM --pose1 P1 --pose2 P2 [--planes N] --out ELEV.pfm
// [--color ELEV.png]`: the descent plane sweep (fsw/descent) run on the ground on two
// descent frames, writing a site-frame elevation grid (docs/descent.md "Command line").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "vtm/descent/plane_sweep.hpp"

namespace vtm::tools {

struct DescentOptions {
    std::string image1;       // earlier (higher) frame: 8- or 12-bit PNG/PGM
    std::string image2;       // later (closer) frame
    std::string camera;       // camera model file (an undistorted pinhole)
    std::string pose1;        // FILE or FILE:INDEX of a vtm-camera-poses 1 file
    std::string pose2;
    int planes = 64;
    std::string depth_range;  // "MIN:MAX" metres along camera 1's axis; default from pose1's height
    std::string score = "ncc";
    int window = vtm::descent::Config{}.window;
    double min_parallax_px = -1.0;  // < 0: 50 f (see docs/descent.md)
    double cell_m = 0.0;            // <= 0: the ground size of one image-1 pixel
    std::string out_pfm;            // elevation grid (NaN = NO_DATA), north up
    std::string color_png;
    std::string depth_pfm;          // optional: per-pixel depth of image 1 (NaN = none)
};

CLI::App* addDescentCommand(CLI::App& app, DescentOptions& options);
// Runs it; returns the exit code (exit_codes.hpp). Errors: one line on stderr naming the input.
int runDescent(const DescentOptions& options);

}  // namespace vtm::tools
