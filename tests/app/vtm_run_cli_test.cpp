// `vtm run` as a user runs it (the README's main-job command on a smaller frame size):
// the built-in descent flown in process, its products and report on disk; each pair's
// depth against the true depth that `vtm-sim render` writes for the same scenario (a
// separate program rendering the same world), and bad inputs as one line naming them.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_world.hpp"

namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

int run(const std::string& command, const std::string& dir, std::string& err) {
    const std::string cmd = command + " >'" + dir + "/out.txt' 2>'" + dir + "/err.txt'";
    const int status = std::system(cmd.c_str());
    err = slurp(dir + "/err.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class VtmRunCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = (fs::temp_directory_path() / ("vtm_run_cli_" + std::to_string(::getpid()))).string();
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string dir_;
};

TEST_F(VtmRunCli, FliesTheBuiltInDescentAndItsDepthMatchesTheRenderedTruth) {
    std::string err;
    const std::string out = dir_ + "/run";
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run descent --size 256 --out '" + out + "'", dir_, err), 0) << err;
    EXPECT_NE(err.find("pair 4/4 mapped"), std::string::npos) << err;
    const std::string md = slurp(out + "/report.md");
    const std::string html = slurp(out + "/report.html");
    EXPECT_NE(md.find("![elevation](pair0_elevation.png)"), std::string::npos);
    EXPECT_NE(html.find("<img src=\"pair3_elevation.png\">"), std::string::npos);
    // The same scenario at the same size, rendered with its truth by the simulator's CLI.
    std::string scn = slurp(std::string(VTM_SCENARIO_DIR) + "/descent.scn");
    for (const char* key : {"width_px 1024", "height_px 1024"}) {
        scn.replace(scn.find(key), std::string(key).size(), std::string(key).substr(0, 9) + " 256");
    }
    std::ofstream(dir_ + "/d256.scn") << scn;
    ASSERT_EQ(run("'" VTM_SIM_EXECUTABLE "' render '" + dir_ + "/d256.scn' '" + dir_ + "/sim' --frames 0,2,4,6", dir_, err), 0)
        << err;
    for (int pair = 0; pair < 4; ++pair) {
        SCOPED_TRACE("pair " + std::to_string(pair));
        const std::string p = out + "/pair" + std::to_string(pair);
        for (const char* suffix : {"_image1.png", "_image2.png"}) {
            const auto png = vtm::ground::loadGrey16(p + suffix);
            ASSERT_TRUE(png.ok) << png.error;
            EXPECT_EQ(png.value.width, 256);
        }
        for (const char* suffix : {"_elevation.png", "_depth.png"}) {  // RGB: signature and a non-empty IHDR
            const std::string png = slurp(p + suffix);
            ASSERT_GT(png.size(), 24U) << suffix;
            EXPECT_EQ(png.substr(1, 3), "PNG") << suffix;
            EXPECT_EQ(png.substr(12, 4), "IHDR") << suffix;
            EXPECT_GT(static_cast<unsigned char>(png[18]) * 256 + static_cast<unsigned char>(png[19]), 16) << suffix;
        }
        const auto depth = vtm::ground::readPfm(p + "_depth.pfm");
        char truth_name[64];
        std::snprintf(truth_name, sizeof truth_name, "/sim/nadir_%03d_depth.pfm", 2 * pair);
        const auto truth = vtm::ground::readPfm(dir_ + truth_name);
        ASSERT_TRUE(depth.ok && truth.ok) << depth.error << truth.error;
        ASSERT_TRUE(depth.value.sameSize(truth.value));
        std::vector<double> rel;
        for (std::size_t i = 0; i < depth.value.pixels.size(); ++i) {
            const float d = depth.value.pixels[i];
            const float t = truth.value.pixels[i];
            if (std::isfinite(d) && std::isfinite(t)) rel.push_back(std::fabs(d - t) / t);
        }
        ASSERT_GT(rel.size(), depth.value.pixels.size() / 10);  // the overlap is ~1/4 of image 1
        std::sort(rel.begin(), rel.end());
        EXPECT_LT(rel[rel.size() / 2], 0.015);  // median relative depth error (measured 0.24-0.73 %)
        // The point cloud holds one vertex per pixel with a depth.
        const std::string ply = slurp(p + "_points.ply");
        const std::size_t at = ply.find("element vertex ");
        ASSERT_NE(at, std::string::npos);
        std::size_t with_depth = 0;
        for (const float d : depth.value.pixels) with_depth += std::isfinite(d) ? 1U : 0U;
        EXPECT_EQ(std::stoul(ply.substr(at + 15)), with_depth);
    }
}

// The built-in rover pair at 512 x 512: the range of image 1's pixels that vtm run writes
// against the true range that vtm-sim render writes for the same scenario.
TEST_F(VtmRunCli, FliesTheBuiltInRoverPairAndItsRangeMatchesTheRenderedTruth) {
    std::string err;
    const std::string out = dir_ + "/run";
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run rover --size 512 --out '" + out + "'", dir_, err), 0) << err;
    EXPECT_NE(err.find("rover pair mapped"), std::string::npos) << err;
    const std::string md = slurp(out + "/report.md");
    EXPECT_NE(md.find("![disparity](rover_disparity.png)"), std::string::npos);
    EXPECT_NE(slurp(out + "/report.html").find("<img src=\"rover_elevation.png\">"), std::string::npos);
    std::string scn = slurp(std::string(VTM_SCENARIO_DIR) + "/rover_wide_baseline.scn");
    for (const char* key : {"width_px 1024", "height_px 1024"}) {
        scn.replace(scn.find(key), std::string(key).size(), std::string(key).substr(0, 9) + " 512");
    }
    std::ofstream(dir_ + "/r512.scn") << scn;
    ASSERT_EQ(run("'" VTM_SIM_EXECUTABLE "' render '" + dir_ + "/r512.scn' '" + dir_ + "/sim' --frames 0", dir_, err), 0)
        << err;
    const auto range = vtm::ground::readPfm(out + "/rover_range.pfm");
    const auto truth = vtm::ground::readPfm(dir_ + "/sim/mast_000_range.pfm");
    ASSERT_TRUE(range.ok && truth.ok) << range.error << truth.error;
    ASSERT_TRUE(range.value.sameSize(truth.value));
    std::vector<double> rel;
    for (std::size_t i = 0; i < range.value.pixels.size(); ++i) {
        const float r = range.value.pixels[i];
        const float t = truth.value.pixels[i];
        if (std::isfinite(r) && std::isfinite(t)) rel.push_back(std::fabs(r - t) / t);
    }
    ASSERT_GT(rel.size(), 20000U);  // measured 47,494 of 262,144 (docs/run.md)
    std::sort(rel.begin(), rel.end());
    std::printf("[ measure  ] rover_range.pfm against the rendered range: median %.2f %% over %zu pixels\n",
                100.0 * rel[rel.size() / 2], rel.size());
    EXPECT_LT(rel[rel.size() / 2], 0.06);  // median relative range error (docs/run.md)
    // Issue 21's band: true range 12.5..300 m (2.5 x the 5 m baseline). This test has no
    // visibility truth, so its denominator also counts band pixels image 2 does not see:
    // the share is a lower bound of the report's good coverage.
    std::size_t band = 0;
    std::size_t good = 0;
    std::vector<double> band_rel;
    for (std::size_t i = 0; i < range.value.pixels.size(); ++i) {
        const float r = range.value.pixels[i];
        const float t = truth.value.pixels[i];
        if (!(t >= 12.5F && t <= 300.0F)) continue;
        ++band;
        if (!std::isfinite(r)) continue;
        band_rel.push_back(std::fabs(r - t) / t);
        good += band_rel.back() <= 0.05 ? 1U : 0U;
    }
    ASSERT_GT(band_rel.size(), 0U);
    std::sort(band_rel.begin(), band_rel.end());
    std::printf("[ measure  ] band 12.5..300 m: %zu px, %.1f %% with a range within 5 %%, median error %.2f %%\n", band,
                100.0 * static_cast<double>(good) / static_cast<double>(band), 100.0 * band_rel[band_rel.size() / 2]);
    EXPECT_LE(band_rel[band_rel.size() / 2], 0.03);  // the median target
    // The 60 % good coverage is missed (docs/run.md has by how much); this floor
    // holds what is reached: measured 41.0 % at 512 x 512.
    EXPECT_GT(static_cast<double>(good) / static_cast<double>(band), 0.35);
    for (const char* f : {"rover_rectified1.png", "rover_rectified2.png", "rover_elevation.png", "rover_points.ply"}) {
        EXPECT_GT(slurp(out + "/" + f).size(), 100U) << f;
    }
}

// A panorama scenario (the small one of the tests, 16 stations of 128 x 128) flown through
// app::PanoramaMapper: its section and pictures in the report, its products on disk (the
// products' accuracy against the truth is gated by tests/app/panorama_mapper_test.cpp).
TEST_F(VtmRunCli, FliesAPanoramaThroughTheExecutive) {
    std::string err;
    const std::string out = dir_ + "/run";
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run '" VTM_SCENARIO_DIR "/test_panorama_small.scn' --out '" + out + "'", dir_,
                  err),
              0)
        << err;
    EXPECT_NE(err.find("panorama mapped"), std::string::npos) << err;
    const std::string md = slurp(out + "/report.md");
    EXPECT_NE(md.find("## Panorama"), std::string::npos);
    EXPECT_NE(md.find("image RMS before -> after"), std::string::npos);
    EXPECT_NE(md.find("![orthophoto](panorama_orthophoto.png)"), std::string::npos);
    EXPECT_NE(slurp(out + "/report.html").find("<img src=\"panorama_elevation.png\">"), std::string::npos);
    const auto elevation = vtm::ground::readPfm(out + "/panorama_elevation.pfm");
    ASSERT_TRUE(elevation.ok) << elevation.error;
    EXPECT_EQ(elevation.value.width, 80);
    for (const char* f : {"panorama_orthophoto.png", "panorama_left0.png", "panorama_variance.pfm"}) {
        EXPECT_GT(slurp(out + "/" + f).size(), 100U) << f;
    }
}

