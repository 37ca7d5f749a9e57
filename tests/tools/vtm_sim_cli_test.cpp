// `vtm-sim render` as a user runs it: every documented output file is written, and reading
// the files back (tools/ground readers, hal/file FileCamera and FileOdometry) gives the
// same pixels, depths, disparities, poses and camera models as computing the scenario in
// this process; bad input gives a non-zero exit code and one line naming the field.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "hal/file/file_camera.hpp"
#include "hal/file/file_odometry.hpp"
#include "sim/orbital.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::ground {
namespace {

using test::CommandRun;
using test::runCommand;
using test::slurp;

const std::string kSmall = std::string(VTM_SCENARIO_DIR) + "/test_rover_small.scn";

CommandRun vtmSim(const test::TempDir& dir, const std::string& args) {
    return runCommand(dir, VTM_SIM_EXECUTABLE, args);
}

// The scenario computed in this process: terrain, frames, renders.
struct InProcess {
    sim::Scenario scenario;
    std::vector<std::byte> storage;
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain;
    std::unique_ptr<sim::ScenarioFrames> frames = std::make_unique<sim::ScenarioFrames>();

    explicit InProcess(const std::string& text) {
        EXPECT_TRUE(sim::parseScenario(text, scenario).isOk());
        storage.resize(sim::scenarioTerrainBytes(scenario));
        arena = std::make_unique<Arena>(storage.data(), storage.size());
        EXPECT_TRUE(sim::buildScenarioTerrain(scenario, *arena, terrain).isOk());
        EXPECT_TRUE(sim::buildScenarioFrames(scenario, terrain, *frames).isOk());
    }

    // Frame k rendered here: 8-bit or 16-bit pixels (widened) and depth with sky = +inf.
    void render(int k, std::vector<std::uint16_t>& pixels, FloatImage& depth) const {
        const sim::ScenarioFrame& f = frames->frames[k];
        const int w = f.model.width_px;
        const int h = f.model.height_px;
        GreyImage img8(w, h);
        Grey16Image img16(w, h);
        depth = FloatImage(w, h);
        const sim::FrameRequest request = sim::scenarioFrameRequest(scenario, terrain, f);
        sim::FrameOutput out;
        if (f.sensor.bit_depth == 8) {
            out.image8 = img8.view();
        } else {
            out.image16 = img16.view();
        }
        out.truth.depth_m = depth.view();
        ASSERT_TRUE(sim::renderFrame(request, out, nullptr).isOk());
        pixels.clear();
        for (std::size_t i = 0; i < img8.pixels.size(); ++i) {
            pixels.push_back(f.sensor.bit_depth == 8 ? img8.pixels[i] : img16.pixels[i]);
        }
        for (float& v : depth.pixels) {
            if (std::isnan(v)) v = std::numeric_limits<float>::infinity();
        }
    }
};

bool samePose(const hal::PoseEstimate& a, const sim::VehiclePose& b) {
    return a.timestamp_ns == b.timestamp_ns && std::memcmp(a.position_m, b.position_m, sizeof(b.position_m)) == 0 &&
           std::memcmp(a.attitude_wxyz, b.attitude_wxyz, sizeof(b.attitude_wxyz)) == 0 &&
           std::memcmp(a.covariance, b.covariance, sizeof(b.covariance)) == 0;
}

TEST(VtmSimRender, WritesEveryDocumentedFileAndItReadsBackAsComputedInProcess) {
    const test::TempDir dir;
    const std::string out = dir.file("out");
    const CommandRun run = vtmSim(dir, "render '" + kSmall + "' '" + out + "'");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const char* files[] = {"README.md", "scenario.scn", "truth.poses", "odometry.poses", "camera_poses.txt",
                           "mast.frames", "mast.cmod", "stereo_left.frames", "stereo_left.cmod",
                           "stereo_right.frames", "stereo_right.cmod", "stereo_left_000_disparity.pfm",
                           "stereo_left_000_disparity_code.png"};
    for (const char* f : files) {
        EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + f)) << f;
    }
    const InProcess world(slurp(kSmall));
    ASSERT_EQ(world.frames->count, 4);
    const char* manifests[] = {"mast", "stereo_left", "stereo_right"};
    static hal::FileCamera camera;
    for (const char* name : manifests) {
        const std::string manifest = out + "/" + name + ".frames";
        ASSERT_TRUE(camera.init({manifest.c_str()}).isOk()) << name;
        for (int k = 0; k < world.frames->count; ++k) {
            const sim::ScenarioFrame& f = world.frames->frames[k];
            const std::string stem = std::string(name) + "_00" + std::to_string(f.sequence);
            if ((std::string(name) == "mast") != (f.role == sim::FrameRole::kMain) ||
                (std::string(name) == "stereo_left") != (f.role == sim::FrameRole::kStereoLeft)) {
                continue;
            }
            std::vector<std::uint16_t> expected;
            FloatImage depth;
            world.render(k, expected, depth);
            GreyImage played(f.model.width_px, f.model.height_px);
            hal::FrameInfo info;
            ASSERT_TRUE(camera.capture(played.view(), info).isOk()) << stem;
            EXPECT_EQ(info.timestamp_ns, f.timestamp_ns);
            EXPECT_TRUE(std::equal(expected.begin(), expected.end(), played.pixels.begin())) << stem;
            const Result<FloatImage> pfm = readPfm(out + "/" + stem + "_depth.pfm");
            ASSERT_TRUE(pfm.ok) << pfm.error;
            EXPECT_EQ(pfm.value.pixels, depth.pixels) << stem;
            CameraModel model;
            ASSERT_TRUE(readCameraModelFile(out + "/" + name + ".cmod", model).ok);
            EXPECT_EQ(std::memcmp(&model.fx_px, &f.model.fx_px, 9 * sizeof(double)), 0);
        }
    }
    static hal::FileOdometry truth;
    static hal::FileOdometry odometry;
    ASSERT_TRUE(truth.init({(out + "/truth.poses").c_str(), 0U}).isOk());
    ASSERT_TRUE(odometry.init({(out + "/odometry.poses").c_str(), 0U}).isOk());
    EXPECT_EQ(truth.poseCount(), 2U);  // two rover stations
    for (int k = 0; k < world.frames->count; ++k) {
        const sim::ScenarioFrame& f = world.frames->frames[k];
        hal::PoseEstimate p;
        ASSERT_TRUE(truth.poseAt(f.timestamp_ns, p).isOk());
        EXPECT_TRUE(samePose(p, f.true_pose)) << k;
        ASSERT_TRUE(odometry.poseAt(f.timestamp_ns, p).isOk());
        EXPECT_TRUE(samePose(p, f.odometry_pose)) << k;
    }
    const Result<std::vector<SimCameraPose>> poses = readCameraPoses(out + "/camera_poses.txt");
    ASSERT_TRUE(poses.ok) << poses.error;
    ASSERT_EQ(poses.value.size(), 4U);
    for (const SimCameraPose& p : poses.value) {
        const RigidPose& site_from_cam = world.frames->frames[p.frame_index].camera_pose;
        const RigidPose read_back = siteFromCam(p);
        for (int i = 0; i < 3; ++i) EXPECT_EQ(read_back.t_m[i], site_from_cam.t_m[i]);
        EXPECT_LT((read_back.R - site_from_cam.R).norm(), 1e-12);
    }
}

