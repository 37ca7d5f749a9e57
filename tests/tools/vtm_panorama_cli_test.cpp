// `vtm panorama` as a user runs it (docs/panorama-cli.md): `vtm-sim render` of the tests'
// small panorama (16 stations of 128 x 128 eyes), then `vtm panorama` on its
// panorama_stations.txt. Checked against the simulator's terrain in this process (the
// kriged elevation near the mast), against app::PanoramaMapper run here on the same
// stations and images rendered here (identical bits of the elevation map), and bad inputs
// exit 1 with one line naming the file, the line and the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "hal/event_log.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "panorama_setup.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "vtm/app/panorama_mapper.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/panorama_stations.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"
#include "vtm/ground/sim_world.hpp"

namespace vtm::ground {
namespace {

using test::CommandRun;
using test::runCommand;
using test::slurp;

// One render and one mapping shared by the tests of this file (they only read them).
struct Rendered {
    test::TempDir dir;
    std::string scn = std::string(VTM_SCENARIO_DIR) + "/test_panorama_small.scn";
    std::string render = dir.file("render");
    std::string out = dir.file("out");
    CommandRun sim_run, run;
    Rendered() {
        sim_run = runCommand(dir, VTM_SIM_EXECUTABLE, "render '" + scn + "' '" + render + "'");
        run = runCommand(dir, VTM_EXECUTABLE, "panorama '" + render + "/panorama_stations.txt' --out '" + out + "'");
    }
};

const Rendered& rendered() {
    static const auto r = std::make_unique<Rendered>();
    return *r;
}

CommandRun vtm(const std::string& args) { return runCommand(rendered().dir, VTM_EXECUTABLE, args); }

::testing::AssertionResult failsWith(const CommandRun& r, int code, const std::vector<std::string>& needles) {
    const bool one_line = !r.err.empty() && r.err.find('\n') == r.err.size() - 1;
    bool all = true;
    for (const std::string& n : needles) all = all && r.err.find(n) != std::string::npos;
    if (r.exit_code == code && one_line && all) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "exit " << r.exit_code << " (want " << code << "), stderr \"" << r.err << "\"";
}

// The scenario's world and panorama, built here.
struct World {
    SimWorld world;
    std::unique_ptr<sim::Panorama> pano = std::make_unique<sim::Panorama>();
    World() {
        EXPECT_EQ(buildSimWorld(slurp(rendered().scn), world), "");
        EXPECT_TRUE(sim::buildPanorama(world.scenario, world.terrain, *pano).isOk());
    }
};

TEST(VtmPanorama, ElevationNearTheMastMatchesTheSimulatedTerrain) {
    const Rendered& r = rendered();
    ASSERT_EQ(r.sim_run.exit_code, 0) << r.sim_run.err;
    ASSERT_EQ(r.run.exit_code, 0) << r.run.err;
    const World w;
    const Result<FloatImage> elevation = readPfm(r.out + "/panorama_elevation.pfm");
    ASSERT_TRUE(elevation.ok) << elevation.error;
    // The command's grid: 20 m at 0.25 m centred on the mean approximate left eye.
    double cn = 0.0, ce = 0.0;
    for (int k = 0; k < w.pano->count; ++k) {
        cn += w.pano->stations[k].approx.site_from_a.t_m.x() / w.pano->count;
        ce += w.pano->stations[k].approx.site_from_a.t_m.y() / w.pano->count;
    }
    ASSERT_EQ(elevation.value.width, 80);
    ASSERT_EQ(elevation.value.height, 80);
    const Vec3 mast = w.pano->rover.position_site_m;
    double sum2 = 0.0;
    int nodes = 0, estimated = 0;
    for (int row = 0; row < 80; ++row) {
        for (int col = 0; col < 80; ++col) {
            const double n = cn + 10.0 - 0.25 * (row + 0.5), e = ce - 10.0 + 0.25 * (col + 0.5);
            const double d = std::hypot(n - mast.x(), e - mast.y());
            if (d < 1.5 || d > 4.0) continue;
            ++nodes;
            const float z = elevation.value.at(col, row);
            if (!std::isfinite(z)) continue;
            ++estimated;
            const double err = static_cast<double>(z) - w.world.terrain.elevationAt(n, e);
            sum2 += err * err;
        }
    }
    ASSERT_GT(nodes, 100);
    std::printf("elevation 1.5-4 m from the mast: %d of %d nodes estimated, RMS %.4f m\n", estimated, nodes,
                std::sqrt(sum2 / estimated));
    EXPECT_GT(estimated, nodes * 9 / 10) << estimated << " of " << nodes;
    EXPECT_LT(std::sqrt(sum2 / estimated), 0.05) << "elevation RMS 1.5-4 m from the mast, metres";
    for (const char* f : {"panorama_elevation.tif", "panorama_variance.pfm", "panorama_orthophoto.png",
                          "panorama_orthophoto.tif", "panorama_poses.txt", "panorama_tiepoints.txt",
                          "panorama_report.md"}) {
        EXPECT_FALSE(slurp(r.out + "/" + f).empty()) << f;
    }
}

TEST(VtmPanorama, ElevationHasTheBitsOfTheExecutiveRunInProcess) {
    const Rendered& r = rendered();
    ASSERT_EQ(r.run.exit_code, 0) << r.run.err;
    const World w;
    const sim::Panorama& pano = *w.pano;
    const int side = w.world.frames->frames[0].model.width_px;
    std::vector<std::vector<std::uint8_t>> pixels(static_cast<std::size_t>(2 * pano.count),
                                                  std::vector<std::uint8_t>(static_cast<std::size_t>(side * side)));
    std::vector<NetworkStation> stations;
    std::vector<StationImages> images;
    for (int k = 0; k < 2 * pano.count; ++k) {  // frame k: station k / 2, eye k % 2
        sim::FrameOutput o;
        o.image8 = ImageView<std::uint8_t>(pixels[static_cast<std::size_t>(k)].data(), side, side);
        ASSERT_TRUE(sim::renderFrame(sim::scenarioFrameRequest(w.world.scenario, w.world.terrain,
                                                               w.world.frames->frames[k]),
                                     o, nullptr)
                        .isOk());
    }
    double cn = 0.0, ce = 0.0;
    for (int s = 0; s < pano.count; ++s) {
        NetworkStation st = pano.stations[s].approx;
        SimCameraPose record;  // the file holds the attitude as a quaternion (docs/cli-poses.md)
        setSiteFromCam(record, st.site_from_a);
        st.site_from_a = siteFromCam(record);
        stations.push_back(st);
        images.push_back({ImageView<const std::uint8_t>(pixels[static_cast<std::size_t>(2 * s)].data(), side, side),
                          ImageView<const std::uint8_t>(pixels[static_cast<std::size_t>(2 * s + 1)].data(), side, side)});
        cn += st.site_from_a.t_m.x() / pano.count;
        ce += st.site_from_a.t_m.y() / pano.count;
    }
    tools::PanoramaGrid grid;
    grid.centre_north_m = cn;
    grid.centre_east_m = ce;
    const app::PanoramaMapperConfig c = tools::panoramaMapperConfig(pano.count, pano.columns, side, side, grid);
    hal::MonotonicClock clock;
    auto events = std::make_unique<hal::EventLog>();
    std::vector<std::byte> pool(app::PanoramaMapper::workspaceBytes(c) + 64U);
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::PanoramaMapper>();
    ASSERT_TRUE(mapper->init(c, arena, clock, *events).isOk());
    ASSERT_TRUE(mapper->map(Span<const NetworkStation>(stations.data(), stations.size()),
                            Span<const StationImages>(images.data(), images.size()))
                    .isOk());
    const kriging::KrigedMap& map = *mapper->products()->elevation;
    const Result<FloatImage> elevation = readPfm(r.out + "/panorama_elevation.pfm");
    ASSERT_TRUE(elevation.ok) << elevation.error;
    ASSERT_EQ(elevation.value.width, map.grid().cols);
    ASSERT_EQ(elevation.value.height, map.grid().rows);
    int differ = 0, finite = 0;
    for (int row = 0; row < map.grid().rows; ++row) {
        for (int col = 0; col < map.grid().cols; ++col) {
            const float a = elevation.value.at(col, row), b = map.elevation(col, row);
            finite += std::isfinite(b) ? 1 : 0;
            differ += (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0 ? 0 : 1;
        }
    }
    EXPECT_GT(finite, 1000);
    EXPECT_EQ(differ, 0);
}

// A copy of the rendered stations file with one line replaced (the 1-based line `line`
// becomes `text`), written into the render directory so that its relative names resolve.
std::string stationsWith(int line, const std::string& text, const std::string& name) {
    std::istringstream in(slurp(rendered().render + "/panorama_stations.txt"));
    std::string out, l;
    for (int n = 1; std::getline(in, l); ++n) out += (n == line ? text : l) + "\n";
    const std::string path = rendered().render + "/" + name;
    std::ofstream(path) << out;
    return path;
}

int lineOf(const std::string& key_prefix) {
    std::istringstream in(slurp(rendered().render + "/panorama_stations.txt"));
    std::string l;
    for (int n = 1; std::getline(in, l); ++n) {
        if (l.rfind(key_prefix, 0) == 0) return n;
    }
    return -1;
}

TEST(VtmPanorama, BadInputsExitWithOneLineNamingFileLineAndReason) {
    const Rendered& r = rendered();
    ASSERT_EQ(r.sim_run.exit_code, 0) << r.sim_run.err;
    const std::string out = " --out '" + r.dir.file("bad") + "'";
    const int approx = lineOf("approx"), prior = lineOf("prior"), stations = lineOf("stations"),
              images = lineOf("images");
    ASSERT_GT(approx, 0);
    EXPECT_TRUE(failsWith(vtm("panorama '" + r.dir.file("none.txt") + "'" + out), tools::kExitInputError,
                          {"none.txt", "cannot open"}));
    std::string p = stationsWith(approx, "approx 1 2 3 0.5 0.5 0.5", "short_pose.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"short_pose.txt", "line " + std::to_string(approx), "expected 7 finite numbers"}));
    p = stationsWith(approx, "approx 1 2 3 0.9 0.1 0.1 0.1", "not_unit.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"not_unit.txt", "line " + std::to_string(approx), "not a unit quaternion"}));
    // A prior with a negative eigenvalue (|cov(0,1)| > the variances) is not positive definite.
    p = stationsWith(prior, "prior 1 2 0 0 0 0  2 1 0 0 0 0  0 0 1 0 0 0  0 0 0 1 0 0  0 0 0 0 1 0  0 0 0 0 0 1",
                     "not_pd.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"not_pd.txt", "line " + std::to_string(prior), "not positive definite"}));
    p = stationsWith(prior, "prior 1 2 3", "short_prior.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"short_prior.txt", "line " + std::to_string(prior), "36 finite numbers"}));
    p = stationsWith(stations, "stations 65", "too_many.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"too_many.txt", "line " + std::to_string(stations), "at most 64"}));
    p = stationsWith(images, "images missing_left.png stereo_right_000.png", "missing_image.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"missing_image.txt", "line " + std::to_string(images), "missing_left.png"}));
    // An eye of another size than its camera model.
    ASSERT_TRUE(writePng(r.render + "/small.png", GreyImage(64, 64)).ok);
    p = stationsWith(images, "images small.png stereo_right_000.png", "wrong_size.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError,
                          {"wrong_size.txt", "line " + std::to_string(images), "64x64", "128x128"}));
    p = stationsWith(1, "vtm-panorama-stations 2", "version.txt");
    EXPECT_TRUE(failsWith(vtm("panorama '" + p + "'" + out), tools::kExitInputError, {"version.txt", "line 1"}));
    EXPECT_TRUE(failsWith(vtm("panorama '" + r.render + "/panorama_stations.txt' --ring 5" + out),
                          tools::kExitUsageError, {"--ring 5", "16 stations"}));
}

// The per-axis form of the prior and a prior that holds parameters fixed.
TEST(PanoramaStationsFile, SigmaGivesADiagonalPriorAndZeroVariancesHoldParametersFixed) {
    const std::string head = "vtm-panorama-stations 1\nleft_camera l.cmod\nright_camera r.cmod\n"
                             "right_from_left -0.4 0 0 1 0 0 0\nstations 2\n";
    const std::string station = "images a.png b.png\napprox 1 2 -1.5 1 0 0 0\n";
    const Result<PanoramaStationsFile> f = parsePanoramaStations(
        head + "station 0\n" + station + "sigma 0.01 0.02 0.03 0 0 0.5\nstation 1\n" + station +
        "sigma 0 0 0 0 0 0\n");
    ASSERT_TRUE(f.ok) << f.error;
    EXPECT_EQ(f.value.stations[0].prior(1, 1), 0.02 * 0.02);
    EXPECT_EQ(f.value.stations[0].prior(5, 5), 0.25);
    EXPECT_EQ(f.value.stations[0].prior(0, 1), 0.0);
    EXPECT_EQ(f.value.stations[1].prior, Mat6::Zero());
    const Result<PanoramaStationsFile> short_file = parsePanoramaStations(head + "station 0\n" + station + "sigma 1 1 1 1 1 1\n");
    ASSERT_FALSE(short_file.ok);
    EXPECT_NE(short_file.error.find("1 stations of the 2 announced"), std::string::npos) << short_file.error;
}

}  // namespace
}  // namespace vtm::ground