// The traverse and the descent over its terrain, fused by app::TerrainIntegrator (the main
// job's last part): every model added, the height maps at 2, 0.5 and 0.25 m on disk, each
// against the terrain of the same scenario built here (sim/, another program than vtm).
TEST_F(VtmRunCli, FusesTheTraverseAndTheDescentIntoHeightMapsThatMatchTheTerrain) {
    std::string err;
    const std::string out = dir_ + "/run";
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run traverse --out '" + out + "'", dir_, err), 0) << err;
    EXPECT_NE(err.find("7 of 7 stops registered"), std::string::npos) << err;
    const std::string md = slurp(out + "/report.md");
    EXPECT_NE(md.find("9 of 9 requests mapped"), std::string::npos);
    EXPECT_NE(md.find("## Traverse and descent, fused"), std::string::npos);
    EXPECT_NE(md.find("![error](traverse_fused_error_0.25m.png)"), std::string::npos);
    // The terrain: traverse.scn as vtm run builds it (samples_log2 10, the file's value).
    vtm::ground::SimWorld world;
    ASSERT_EQ(vtm::ground::buildSimWorld(slurp(VTM_SCENARIO_DIR "/traverse.scn"), world), "");
    // The octree's 64 m cube: north edge 40 m, west edge -24 m (docs/integrator.md); row 0 north.
    const struct { const char* file; int side; double cell_m; double max_rms_m; } levels[] = {
        {"traverse_fused_2m.pfm", 32, 2.0, 0.10}, {"traverse_fused_0.5m.pfm", 128, 0.5, 0.08},
        {"traverse_fused_0.25m.pfm", 256, 0.25, 0.08}};
    for (const auto& level : levels) {
        const auto map = vtm::ground::readPfm(out + "/" + level.file);
        ASSERT_TRUE(map.ok) << map.error;
        ASSERT_EQ(map.value.width, level.side) << level.file;
        ASSERT_EQ(map.value.height, level.side) << level.file;
        double sum2 = 0.0;
        int cells = 0;
        for (int row = 0; row < level.side; ++row) {
            for (int col = 0; col < level.side; ++col) {
                const float e = map.value.at(col, row);
                if (!std::isfinite(e)) continue;
                const double north = 40.0 - (row + 0.5) * level.cell_m, east = -24.0 + (col + 0.5) * level.cell_m;
                const double d = e - world.terrain.elevationAt(north, east);
                sum2 += d * d;
                ++cells;
            }
        }
        // The stops' wedge and the descent's footprint: about 30 m x 20 m.
        EXPECT_GT(cells * level.cell_m * level.cell_m, 300.0) << level.file;
        EXPECT_LT(std::sqrt(sum2 / std::max(cells, 1)), level.max_rms_m) << level.file << ": " << cells << " cells";
    }
}