TEST(VtmSimRender, TrueDisparityFileMatchesTheRectifiedPairInProcess) {
    const test::TempDir dir;
    const std::string out = dir.file("out");
    ASSERT_EQ(vtmSim(dir, "render '" + kSmall + "' '" + out + "' --frames 2").exit_code, 0);
    const InProcess world(slurp(kSmall));
    const sim::ScenarioFrame& left = world.frames->frames[2];
    FloatImage disparity(left.model.width_px, left.model.height_px);
    sim::StereoTruthRequest request;
    request.terrain = &world.terrain;
    request.left_model = left.model;
    request.left_pose = left.camera_pose;
    request.baseline_m = 0.42;
    sim::StereoTruthOutput truth;
    truth.disparity_px = disparity.view();
    ASSERT_TRUE(sim::rectifiedDisparity(request, truth).isOk());
    const Result<FloatImage> pfm = readPfm(out + "/stereo_left_000_disparity.pfm");
    ASSERT_TRUE(pfm.ok) << pfm.error;
    int finite = 0;
    for (std::size_t i = 0; i < disparity.pixels.size(); ++i) {
        const float d = disparity.pixels[i];
        if (std::isnan(d)) {
            EXPECT_TRUE(std::isinf(pfm.value.pixels[i]));
        } else {
            EXPECT_EQ(pfm.value.pixels[i], d);
            ++finite;
        }
    }
    EXPECT_GT(finite, 0);
    // Only the requested frame was rendered; the others are absent.
    EXPECT_FALSE(std::filesystem::exists(out + "/mast_000.png"));
    EXPECT_TRUE(std::filesystem::exists(out + "/stereo_left_000.png"));
}

