// `vtm refine` and `vtm rectify`: the wide-baseline front end (fsw/features, fsw/motion,
// fsw/rectify) run on the ground on user files (docs/wide-baseline-cli.md).
//   vtm refine  IMG1 IMG2 --camera CAM --pose1 P1 --pose2 P2 --out POSES.txt [--report R.md]
//   vtm rectify IMG1 IMG2 --camera CAM --pose1 P1 --pose2 P2 --out-dir DIR
// Poses are camera-reference poses in the site frame ("FILE" or "FILE:INDEX" of a
// vtm-camera-poses 1 file, docs/cli-poses.md); `vtm refine` writes one that `vtm rectify`
// reads, so the two chain: refine, then rectify with the refined poses, then vtm stereo.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vtm::tools {

struct WideBaselineOptions {
    std::string image1;
    std::string image2;
    std::string camera;   // model of camera 1 (and 2 unless camera2 is given)
    std::string camera2;
    std::string pose1;
    std::string pose2;
    std::string range = "1:1000";  // MIN:MAX metres along camera 1's rays (refine: search; rectify: d range)
    double margin_px = 60.0;       // refine: odometry uncertainty around the predicted segment
    double mast_height_m = 1.9;    // refine: camera 1 above the ground, for the visibility mask (0: none)
    // refine: the certainty gate, degrees (refine::Config::max_rotation_sigma_deg); < 0:
    // the scene's default (general scene 0.25, ground scene off), 0: off.
    double max_rotation_sigma_deg = -1.0;
    std::string out;               // refine: refined poses (vtm-camera-poses 1)
    std::string matches;           // refine: optional match list
    std::string report;            // refine: optional Markdown report (also printed)
    std::string out_dir;           // rectify: output folder
};

CLI::App* addRefineCommand(CLI::App& app, WideBaselineOptions& options);
CLI::App* addRectifyCommand(CLI::App& app, WideBaselineOptions& options);
// Run them; return the exit code (exit_codes.hpp). Errors: one line on stderr.
int runRefine(const WideBaselineOptions& options);
int runRectify(const WideBaselineOptions& options);

}  // namespace vtm::tools
