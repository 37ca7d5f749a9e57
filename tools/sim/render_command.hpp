// `vtm-sim render <scenario> <outdir> [--format png|pgm] [--frames i,j,...]`: renders a
// scenario's frames with their ground truth into a directory (docs/sim-scenarios.md
// "Output files"): frames, true depth and range (PFM), the true disparity of the fixed
// stereo pair (PFM), true and odometry pose logs, camera model files, FileCamera frame
// manifests, the camera pose table and a README.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vtm::simtool {

struct RenderOptions {
    std::string scenario;        // scenario text file
    std::string outdir;          // created if missing
    std::string format = "png";  // png | pgm
    std::string frames;          // "" = all, else comma-separated frame indices
};

// Registers the subcommand; the caller runs runRender() when it was parsed.
CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options);

// Exit code: 0 ok, 1 input error (file, scenario field, render failure, output not
// writable), 2 usage error (bad --frames list). Errors: one line on stderr naming the
// file and the field.
int runRender(const RenderOptions& options);

}  // namespace vtm::simtool