TEST(VtmSimRender, TwelveBitFramesPlayBackFromPngAndPgm) {
    const test::TempDir dir;
    std::string text = slurp(kSmall);
    text.replace(text.find("bit_depth 8"), 11, "bit_depth 12");
    const std::string scenario = dir.file("twelve.scn");
    std::ofstream(scenario) << text;
    const InProcess world(text);
    std::vector<std::uint16_t> expected;
    FloatImage depth;
    world.render(0, expected, depth);
    for (const char* format : {"png", "pgm"}) {
        const std::string out = dir.file(std::string("out_") + format);
        const CommandRun run = vtmSim(dir, "render '" + scenario + "' '" + out + "' --frames 0 --format " + format);
        ASSERT_EQ(run.exit_code, 0) << run.err;
        static hal::FileCamera camera;
        ASSERT_TRUE(camera.init({(out + "/mast.frames").c_str()}).isOk()) << format;
        Grey16Image played(128, 128);
        hal::FrameInfo info;
        ASSERT_TRUE(camera.capture16(played.view(), info).isOk()) << format;
        EXPECT_EQ(info.bit_depth, 12U);
        EXPECT_EQ(played.pixels, expected) << format;
        const Result<Grey16Image> loaded = loadGrey16(out + "/mast_000." + format);
        ASSERT_TRUE(loaded.ok) << loaded.error;
        EXPECT_EQ(loaded.value.pixels, expected) << format;
    }
}

// A descent with [orbital]: orbital.png, orbital.geo and orbital_elevation.pfm are written;
// the geo file's numbers are the in-process georeference, the image and the elevation the
// in-process renderOrbital's; a bad [orbital] value exits 1 naming the key and the line.
TEST(VtmSimRender, OrbitalViewAndItsGeoreferenceAreWrittenAsComputedInProcess) {
    const test::TempDir dir;
    const std::string text = slurp(std::string(VTM_SCENARIO_DIR) + "/test_descent_small.scn") +
                             "\n[orbital]\nwidth_px 96\nheight_px 64\ncell_m 2\nbit_depth 16\ncentre_offset_m 3 -5\n";
    const std::string scenario = dir.file("orbital.scn");
    std::ofstream(scenario) << text;
    const std::string out = dir.file("out");
    const CommandRun run = vtmSim(dir, "render '" + scenario + "' '" + out + "' --frames 0");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const InProcess world(text);
    const sim::OrbitalParams p = sim::scenarioOrbitalParams(world.scenario);
    const sim::OrbitalGeoreference geo = sim::orbitalGeoreference(p);
    Grey16Image image(96, 64);
    FloatImage elevation(96, 64);
    sim::OrbitalOutput views;
    views.image16 = image.view();
    views.elevation_m = elevation.view();
    ASSERT_TRUE(sim::renderOrbital(world.terrain, p, views, nullptr).isOk());
    const Result<Grey16Image> loaded = loadGrey16(out + "/orbital.png");
    ASSERT_TRUE(loaded.ok) << loaded.error;
    EXPECT_EQ(loaded.value.pixels, image.pixels);
    const Result<FloatImage> pfm = readPfm(out + "/orbital_elevation.pfm");
    ASSERT_TRUE(pfm.ok) << pfm.error;
    EXPECT_EQ(pfm.value.pixels, elevation.pixels);
    // orbital.geo: "key value..." lines after the version line.
    std::istringstream geo_text(slurp(out + "/orbital.geo"));
    std::string line;
    ASSERT_TRUE(std::getline(geo_text, line));
    EXPECT_EQ(line, "vtm-orbital-geo 1");
    std::map<std::string, std::string> kv;
    while (std::getline(geo_text, line)) {
        if (line.empty() || line[0] == '#') continue;
        const std::size_t space = line.find(' ');
        kv[line.substr(0, space)] = line.substr(space + 1);
    }
    EXPECT_EQ(std::stod(kv["north0_m"]), geo.north0_m);
    EXPECT_EQ(std::stod(kv["east0_m"]), geo.east0_m);
    EXPECT_EQ(std::stod(kv["cell_m"]), 2.0);
    EXPECT_EQ(kv["width_px"], "96");
    EXPECT_EQ(kv["height_px"], "64");
    EXPECT_EQ(kv["axes"], "col_east row_south");
    EXPECT_EQ(kv["modality"], "thermal");
    EXPECT_EQ(kv["bit_depth"], "16");
    EXPECT_EQ(kv["image"], "orbital.png");
    // The documented centre: motion.start_m (0 0) + centre_offset_m, half the image away.
    EXPECT_DOUBLE_EQ(geo.north0_m, 3.0 + 0.5 * 63 * 2.0);
    EXPECT_DOUBLE_EQ(geo.east0_m, -5.0 - 0.5 * 95 * 2.0);
    EXPECT_NE(slurp(out + "/README.md").find("orbital.geo"), std::string::npos);
    // A bad [orbital] value: exit 1, one line naming the key and its line.
    std::string bad_text = text;
    bad_text.replace(bad_text.find("cell_m 2"), 8, "cell_m 0");
    const std::string bad = dir.file("bad_orbital.scn");
    std::ofstream(bad) << bad_text;
    const CommandRun refused = vtmSim(dir, "render '" + bad + "' '" + dir.file("bad_out") + "'");
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("orbital.cell_m is out of range"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("line "), std::string::npos) << refused.err;
}

