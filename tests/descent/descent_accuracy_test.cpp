// vtm_descent_accuracy_tests (host only, label "accuracy"): the plane sweep on the
// simulated descent (sim/scenarios/descent.scn: 2000 m -> 20 m in 8 frames, 0.5 deg of
// attitude noise, 12-bit), rendered at 512 x 512 (the scenario's 1024 x 1024 with the same
// field of view would take four times as long) for several seeds. For every pair of
// consecutive frames and several plane counts: elevation RMS and 95th percentile error of
// the valid pixels against the renderer's per-pixel truth (point_site_m), as a percentage
// of the altitude. Prints the table docs/descent.md quotes; asserts the target
// (RMS <= 0.5 % of the altitude) at the default plane count and Config's default window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "descent_scene.hpp"
#include "sim/scenario.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent {
namespace {

constexpr std::int32_t kSize = 512;
constexpr std::uint64_t kSeeds[] = {7U, 8U, 9U};
constexpr std::int32_t kPlaneCounts[] = {16, 32, 64};
constexpr std::int32_t kDefaultPlanes = 64;  // kPlaneCounts' last entry
// Config's default score window is 11 x 11. With 7 x 7 the ~280 m pair misses the target (1.1 % RMS): at 512 x 512 its
// image 1 has a 0.45 m pixel footprint, and the renderer, which point-samples and fades
// each texture octave out between two footprints and one, drops the terrain's fine
// texture (longest wavelength 0.5 m) from image 1 while image 2 (0.24 m) shows it at full
// contrast; what the two images share is ~7.5 DN of 7 x 7 texture over 2.4 DN of noise.
// Rendering image 1 at 1024 x 1024 and box-averaging it to 512 (a pixel that integrates its
// area) gives 0.07 % on the same pair; at 1024 x 1024 the miss moves to the ~540 m pair
// (docs/descent.md "Accuracy"). A larger window averages the noise: 11 x 11 meets the
// target at every altitude; the sweep's cost does not depend on the window.
// VTM_DESCENT_WINDOW=N overrides it for exploration (7: the earlier default).

std::string readScenarioText(std::uint64_t seed) {
    std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/descent.scn");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    auto replace = [&](const std::string& from, const std::string& to) {
        const std::size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) {
            text.replace(at, from.size(), to);
        }
    };
    replace("seed 7", "seed " + std::to_string(seed));
    replace("width_px 1024", "width_px " + std::to_string(kSize));
    replace("height_px 1024", "height_px " + std::to_string(kSize));
    return text;
}

struct PairResult {
    double altitude_m = 0.0;
    double rms_percent = 0.0;
    double map_rms_percent = 0.0;  // the height map's cells (see mapRmsPercent)
    double p95_percent = 0.0;
    double valid_fraction = 0.0;
};

// Depth range and FOE threshold a caller derives from its altimeter and relief bound: here
// the true depths of image 1 with a 5 % margin; the mask keeps pixels where 0.25 px of
// registration error is at most 0.5 % of depth: parallax over the range >= 50 f, f the
// range's inverse-depth span relative to the median depth.
Config pairConfig(const std::vector<float>& depth, std::int32_t planes) {
    std::vector<float> d;
    for (const float v : depth) {
        if (std::isfinite(v)) {
            d.push_back(v);
        }
    }
    std::sort(d.begin(), d.end());
    Config c;
    c.max_width = kSize;
    c.max_height = kSize;
    c.planes = planes;
    c.depth_min_m = 0.95 * static_cast<double>(d.front());
    c.depth_max_m = 1.05 * static_cast<double>(d.back());
    const double median = static_cast<double>(d[d.size() / 2]);
    const double f = (1.0 / c.depth_min_m - 1.0 / c.depth_max_m) * median;
    c.min_parallax_px = 50.0 * f;
    c.score = std::getenv("VTM_DESCENT_SAD") != nullptr ? Score::kSad : Score::kNcc;
    const char* window = std::getenv("VTM_DESCENT_WINDOW");
    if (window != nullptr) {
        c.window = std::atoi(window);
    }
    EXPECT_TRUE(c.validate().isOk()) << "VTM_DESCENT_WINDOW: odd, 3..31";
    return c;
}

