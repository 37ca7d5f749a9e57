// `vtm eval DISP.pfm GT --scale S [--mask M]` and `vtm eval DISP.pfm --middlebury SET`:
// accuracy of a disparity map against ground truth (vtm/ground/disparity_evaluation.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <limits>
#include <string>

namespace vtm::tools {

struct EvalOptions {
    std::string disparity_pfm;
    std::string ground_truth;  // empty with --middlebury
    double scale = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
    std::string mask;
    std::string middlebury;    // set name
    std::string data_dir;      // empty: $VTM_DATA

    [[nodiscard]] bool scaleGiven() const { return !std::isnan(scale); }
};

CLI::App* addEvalCommand(CLI::App& app, EvalOptions& options);
int runEval(const EvalOptions& options);

}  // namespace vtm::tools