// --link: the same descent flown against a separate `vtm-sim serve` over a Unix socket
// (hal/link) gives the same bits as in process: the frames and poses that cross the link
// are the simulated drivers' exactly.
TEST_F(VtmRunCli, TheHilLinkFliesTheSameBitsAsInProcess) {
    std::string err;
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run descent --size 256 --out '" + dir_ + "/ip'", dir_, err), 0) << err;
    ASSERT_EQ(run("'" VTM_EXECUTABLE "' run descent --size 256 --link --sim '" VTM_SIM_EXECUTABLE "' --out '" + dir_ +
                      "/lk'",
                  dir_, err),
              0)
        << err;
    EXPECT_NE(err.find("vtm-sim serve: 8 frames"), std::string::npos) << err;
    EXPECT_NE(slurp(dir_ + "/lk/report.md").find("link faults counted: 0"), std::string::npos);
    for (int pair = 0; pair < 4; ++pair) {
        for (const char* suffix : {"_depth.pfm", "_elevation.pfm"}) {
            const std::string name = "/pair" + std::to_string(pair) + suffix;
            const std::string a = slurp(dir_ + "/ip" + name);
            ASSERT_GT(a.size(), 1000U) << name;
            EXPECT_EQ(a, slurp(dir_ + "/lk" + name)) << name << " differs between in-process and link";
        }
    }
    // A simulator that exits before it listens: one line, no minute-long wait.
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --size 64 --link --sim /bin/false --out '" + dir_ + "/f'", dir_, err),
              1);
    EXPECT_NE(err.find("vtm-sim serve ended before it listened (exit status 1"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 4) << err;  // building, built, starting, then the error
}

