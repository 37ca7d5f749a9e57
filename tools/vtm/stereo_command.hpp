// `vtm stereo LEFT RIGHT --disparity MIN:MAX ...`: dense disparity of a rectified pair
// with the flight ML stereo module (vtm::stereo::MlStereo), run on the ground.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <string>

#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::tools {

// The dense-stereo share of the flight memory plan: the arena a flight configuration
// grants MlStereo. The ground tool could take more, but a range that does not fit here
// would not fly, so it is refused unless --budget-mib says otherwise.
constexpr double kStereoFlightBudgetMiB = 8.0;

struct StereoOptions {
    std::string left;
    std::string right;
    std::string disparity_range;  // "MIN:MAX", pixels, inclusive
    int window = stereo::Config{}.window;  // matching window side, pixels
    std::string out_pfm;
    std::string uncertainty_pfm;
    std::string color_png;
    double budget_mib = kStereoFlightBudgetMiB;
};

// Registers the subcommand; the options are filled in when the command line is parsed.
CLI::App* addStereoCommand(CLI::App& app, StereoOptions& options);
// Runs it; returns the exit code (exit_codes.hpp). Errors: one line on stderr.
int runStereo(const StereoOptions& options);

}  // namespace vtm::tools