TEST(VtmSimRender, BadInputExitsNonZeroWithOneLineNamingTheField) {
    const test::TempDir dir;
    std::string text = slurp(kSmall);
    text.replace(text.find("rock_k 0.05"), 11, "rock_k 0.9");
    const std::string bad = dir.file("bad.scn");
    std::ofstream(bad) << text;
    struct Case {
        std::string args;
        int code;
        std::string needle;
    };
    const Case cases[] = {
        {"render '" + bad + "' '" + dir.file("o1") + "'", 1, "terrain.rock_k is out of range"},
        {"render '" + dir.file("missing.scn") + "' '" + dir.file("o2") + "'", 1, "missing.scn: cannot open"},
        {"render '" + kSmall + "' '" + dir.file("o3") + "' --frames 9", 2, "--frames: '9'"},
        {"render '" + kSmall + "' '" + dir.file("o4") + "' --format jpg", 2, "jpg"},
    };
    for (const Case& c : cases) {
        const CommandRun r = vtmSim(dir, c.args);
        EXPECT_EQ(r.exit_code, c.code) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    }
    // The bad field's line number is in the message.
    EXPECT_NE(vtmSim(dir, cases[0].args).err.find("line "), std::string::npos);
}

// panorama_stations.txt (docs/sim-scenarios.md "Panorama"): every station's true and
// approximate left-eye pose and its prior, as buildPanorama computes them in this process.
TEST(VtmSimRender, PanoramaStationsFileHoldsTheInProcessStations) {
    const test::TempDir dir;
    const std::string out = dir.file("pano");
    const std::string scn = std::string(VTM_SCENARIO_DIR) + "/test_panorama_small.scn";
    const CommandRun run = vtmSim(dir, "render '" + scn + "' '" + out + "' --frames 0,1");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(std::filesystem::is_regular_file(out + "/stereo_left_000.png"));
    EXPECT_TRUE(std::filesystem::is_regular_file(out + "/stereo_right_000.png"));
    const InProcess world(slurp(scn));
    auto panorama = std::make_unique<sim::Panorama>();
    ASSERT_TRUE(sim::buildPanorama(world.scenario, world.terrain, *panorama).isOk());
    std::istringstream in(slurp(out + "/panorama_stations.txt"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "vtm-panorama-stations 1");
    int station = -1;
    int poses = 0;
    int priors = 0;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string key;
        fields >> key;
        if (key == "station") {
            fields >> station;
            continue;
        }
        if (key != "true" && key != "approx" && key != "prior") continue;
        ASSERT_GE(station, 0);
        ASSERT_LT(station, panorama->count);
        const sim::PanoramaStation& s = panorama->stations[station];
        if (key == "prior") {
            for (int i = 0; i < 36; ++i) {
                double v = 0.0;
                fields >> v;
                EXPECT_EQ(v, s.approx.prior_covariance(i / 6, i % 6)) << station << " " << i;
            }
            ++priors;
            continue;
        }
        const RigidPose& expected = (key == "true") ? s.truth.site_from_a : s.approx.site_from_a;
        double v[7] = {};
        for (double& x : v) fields >> x;
        for (int i = 0; i < 3; ++i) EXPECT_EQ(v[i], expected.t_m[i]) << key << " " << station;
        const Mat3 R = Quat(v[3], v[4], v[5], v[6]).toRotationMatrix();
        EXPECT_LT((R - expected.R).norm(), 1e-12) << key << " " << station;
        ++poses;
    }
    EXPECT_EQ(poses, 2 * panorama->count);
    EXPECT_EQ(priors, panorama->count);
}

}  // namespace
}  // namespace vtm::ground