TEST_F(VtmRunCli, BadInputsExitNonZeroWithOneLineNamingTheInput) {
    std::string err;
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run '" + dir_ + "/missing.scn' --out '" + dir_ + "/o'", dir_, err), 1);
    EXPECT_NE(err.find("missing.scn: cannot open"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run --size 8 --out '" + dir_ + "/o'", dir_, err), 1);
    EXPECT_NE(err.find("--size 8: must be 64..2048"), std::string::npos) << err;
    std::ofstream(dir_ + "/bad.scn") << "name x\nkind descent\nseed nope\n";
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run '" + dir_ + "/bad.scn' --out '" + dir_ + "/o'", dir_, err), 1);
    EXPECT_NE(err.find("bad.scn: "), std::string::npos) << err;
}

// --target's refusals (its flight is checked on each cross build by run.target_bits,
// tools/scripts/run_target_check.sh): each one line naming the input, before any world
// is built.
TEST_F(VtmRunCli, TargetRefusalsNameTheInputInOneLine) {
    std::string err;
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --target m68k --out '" + dir_ + "/t'", dir_, err), 1);
    EXPECT_NE(err.find("--target 'm68k': unknown (one of: aarch64 armhf ppc750 leon3 riscv64)"), std::string::npos)
        << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --target ppc750 --flight '" + dir_ + "/none' --out '" + dir_ + "/t'",
                  dir_, err),
              1);
    EXPECT_NE(err.find("--flight '" + dir_ + "/none': no ppc750 vtm there (build it: cmake --preset ppc750"),
              std::string::npos)
        << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    // A host vtm handed over as the "ppc750" one: the flight vtm checks what it was built for.
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --expect-target ppc750 --out '" + dir_ + "/t'", dir_, err), 1);
    EXPECT_NE(err.find("--expect-target ppc750: this vtm was built for host"), std::string::npos) << err;
    // Usage errors: --flight alone, --target with --link.
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --flight x --out '" + dir_ + "/t'", dir_, err), 2);
    EXPECT_NE(err.find("--flight requires --target"), std::string::npos) << err;
    EXPECT_EQ(run("'" VTM_EXECUTABLE "' run descent --target ppc750 --link --out '" + dir_ + "/t'", dir_, err), 2);
    EXPECT_NE(err.find("excludes"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir_ + "/t/report.md"));
}

}  // namespace