// The elevation product: the swept depth through a mean terrain::HeightMap (cells of two
// image-1 pixels at camera 1's height, centred under camera 1, as the descent mapper
// does), each cell against the cell of a second map fed the renderer's true points of the
// same pixels (point_site_m); RMS over the cells both hold, % of the altitude.
double mapRmsPercent(const test::RenderedFrame& f1, const CameraModel& camera, const RigidPose& site_from_cam1,
                     const std::vector<float>& depth, double altitude_m) {
    terrain::HeightMapConfig mc;
    mc.reducer = terrain::Reducer::kMean;
    mc.grid.cols = kSize / 2;
    mc.grid.rows = kSize / 2;
    mc.grid.cell_m = 2.0 * -site_from_cam1.t_m.z() / camera.fx_px;
    const double half = 0.5 * static_cast<double>(mc.grid.cols) * mc.grid.cell_m;
    mc.grid.north_edge_m = site_from_cam1.t_m.x() + half;
    mc.grid.west_edge_m = site_from_cam1.t_m.y() - half;
    std::vector<std::byte> pool(2U * terrain::HeightMap::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    terrain::HeightMap swept, truth;
    EXPECT_TRUE(swept.init(mc, arena).isOk());
    EXPECT_TRUE(truth.init(mc, arena).isOk());
    std::vector<float> masked(depth.size(), std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < depth.size(); ++i) {
        if (std::isfinite(depth[i]) && std::isfinite(f1.depth_m[i])) {
            masked[i] = depth[i];
            const Vec3 p(static_cast<double>(f1.point_site_m[3 * i]), static_cast<double>(f1.point_site_m[3 * i + 1]),
                         static_cast<double>(f1.point_site_m[3 * i + 2]));
            EXPECT_TRUE(truth.add(p).isOk());
        }
    }
    EXPECT_TRUE(addDepthToHeightMap(ImageView<const float>(masked.data(), kSize, kSize), camera, site_from_cam1,
                                    swept)
                    .isOk());
    double sum2 = 0.0;
    std::size_t n = 0U;
    for (std::int32_t row = 0; row < mc.grid.rows; ++row) {
        for (std::int32_t col = 0; col < mc.grid.cols; ++col) {
            if (swept.count(col, row) == 0U || truth.count(col, row) == 0U) {
                continue;
            }
            const double e =
                static_cast<double>(swept.elevation(col, row)) - static_cast<double>(truth.elevation(col, row));
            sum2 += e * e;
            ++n;
        }
    }
    EXPECT_GT(n, static_cast<std::size_t>(kSize));
    return n == 0U ? 0.0 : 100.0 * std::sqrt(sum2 / static_cast<double>(n)) / altitude_m;
}

PairResult evaluatePair(const test::RenderedFrame& f1, const test::RenderedFrame& f2, const CameraModel& camera,
                        std::int32_t planes) {
    const Config c = pairConfig(f1.depth_m, planes);
    std::vector<std::byte> pool(PlaneSweep::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    static PlaneSweep sweep;
    EXPECT_TRUE(sweep.init(c, arena).isOk());
    std::vector<float> depth(f1.depth_m.size());
    PairGeometry g;
    g.camera = camera;
    g.site_from_cam1 = f1.pose;
    g.site_from_cam2 = f2.pose;
    SweepStats stats;
    const Status s = sweep.compute(ImageView<const std::uint16_t>(f1.image.data(), kSize, kSize),
                                   ImageView<const std::uint16_t>(f2.image.data(), kSize, kSize), g,
                                   SweepOutput{ImageView<float>(depth.data(), kSize, kSize), {}, {}}, &stats);
    EXPECT_TRUE(s.isOk()) << s.reason();
    if (std::getenv("VTM_DESCENT_VERBOSE") != nullptr) {
        std::printf("pair: z1 %.1f z2 %.1f depth %.1f..%.1f planes %d minpar %.2f scale %.3f sigma %.3f valid %d lowpar %d oov %d range %d notex %d\n",
                    f1.pose.t_m.z(), f2.pose.t_m.z(), c.depth_min_m, c.depth_max_m, c.planes,
                    c.min_parallax_px, stats.scale, stats.prefilter_sigma_px, stats.valid_pixels, stats.reason_counts[3],
                    stats.reason_counts[2], stats.reason_counts[4], stats.reason_counts[5]);
    }
    PairResult r;
    r.altitude_m = -f1.pose.t_m.z();  // above the site datum, refined below
    std::vector<double> err;
    double sum2 = 0.0;
    for (std::int32_t y = 0; y < kSize; ++y) {
        for (std::int32_t x = 0; x < kSize; ++x) {
            const auto i = static_cast<std::size_t>(y * kSize + x);
            if (!std::isfinite(depth[i]) || !std::isfinite(f1.depth_m[i])) {
                continue;
            }
            const Vec3 ray((x - camera.cx_px) / camera.fx_px, (y - camera.cy_px) / camera.fy_px, 1.0);
            const Vec3 p = f1.pose.R * (ray * static_cast<double>(depth[i])) + f1.pose.t_m;
            const double e = -p.z() - (-static_cast<double>(f1.point_site_m[3 * i + 2]));
            err.push_back(std::fabs(e));
            sum2 += e * e;
        }
    }
    // Altitude: camera height above the terrain it sees (median true depth).
    std::vector<float> d = f1.depth_m;
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    r.altitude_m = static_cast<double>(d[d.size() / 2]);
    std::sort(err.begin(), err.end());
    r.valid_fraction = static_cast<double>(err.size()) / static_cast<double>(kSize * kSize);
    if (!err.empty()) {
        r.rms_percent = 100.0 * std::sqrt(sum2 / static_cast<double>(err.size())) / r.altitude_m;
        r.p95_percent = 100.0 * err[static_cast<std::size_t>(0.95 * static_cast<double>(err.size() - 1))] / r.altitude_m;
    }
    r.map_rms_percent = mapRmsPercent(f1, camera, g.site_from_cam1, depth, r.altitude_m);
    return r;
}

TEST(DescentAccuracy, ElevationErrorBySimulatedAltitudeAndPlaneCount) {
    constexpr std::int32_t kPairs = 7;
    constexpr std::int32_t kCounts = sizeof(kPlaneCounts) / sizeof(kPlaneCounts[0]);
    double rms[kPairs][kCounts] = {}, p95[kPairs][kCounts] = {}, valid[kPairs][kCounts] = {}, alt[kPairs] = {};
    double mapRms[kPairs] = {};  // the height map at the default plane count
    double worstDefault = 0.0, worstMap = 0.0;
    for (const std::uint64_t seed : kSeeds) {
        sim::Scenario sc;
        ASSERT_TRUE(sim::parseScenario(readScenarioText(seed), sc).isOk());
        std::vector<std::byte> pool(sim::scenarioTerrainBytes(sc));
        Arena arena(pool.data(), pool.size());
        static sim::Terrain terrain;
        terrain = sim::Terrain();
        ASSERT_TRUE(sim::buildScenarioTerrain(sc, arena, terrain).isOk());
        static sim::ScenarioFrames frames;
        ASSERT_TRUE(sim::buildScenarioFrames(sc, terrain, frames).isOk());
        ASSERT_EQ(frames.count, kPairs + 1);
        std::vector<test::RenderedFrame> rendered;
        for (std::int32_t k = 0; k < frames.count; ++k) {
            const sim::ScenarioFrame& fr = frames.frames[k];
            const sim::FrameRequest req = sim::scenarioFrameRequest(sc, terrain, fr);
            rendered.push_back(test::render(terrain, fr.model, fr.camera_pose, fr.index, req.sensor));
        }
        for (std::int32_t k = 0; k < kPairs; ++k) {
            for (std::int32_t j = 0; j < kCounts; ++j) {
                const PairResult r = evaluatePair(rendered[static_cast<std::size_t>(k)],
                                                  rendered[static_cast<std::size_t>(k + 1)], frames.frames[k].model,
                                                  kPlaneCounts[j]);
                alt[k] += (j == 0) ? r.altitude_m / std::size(kSeeds) : 0.0;
                rms[k][j] += r.rms_percent / std::size(kSeeds);
                p95[k][j] += r.p95_percent / std::size(kSeeds);
                valid[k][j] += 100.0 * r.valid_fraction / std::size(kSeeds);
                if (kPlaneCounts[j] == kDefaultPlanes) {
                    worstDefault = std::max(worstDefault, r.rms_percent);
                    worstMap = std::max(worstMap, r.map_rms_percent);
                    mapRms[k] += r.map_rms_percent / std::size(kSeeds);
                }
            }
        }
    }
    std::printf("| altitude (m) |");
    for (const std::int32_t n : kPlaneCounts) {
        std::printf(" %d planes: RMS %% / p95 %% / valid %% |", n);
    }
    std::printf("\n");
    for (std::int32_t k = 0; k < kPairs; ++k) {
        std::printf("| %.0f |", alt[k]);
        for (std::int32_t j = 0; j < kCounts; ++j) {
            std::printf(" %.3f / %.3f / %.1f |", rms[k][j], p95[k][j], valid[k][j]);
        }
        std::printf("\n");
    }
    std::printf("worst single-pair RMS at %d planes: %.3f %% of altitude\n", kDefaultPlanes, worstDefault);
    std::printf("\n| altitude (m) | height map (mean, 2-pixel cells) RMS %% at %d planes |\n|---|---|\n",
                kDefaultPlanes);
    for (std::int32_t k = 0; k < kPairs; ++k) {
        std::printf("| %.0f | %.3f |\n", alt[k], mapRms[k]);
    }
    std::printf("worst single-pair height-map RMS at %d planes: %.3f %% of altitude\n", kDefaultPlanes, worstMap);
    // The target: RMS <= 0.5 % of the altitude at every altitude (mean over the
    // seeds; 11 x 11 window: 0.41 % at worst, ~280 m); a single seed may not be far above.
    if (std::getenv("VTM_DESCENT_WINDOW") != nullptr || std::getenv("VTM_DESCENT_SAD") != nullptr) {
        return;  // an exploration run, not the configuration the gate is for
    }
    for (std::int32_t k = 0; k < kPairs; ++k) {
        EXPECT_LE(rms[k][kCounts - 1], 0.5) << "altitude " << alt[k] << " m";
        EXPECT_LE(mapRms[k], 0.5) << "height map, altitude " << alt[k] << " m";
    }
    EXPECT_LE(worstDefault, 0.6);
    EXPECT_LE(worstMap, 0.6);
}

}  // namespace
}  // namespace vtm::descent
