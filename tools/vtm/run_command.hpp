// `vtm run [SCENARIO] [--out DIR] [--size N] [--link | --target T]`: the main job. Flies a
// simulated mission: the scenario's world and frames (sim/), the simulated drivers
// (hal/sim in process, or a separate vtm-sim over hal/link with --link) and the flight
// executives (fsw/app), then writes the products and a report (Markdown and HTML with
// the pictures) whose accuracy figures come from this run against the simulator's truth.
// With no SCENARIO the built-in rover pair and then the built-in descent are flown
// (sim/scenarios/*.scn, compiled in). --target T hands the run to the vtm cross-compiled
// for T under qemu (run_target.hpp). docs/run.md.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vtm::tools {

struct RunOptions {
    std::string scenario;         // a .scn file; empty: the built-in descent
    std::string out_dir = "vtm-run";
    int size_px = 0;              // > 0: override the camera's width and height (quick runs)
    bool link = false;            // frames and poses from a separate vtm-sim serve (hal/link)
    std::string sim_executable;   // vtm-sim for --link; empty: next to vtm
    std::string target;           // --target: fly with the vtm cross-compiled for it, under qemu
    std::string flight_executable;  // that vtm; empty: build/<target>/tools/vtm/vtm
    std::string expect_target;    // set by --target for the cross vtm: refuse to run if built for another
};

CLI::App* addRunCommand(CLI::App& app, RunOptions& options);
// Exit code (exit_codes.hpp): 0 when every request was mapped, 1 when a request failed
// (its stage and reason on stderr and in the report) or an input was bad.
int runMission(const RunOptions& options);

}  // namespace vtm::tools
