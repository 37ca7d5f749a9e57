// vtm-sim: the simulated world of VTM on the ground side.
//   vtm-sim render <scenario> <outdir> [--format png|pgm] [--frames i,j]   (render_command.hpp)
//   vtm-sim serve <scenario> --tcp HOST:PORT | --unix PATH ...            (serve_command.hpp)
// docs/sim-scenarios.md describes render's files; docs/icd-hil-link.md the serve protocol.
#include <CLI/CLI.hpp>
#include <string>

#include "vtm/ground/exit_codes.hpp"
#include "render_command.hpp"
#include "serve_command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"vtm-sim: render and serve the simulated world of VTM"};
    app.require_subcommand(1);
    vtm::simtool::RenderOptions render_options;
    CLI::App* render = vtm::simtool::addRenderCommand(app, render_options);
    // The HIL link server runs from its own subcommand callback during parse().
    vtm::simtool::addServeCommand(app);
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("vtm-sim: ") + e.what() + " (--help for usage)\n";
    });
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return (app.exit(e) == 0) ? vtm::tools::kExitOk : vtm::tools::kExitUsageError;
    }
    if (render->parsed()) {
        return vtm::simtool::runRender(render_options);
    }
    return vtm::tools::kExitOk;
}
