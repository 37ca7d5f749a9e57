// `vtm descent` as a user runs it: vtm-sim renders two frames of a 128 x 128 version of
// the descent scenario, `vtm descent` maps them, the elevation PFM is read back and
// compared with the renderer's true depth turned into elevations; errors are one line
// naming the input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"

namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

int run(const std::string& exe, const std::string& args, const std::string& dir, std::string& err) {
    const std::string cmd = "'" + exe + "' " + args + " >'" + dir + "/out.txt' 2>'" + dir + "/err.txt'";
    const int status = std::system(cmd.c_str());
    err = slurp(dir + "/err.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

TEST(VtmDescentCli, MapsTwoRenderedDescentFrames) {
    const fs::path dir = fs::temp_directory_path() / ("vtm_descent_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::string text = slurp(std::string(VTM_SCENARIO_DIR) + "/descent.scn");
    for (const char* key : {"width_px 1024", "height_px 1024"}) {
        text.replace(text.find(key), std::string(key).size(), std::string(key).substr(0, 9) + " 128");
    }
    std::ofstream(dir / "small.scn") << text;
    std::string err;
    const std::string d = dir.string();
    ASSERT_EQ(run(VTM_SIM_EXECUTABLE, "render '" + d + "/small.scn' '" + d + "/sim' --frames 5,6", d, err), 0) << err;
    const std::string sim = d + "/sim/";
    // --window 7: at 128 x 128 the default 11 leaves too few pixels whose window both images hold.
    auto argsWith = [&](const std::string& pose2) {
        return "descent '" + sim + "nadir_005.png' '" + sim + "nadir_006.png' --camera '" + sim + "nadir.cmod' --pose1 '" +
               sim + "camera_poses.txt:5' --pose2 '" + sim + pose2 + "' --planes 32 --window 7 --out '" + d +
               "/elev.pfm' --color '" + d + "/elev.png'";
    };
    const std::string args = argsWith("camera_poses.txt:6");
    ASSERT_EQ(run(VTM_EXECUTABLE, args, d, err), 0) << err;
    EXPECT_TRUE(fs::exists(dir / "elev.png"));
    const auto elev = vtm::ground::readPfm(d + "/elev.pfm");
    ASSERT_TRUE(elev.ok) << elev.error;
    std::vector<double> mapped;
    for (const float v : elev.value.pixels) {
        if (std::isfinite(v)) mapped.push_back(v);
    }
    ASSERT_GT(mapped.size(), 50U);
    // Truth: the renderer's depth of frame 5 as elevations, over the same central third
    // of the image (the part frame 6 sees).
    const auto depth = vtm::ground::readPfm(sim + "nadir_005_depth.pfm");
    const auto pose = vtm::ground::readCameraPoseSpec(sim + "camera_poses.txt:5");
    ASSERT_TRUE(depth.ok && pose.ok);
    const double camZ = pose.value.position_m[2];
    std::vector<double> truth;
    for (int y = 43; y < 85; ++y) {
        for (int x = 43; x < 85; ++x) {
            truth.push_back(-(camZ + depth.value.at(x, y)));  // nadir within 0.5 deg: z ~ depth
        }
    }
    EXPECT_NEAR(median(mapped), median(truth), 0.01 * std::fabs(-camZ - median(truth)) + 0.5);
    // Errors: one line naming the input.
    EXPECT_EQ(run(VTM_EXECUTABLE, "descent '" + d + "/missing.png' '" + sim + "nadir_006.png' --camera '" + sim +
                                      "nadir.cmod' --pose1 '" + sim + "camera_poses.txt:5' --pose2 '" + sim +
                                      "camera_poses.txt:6' --out '" + d + "/x.pfm'",
                  d, err),
              1);
    EXPECT_NE(err.find("missing.png"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run(VTM_EXECUTABLE, argsWith("camera_poses.txt:9"), d, err), 1);
    EXPECT_NE(err.find("--pose2"), std::string::npos) << err;
    EXPECT_EQ(run(VTM_EXECUTABLE, args + " --score zncc", d, err), 1);
    EXPECT_NE(err.find("--score"), std::string::npos) << err;
    fs::remove_all(dir);
}

}  // namespace
