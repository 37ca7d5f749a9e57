// Issue 25 item 4: the simulated traverse (8 stops) and the descent over the same terrain,
// each map in its own navigation frame, registered and fused by TerrainIntegrator, against
// the truth (the simulator's poses and sim::Terrain::elevationAt) and against OpenCV's
// surface-matching ICP on the same clouds and guesses. Host only, label "accuracy";
// VTM_EVAL_FULL=1 for the long form, VTM_TRAVERSE_OUT=<dir> for pictures.
// docs/integrator.md "The traverse and the descent, fused".
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "fusion_measures.hpp"
#include "fusion_peer.hpp"
#include "traverse_fusion.hpp"

namespace vtm::traverse {
namespace {

const World& world() {
    static const std::unique_ptr<World> w = [] {
        Sizes s;
        if (std::getenv("VTM_EVAL_FULL") != nullptr) {
            s = Sizes{768, 768, 10};
        }
        std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/traverse.scn", std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        return buildWorld(text.str(), s);
    }();
    return *w;
}

std::unique_ptr<Fusion> fused(Mode mode) {
    std::unique_ptr<Fusion> f = fuse(world(), mode);
    EXPECT_TRUE(f->error.empty()) << modeName(mode) << ": " << f->error;
    for (const std::string& r : f->refusals) ADD_FAILURE() << modeName(mode) << ": " << r;
    return f;
}

TEST(TraverseFusionEvaluation, StopsAndDescentRegisteredAndFusedAgainstTheTruth) {
    const World& w = world();
    ASSERT_TRUE(w.error.empty()) << w.error;
    ASSERT_EQ(w.stops.size(), 8U);
    std::printf("world: %s form; stereo %d px, descent %d px, terrain samples 2^%d; built in %.1f s, "
                "stereo maps %.1f s, descent map %.1f s\n",
                std::getenv("VTM_EVAL_FULL") != nullptr ? "long (VTM_EVAL_FULL)" : "CI", w.sizes.stereo_px,
                w.sizes.descent_px, w.sizes.samples_log2, w.build_s, w.stereo_s, w.descent_s);
    std::printf("descent map: %zu cells of %.2f m, camera 1 %.1f m above the ground, RMS %.3f m against the terrain\n",
                w.descent_map.points.size(), w.descent_map.cell_m, w.descent_map.camera1_height_m,
                w.descent_map.rms_vs_truth_m);
    for (std::size_t k = 0; k < w.stops.size(); ++k) {
        std::printf("stop %zu: %lld valid disparities, %zu points, median |elevation - terrain| at the true pose %.1f mm\n", k,
                    static_cast<long long>(w.stops[k].valid_disparities), w.stops[k].points.size(),
                    1000.0 * w.stops[k].median_abs_vs_truth_m);
    }
    const auto reg = fused(Mode::kRegistered);
    const auto nav = fused(Mode::kNavigation);
    const auto tru = fused(Mode::kTruePoses);

    // Per model: the registered pose against the truth (site_from_vehicle; the descent's
    // E^-1), the translation at the model's centroid.
    const Truth truth{&w.traverse.terrain, descentError(), &w.stops, &w.descent_map};
    std::printf("\n%s", stopTable(truth, reg->results, nav->results, reg->seconds).c_str());
    const std::vector<PoseError> reg_errors = poseErrors(truth, reg->results);
    const std::vector<PoseError> nav_errors = poseErrors(truth, nav->results);
    for (std::size_t k = 1; k < w.stops.size(); ++k) {  // stop 0 is the reference
        EXPECT_TRUE(reg->results[k].registered) << "stop " << k;
        // The targets (0.05 deg, 1 % of the step) are MISSED (docs/integrator.md): the
        // assertions hold what is achieved: registration better than the navigation, and
        // within 1 deg and 10 % of the step.
        EXPECT_LT(reg_errors[k].rotation_deg, nav_errors[k].rotation_deg) << "stop " << k;
        EXPECT_LT(reg_errors[k].translation_m, nav_errors[k].translation_m) << "stop " << k;
        EXPECT_LE(reg_errors[k].rotation_deg, 1.0) << "stop " << k;
        EXPECT_LE(reg_errors[k].translation_percent, 10.0) << "stop " << k;
    }
    const TargetCount met = countTargets(truth, reg->results);
    std::printf("targets: rotation <= %.2f deg met by %d of 7 registered stops, translation <= %.0f %% of the step by "
                "%d of 7\n", kRotationTarget_deg, met.rotation_met, kTranslationTarget_percent, met.translation_met);
    // The descent map (overlap with the rover map about 0.2): registered, and its position
    // (at its centroid) better than its navigation's; its rotation is not (a miss).
    const std::size_t d = w.stops.size();
    EXPECT_TRUE(reg->results[d].registered);
    EXPECT_LT(reg_errors[d].translation_m, nav_errors[d].translation_m);

    // Height maps against the terrain by distance band and source; the seam.
    const std::vector<const app::TerrainIntegrator*> runs = {reg->integrator.get(), nav->integrator.get(),
                                                             tru->integrator.get()};
    const std::vector<const char*> names = {modeName(Mode::kRegistered), modeName(Mode::kNavigation),
                                            modeName(Mode::kTruePoses)};
    std::vector<HeightReport> reports;
    for (const auto* run : runs) reports.push_back(heightReport(truth, *run->products()));
    std::printf("\n%s", heightTables(names, reports).c_str());
    for (std::size_t b = 0; b < kBands; ++b) {
        if (reports[0].band[b].bins == 0 || reports[1].band[b].bins == 0) continue;
        EXPECT_LT(reports[0].band[b].rms_m, reports[1].band[b].rms_m) << "band " << b << ": registered not better";
    }
    EXPECT_LT(reports[0].rover.rms_m, reports[1].rover.rms_m);
    // No seam: the height step between rover bins and their descent-only neighbours is the
    // terrain's step within the descent map's own error (its RMS against the terrain).
    EXPECT_GT(reports[0].seam.pairs, 0);
    EXPECT_LT(std::fabs(reports[0].seam.mean_m), w.descent_map.rms_vs_truth_m);
    EXPECT_LT(reports[0].seam.rms_m, 2.0 * w.descent_map.rms_vs_truth_m);

    comparePeer(truth, fusionConfig().icp, reg->results);  // the integrator's ICP settings

    if (const char* dir = std::getenv("VTM_TRAVERSE_OUT")) {
        const std::string e = writePictures(truth, *reg->integrator->products(), dir, 3);
        std::printf("pictures: %s\n", e.empty() ? "traverse_fused_0.25m.png, traverse_fused_error_0.25m.png" : e.c_str());
    }
}

}  // namespace
}  // namespace vtm::traverse
