// `vtm integrate` as a user runs it (docs/tools.md "vtm integrate"): a reference DEM as PFM
// with its vtm-orbital-geo side file and a rover stop as a PLY cloud in its own frame with
// a navigation pose that is off by a known motion, both of the analytic hills-and-rocks
// terrain of the ICP tests. Checked against that truth: the registered pose in poses.txt,
// the GeoTIFF read back against the surface (and against the same run without
// registration), the mesh's vertex count, and one-line errors with their exit codes.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "icp_scene.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/geotiff.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/ply_reader.hpp"
#include "vtm/ground/sim_output.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::ground {
namespace {

using test::CommandRun;
using test::runCommand;
using test::slurp;

using icp::test::motion;
using tools::kExitInputError;
using tools::kExitOk;
using tools::kExitUsageError;
using icp::test::rotationErrorDeg;
using icp::test::terrainZ;

CommandRun vtm(const test::TempDir& dir, const std::string& args) { return runCommand(dir, VTM_EXECUTABLE, args, true); }

::testing::AssertionResult failsWith(const CommandRun& r, int code, const std::string& needle) {
    const bool one_line = !r.err.empty() && r.err.find('\n') == r.err.size() - 1;
    if (r.exit_code == code && one_line && r.out.empty() && r.err.find(needle) != std::string::npos) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << "exit " << r.exit_code << " (want " << code << "), stderr \"" << r.err
                                         << "\" (want one line containing \"" << needle << "\")";
}

// The DEM: 80 x 80 posts of 0.25 m over x, y in [-10, 10], pixel (0, 0) at the north-west.
void writeDem(const test::TempDir& dir) {
    FloatImage dem(80, 80, 1);
    for (int row = 0; row < 80; ++row) {
        for (int col = 0; col < 80; ++col) {
            dem.at(col, row) = static_cast<float>(-terrainZ(9.875 - 0.25 * row, -9.875 + 0.25 * col));
        }
    }
    ASSERT_TRUE(writePfm(dir.file("dem.pfm"), dem).ok);
    std::ofstream geo(dir.file("dem.geo"));
    geo << "vtm-orbital-geo 1\n# test DEM\nimage dem.pfm\nnorth0_m 9.875\neast0_m -9.875\ncell_m 0.25\n"
           "width_px 80\nheight_px 80\naxes col_east row_south\n";
}

// The stop: a 10 m x 10 m patch at 0.2 m, 5 mm noise, in the rover's frame (truth: 35 deg
// heading, 1.5 m above the patch); the navigation's pose is off by 0.6/-0.5/0.8 deg and
// (0.15, -0.1, 0.05) m.
struct Stop {
    RigidPose truth, guess;
    Vec3 centroid = Vec3::Zero();
};
Stop writeStop(const test::TempDir& dir, double x0) {
    Stop s;
    s.truth = motion(0.0, 0.0, 35.0, Vec3(x0 + 5.0, 0.0, terrainZ(x0 + 5.0, 0.0) - 1.5));
    const RigidPose e = motion(0.6, -0.5, 0.8, Vec3(0.15, -0.1, 0.05));
    s.guess.R = e.R * s.truth.R;
    s.guess.t_m = e.R * s.truth.t_m + e.t_m;
    const std::vector<Vec3> pts = icp::test::sampleCloud({x0, x0 + 10.0, -5.0, 5.0}, 0.2, 5U, 0.005, s.truth);
    for (const Vec3& p : pts) s.centroid += p;
    s.centroid /= static_cast<double>(pts.size());
    EXPECT_TRUE(writePly(dir.file("stop.ply"), pts).ok);
    SimCameraPose pose;
    pose.camera = "rover";
    setSiteFromCam(pose, s.guess);
    std::ofstream(dir.file("nav.txt")) << formatCameraPoses({pose});
    return s;
}

// RMS of the GeoTIFF's elevations against the surface at the cell centres.
double rmsAgainstSurface(const ElevationGeoTiff& g, int* cells) {
    double sum = 0.0;
    *cells = 0;
    for (int row = 0; row < g.grid.rows; ++row) {
        for (int col = 0; col < g.grid.cols; ++col) {
            const float e = g.elevation_m.at(col, row);
            if (!std::isfinite(e)) continue;
            const double n = g.grid.north_edge_m - (row + 0.5) * g.grid.cell_m;
            const double east = g.grid.west_edge_m + (col + 0.5) * g.grid.cell_m;
            sum += (e + terrainZ(n, east)) * (e + terrainZ(n, east));
            ++*cells;
        }
    }
    return std::sqrt(sum / *cells);
}

TEST(VtmIntegrate, RegistersTheStopToTheDemAndWritesTheFusedMaps) {
    test::TempDir dir;
    writeDem(dir);
    const Stop s = writeStop(dir, -6.0);
    const std::string inputs = "dem.pfm,geo=dem.geo stop.ply,pose=nav.txt,footprint=0.02 --cells 0.25,1 --reducer mean";
    const CommandRun r = vtm(dir, "integrate " + inputs + " --out-dir out");
    ASSERT_EQ(r.exit_code, kExitOk) << r.err;
    std::printf("%s", r.out.c_str());
    EXPECT_NE(r.out.find("model 0 dem.pfm: reference, 6400 points"), std::string::npos);
    EXPECT_NE(r.out.find("model 1 stop.ply: registered"), std::string::npos);
    EXPECT_EQ(r.out, slurp(dir.file("out/report.txt")));
    const Result<std::vector<SimCameraPose>> poses = readCameraPoses(dir.file("out/poses.txt"));
    ASSERT_TRUE(poses.ok) << poses.error;
    ASSERT_EQ(poses.value.size(), 2U);
    const RigidPose reg = siteFromCam(poses.value[1]);
    const double rot = rotationErrorDeg(reg.R, s.truth.R);
    const double trans = ((reg.R * s.centroid + reg.t_m) - (s.truth.R * s.centroid + s.truth.t_m)).norm();
    std::printf("registered: %.4f deg, %.4f m at the centroid (navigation %.3f deg)\n", rot, trans,
                rotationErrorDeg(s.guess.R, s.truth.R));
    EXPECT_LE(rot, 0.05);
    EXPECT_LE(trans, 0.01);

    const Result<ElevationGeoTiff> fine = readElevationGeoTiff(dir.file("out/height_0.25m.tif"));
    ASSERT_TRUE(fine.ok) << fine.error;
    EXPECT_EQ(fine.value.grid.cell_m, 0.25);
    ASSERT_TRUE(readElevationGeoTiff(dir.file("out/height_1m.tif")).ok);
    int cells = 0;
    const double rms = rmsAgainstSurface(fine.value, &cells);
    EXPECT_EQ(cells, 6400);  // the DEM's posts; the stop lies inside it

    const CommandRun nr = vtm(dir, "integrate " + inputs + " --out-dir nav --no-register");
    ASSERT_EQ(nr.exit_code, kExitOk) << nr.err;
    const Result<ElevationGeoTiff> nav = readElevationGeoTiff(dir.file("nav/height_0.25m.tif"));
    ASSERT_TRUE(nav.ok) << nav.error;
    int nav_cells = 0;
    const double nav_rms = rmsAgainstSurface(nav.value, &nav_cells);
    std::printf("0.25 m map against the surface: registered %.4f m, navigation only %.4f m (%d cells)\n", rms, nav_rms,
                cells);
    EXPECT_LE(rms, 0.015);
    EXPECT_GE(nav_rms, 2.0 * rms);

    const Result<std::vector<Vec3>> mesh = readPlyPoints(dir.file("out/mesh.ply"));
    ASSERT_TRUE(mesh.ok) << mesh.error;
    EXPECT_EQ(mesh.value.size(), static_cast<std::size_t>(cells));
}

TEST(VtmIntegrate, ErrorsAreOneLineNamingTheInput) {
    test::TempDir dir;
    writeDem(dir);
    (void)writeStop(dir, 30.0);  // 30 m north of the DEM: nothing under it
    EXPECT_TRUE(failsWith(vtm(dir, "integrate nope.ply --out-dir o"), kExitInputError, "nope.ply"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate dem.pfm --out-dir o"), kExitInputError, "dem.pfm: a PFM elevation map needs geo="));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate dem.pfm,geo=dem.geo,colour=red --out-dir o"), kExitInputError,
                          "unknown or empty option 'colour=red'"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate stop.ply,pose=missing.txt --out-dir o"), kExitInputError, "missing.txt"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate stop.ply,footprint=0 --out-dir o"), kExitInputError, "footprint=0"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate dem.pfm,geo=dem.geo --cells 0.25,0.6 --out-dir o"), kExitUsageError,
                          "power of two"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate dem.pfm,geo=dem.geo --reducer max --out-dir o"), kExitUsageError,
                          "--reducer"));
    EXPECT_TRUE(failsWith(vtm(dir, "integrate dem.pfm,geo=dem.geo stop.ply,pose=nav.txt --out-dir o"), kExitInputError,
                          "stop.ply,pose=nav.txt: not integrated: integrator: too little of the map under the model"));
}

}  // namespace
}  // namespace vtm::ground
