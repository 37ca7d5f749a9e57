#include "run_traverse.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "fusion_measures.hpp"
#include "traverse_fusion.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/core/rotation.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {
namespace {

using traverse::Mode;

// "2m", "0.5m", "0.25m": the product's cell in a file name.
std::string cellName(double cell_m) {
    char b[32];
    std::snprintf(b, sizeof b, "%gm", cell_m);
    return b;
}

// The enlargement that shows a map's data (cropToFinite) at about 768 px.
std::int32_t displayFactor(const ground::FloatImage& cropped) {
    return std::max<std::int32_t>(1, 768 / std::max<std::int32_t>(1, std::max(cropped.width, cropped.height)));
}

// Each product level: its elevations (PFM, NaN = no data) and a shaded relief (PNG, north
// up, about 768 px; the finest with its error picture, writePictures).
std::string writeLevels(const traverse::Truth& truth, const octree::HeightProducts& products, const std::string& out_dir,
                        std::string& files) {
    for (std::int32_t p = 0; p < products.count(); ++p) {
        const terrain::HeightMap& map = products.map(p);
        const std::string base = out_dir + "/traverse_fused_" + cellName(map.grid().cell_m);
        const ground::FloatImage elevation = ground::elevationImage(map);
        const ground::Outcome a = ground::writePfm(base + ".pfm", elevation);
        if (!a.ok) return a.error;
        files += (files.empty() ? "`" : ", `") + base.substr(out_dir.size() + 1) + ".pfm`";
        const ground::FloatImage cropped = ground::cropToFinite(elevation);
        if (p == products.count() - 1) {
            const std::string e = traverse::writePictures(truth, products, out_dir, displayFactor(cropped));
            if (!e.empty()) return e;
            continue;
        }
        const ground::Outcome b = ground::writePng(
            base + ".png", traverse::enlarged(ground::shadedRelief(cropped, map.grid().cell_m), displayFactor(cropped)));
        if (!b.ok) return b.error;
    }
    return "";
}

}  // namespace

std::string flyTraverse(const std::string& text, std::int32_t side_px, const std::string& out_dir, std::string& section,
                        int& models, int& refused) {
    models = 0;
    refused = 0;
    if (side_px < 64 || side_px > 2048) return "--size " + std::to_string(side_px) + ": must be 64..2048";
    const auto t0 = std::chrono::steady_clock::now();
    traverse::Sizes sizes;
    sizes.stereo_px = side_px;
    sizes.descent_px = side_px;
    std::fprintf(stderr, "vtm run: building the traverse's world, its %d px stop maps and the descent map\n", side_px);
    const std::unique_ptr<traverse::World> w = traverse::buildWorld(text, sizes);
    if (!w->error.empty()) return "traverse: " + w->error;
    const std::unique_ptr<traverse::Fusion> reg = traverse::fuse(*w, Mode::kRegistered);
    const std::unique_ptr<traverse::Fusion> nav = traverse::fuse(*w, Mode::kNavigation);
    const traverse::Truth truth{&w->traverse.terrain, traverse::descentError(), &w->stops, &w->descent_map};
    std::ostringstream md;
    char b[2048];
    std::snprintf(b, sizeof b,
                  "## Traverse and descent, fused\n\n"
                  "The flight `TerrainIntegrator` (fsw/app: octree, point-to-plane ICP, height maps at several "
                  "resolutions) on one simulated terrain (%s): %zu rover stops, each mapped by the rover's fixed "
                  "stereo pair (%d x %d, %.2f m; MlStereo, the speckle filter and triangulation, flight modules "
                  "composed here: there is no stop executive) in its vehicle frame and placed by the odometry with "
                  "its drift, and one descent pair (%d x %d, DescentMapper) whose elevation map carries a navigation "
                  "error of %.2f deg and %.2f m. Stop 0 is the reference; each later stop is registered to the map of "
                  "the stops before, then the descent map to the rover map (docs/integrator.md). World and maps built "
                  "in %.1f s (stereo %.1f s, descent %.1f s).\n\n",
                  w->traverse.scenario.name, w->stops.size(), side_px, side_px, traverse::kStereoBaseline_m, side_px,
                  side_px,
                  180.0 / 3.14159265358979323846 * rotationAngleRad(traverse::descentError().R, Mat3::Identity()),
                  traverse::descentError().t_m.norm(), w->build_s + w->stereo_s + w->descent_s, w->stereo_s,
                  w->descent_s);
    md << b;
    models = static_cast<int>(reg->results.size());
    if (!reg->error.empty()) {
        std::fprintf(stderr, "vtm run: the fusion failed: %s\n", reg->error.c_str());
        md << "The fusion failed: " << reg->error << ".\n\n";
        refused = models;
        section = md.str();
        return "";
    }
    refused = static_cast<int>(reg->refusals.size());
    for (const std::string& r : reg->refusals) {
        std::fprintf(stderr, "vtm run: the integrator refused %s\n", r.c_str());
        md << "Refused by the integrator (the map left as it was, the later models still added): " << r << ".\n\n";
    }
    const traverse::TargetCount t = traverse::countTargets(truth, reg->results);
    std::snprintf(b, sizeof b,
                  "Registered %d of %zu later stops. Issue 25's targets: rotation <= %.2f deg met by %d of %zu stops, "
                  "translation <= %.0f %% of the stop-to-stop step by %d of %zu. Per model (the navigation column "
                  "is the same model's guess; errors at the model's centroid):\n\n",
                  t.registered, w->stops.size() - 1U, traverse::kRotationTarget_deg, t.rotation_met,
                  w->stops.size() - 1U, traverse::kTranslationTarget_percent, t.translation_met, w->stops.size() - 1U);
    md << b << traverse::stopTable(truth, reg->results, nav->results, reg->seconds) << "\n";
    const std::vector<traverse::HeightReport> reports = {traverse::heightReport(truth, *reg->integrator->products()),
                                                         traverse::heightReport(truth, *nav->integrator->products())};
    md << traverse::heightTables({traverse::modeName(Mode::kRegistered), traverse::modeName(Mode::kNavigation)},
                                 reports)
       << "\n";
    const octree::OctreeConfig cube = traverse::fusionConfig().octree;
    std::string files;
    const std::string e = writeLevels(truth, *reg->integrator->products(), out_dir, files);
    if (!e.empty()) return e;
    md << "### Products\n\nThe fused height maps (mean elevation per bin, shaded: high red ... low purple, north up, "
          "black: no data) at 2 m, 0.5 m and 0.25 m, and the 0.25 m map's error against the terrain (grey = 0, "
          "+-0.25 m to white / black):\n\n"
       << "![2 m](traverse_fused_2m.png) ![0.5 m](traverse_fused_0.5m.png) ![0.25 m](traverse_fused_0.25m.png) "
          "![error](traverse_fused_error_0.25m.png)\n\n"
       << "Files: " << files << " (metres, NaN = no data; row 0 north, the octree's " << cube.side_m << " m cube from "
       << cube.north_edge_m << " m north, " << cube.west_edge_m << " m east). Total " << secondsSince(t0) << " s.\n\n";
    std::fprintf(stderr, "vtm run: traverse fused in %.1f s: %d of %zu stops registered, 0.25 m map RMS %.3f m\n",
                 secondsSince(t0), t.registered, w->stops.size() - 1U, reports[0].product[2].rms_m);
    section = md.str();
    return "";
}

}  // namespace vtm::tools
