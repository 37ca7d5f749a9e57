// vtm: the VTM command line (ground side).
//   vtm            version, build configuration and the static memory budget
//   vtm version    version only
//   vtm budget     the static memory budget of the flight build (--timing: the timing budget)
//   vtm stereo     dense disparity of a rectified pair (stereo_command.hpp)
//   vtm refine     refined relative motion of a wide-baseline pair (wide_baseline_command.hpp)
//   vtm rectify    rectified pair from two images and their poses (wide_baseline_command.hpp)
//   vtm descent    elevation map from two descent images (descent_command.hpp)
//   vtm register   similarity between two images of different sensors (register_command.hpp)
//   vtm integrate  terrain models registered and fused into height maps (integrate_command.hpp; host only)
//   vtm panorama   a mast panorama from files: kriged elevation, orthophoto (panorama_command.hpp; host only)
//   vtm eval       accuracy of a disparity map against ground truth (eval_command.hpp)
//   vtm run        fly a simulated mission in process: products and report (run_command.hpp)
// docs/tools.md describes the commands, the file formats and the exit codes.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "build_info.hpp"
#include "eval_command.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "memory_budget.hpp"
#include "stereo_command.hpp"
#include "wide_baseline_command.hpp"
#include "descent_command.hpp"
#include "register_command.hpp"
#if VTM_WITH_INTEGRATE
#include "integrate_command.hpp"
#endif
#if VTM_WITH_PANORAMA
#include "panorama_command.hpp"
#endif
#include "run_command.hpp"

namespace {

void printVersion() { std::printf("vtm %s (Visual Terrain Mapper)\n", vtm::tools::kVersion); }

void printBuild() {
    using namespace vtm::tools;
    std::printf("\nBuild configuration\n");
    std::printf("  target        %s\n", kTarget);
    std::printf("  build type    %s\n", kBuildType);
    std::printf("  compiler      %s\n", kCompiler);
    std::printf("  C++ flags     %s\n", kCxxFlags);
    std::printf("  flight policy %s\n", kFlightFlags);
    std::printf("  sanitizers    %s\n", kSanitizers[0] != '\0' ? kSanitizers : "none");
}

void printGroup(vtm::tools::BudgetGroup group, const char* title) {
    std::size_t n = 0;
    const vtm::tools::BudgetEntry* e = vtm::tools::memoryBudget(&n);
    std::printf("\n%s\n", title);
    std::printf("  %-60s %-14s %12s\n", "object", "library", "bytes");
    for (std::size_t i = 0; i < n; ++i) {
        if (e[i].group == group) {
            std::printf("  %-60s %-14s %12zu\n", e[i].name, e[i].owner, e[i].bytes);
        }
    }
    std::printf("  %-60s %-14s %12zu\n", "total", "", vtm::tools::memoryBudgetTotal(group));
}

void printBudget() {
    printGroup(vtm::tools::BudgetGroup::kFlight, "Static memory budget: default flight configuration");
    printGroup(vtm::tools::BudgetGroup::kPlaybackDriver,
               "Static memory of the file-playback driver (desk and HIL only, hal/file)");
    std::printf("\n  Per-library .text/.rodata/.data/.bss and worst-case stack per target:\n"
                "  tools/budget/vtm_budget.py BUILD_DIR... (docs/budgets.md)\n"
                "  Per-stage time and instructions per target ISA: vtm budget --timing [FILE]\n");
}

// The timing budget that tools/budget/timing_budget.sh measured last (its Markdown
// report), printed as it is: the numbers come from that run, which the file names.
int printTiming(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr,
                     "vtm budget: %s: cannot open; measure it first with tools/budget/timing_budget.sh "
                     "(from the repository root; docs/budgets.md \"Timing\")\n",
                     path.c_str());
        return vtm::tools::kExitInputError;
    }
    std::printf("Timing budget: default flight configuration, as measured by tools/budget/timing_budget.sh (%s)\n\n",
                path.c_str());
    std::cout << in.rdbuf();
    return vtm::tools::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vtm: Visual Terrain Mapper command line"};
    app.require_subcommand(0, 1);
    CLI::App* version = app.add_subcommand("version", "print the version");
    CLI::App* budget = app.add_subcommand("budget", "print the static memory budget of the flight build");
    std::string timing_path;
    budget->add_option("--timing", timing_path,
                       "print the timing budget measured by tools/budget/timing_budget.sh instead")
        ->expected(0, 1)
        ->default_str("build/timing/timing-budget.md");
    vtm::tools::StereoOptions stereo_options;
    CLI::App* stereo = vtm::tools::addStereoCommand(app, stereo_options);
    vtm::tools::WideBaselineOptions refine_options;
    CLI::App* refine = vtm::tools::addRefineCommand(app, refine_options);
    vtm::tools::WideBaselineOptions rectify_options;
    CLI::App* rectify = vtm::tools::addRectifyCommand(app, rectify_options);
    vtm::tools::DescentOptions descent_options;
    CLI::App* descent = vtm::tools::addDescentCommand(app, descent_options);
    vtm::tools::RegisterOptions register_options;
    CLI::App* registration = vtm::tools::addRegisterCommand(app, register_options);
#if VTM_WITH_INTEGRATE
    vtm::tools::IntegrateOptions integrate_options;
    CLI::App* integrate = vtm::tools::addIntegrateCommand(app, integrate_options);
#endif
#if VTM_WITH_PANORAMA
    vtm::tools::PanoramaOptions panorama_options;
    CLI::App* panorama = vtm::tools::addPanoramaCommand(app, panorama_options);
#endif
    vtm::tools::EvalOptions eval_options;
    CLI::App* eval = vtm::tools::addEvalCommand(app, eval_options);
    vtm::tools::RunOptions run_options;
    CLI::App* run = vtm::tools::addRunCommand(app, run_options);
    // Usage errors in one line, like every other vtm error.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("vtm: ") + e.what() + " (--help for usage)\n";
    });
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help is a "parse error" with exit code 0; every real one is a usage error.
        return (app.exit(e) == 0) ? vtm::tools::kExitOk : vtm::tools::kExitUsageError;
    }
    if (version->parsed()) {
        printVersion();
        return 0;
    }
    if (budget->parsed()) {
        if (budget->count("--timing") > 0U) {
            return printTiming(timing_path.empty() ? "build/timing/timing-budget.md" : timing_path);
        }
        printBudget();
        return 0;
    }
    if (stereo->parsed()) {
        return vtm::tools::runStereo(stereo_options);
    }
    if (refine->parsed()) {
        return vtm::tools::runRefine(refine_options);
    }
    if (rectify->parsed()) {
        return vtm::tools::runRectify(rectify_options);
    }
    if (registration->parsed()) {
        return vtm::tools::runRegister(register_options);
    }
#if VTM_WITH_INTEGRATE
    if (integrate->parsed()) {
        return vtm::tools::runIntegrate(integrate_options);
    }
#endif
#if VTM_WITH_PANORAMA
    if (panorama->parsed()) {
        return vtm::tools::runPanorama(panorama_options);
    }
#endif
    if (descent->parsed()) {
        return vtm::tools::runDescent(descent_options);
    }
    if (eval->parsed()) {
        return vtm::tools::runEval(eval_options);
    }
    if (run->parsed()) {
        return vtm::tools::runMission(run_options);
    }
    printVersion();
    printBuild();
    printBudget();
    return 0;
}
