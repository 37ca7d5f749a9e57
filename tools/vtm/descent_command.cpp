#include "descent_command.hpp"
#include "command_support.hpp"
#include "option_pair.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "vtm/ground/exit_codes.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/descent/plane_sweep.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/disparity_colormap.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {
namespace {

using ground::FloatImage;
using ground::Grey16Image;

RigidPose toPose(const ground::SimCameraPose& p) {
    return ground::siteFromCam(p);
}

struct DescentInputs {
    Grey16Image image1;
    Grey16Image image2;
    descent::PairGeometry geometry;
    descent::Config config;
};

std::string loadInputs(const DescentOptions& o, DescentInputs& in) {
    auto i1 = ground::loadGrey16(o.image1);
    if (!i1.ok) return i1.error;
    auto i2 = ground::loadGrey16(o.image2);
    if (!i2.ok) return i2.error;
    if (!i1.value.sameSize(i2.value)) {
        return o.image2 + ": size differs from " + o.image1;
    }
    const ground::Outcome cam = ground::readCameraModelFile(o.camera, in.geometry.camera);
    if (!cam.ok) return cam.error;
    auto p1 = ground::readCameraPoseSpec(o.pose1);
    if (!p1.ok) return "--pose1 " + p1.error;
    auto p2 = ground::readCameraPoseSpec(o.pose2);
    if (!p2.ok) return "--pose2 " + p2.error;
    in.image1 = std::move(i1.value);
    in.image2 = std::move(i2.value);
    in.geometry.site_from_cam1 = toPose(p1.value);
    in.geometry.site_from_cam2 = toPose(p2.value);
    return "";
}

// The sweep's configuration from the options; "" or the error.
std::string makeConfig(const DescentOptions& o, DescentInputs& in) {
    descent::Config& c = in.config;
    c.max_width = in.image1.width;
    c.max_height = in.image1.height;
    c.planes = o.planes;
    c.window = o.window;
    if (o.score != "sad" && o.score != "ncc") {
        return "--score '" + o.score + "': expected sad or ncc";
    }
    c.score = o.score == "ncc" ? descent::Score::kNcc : descent::Score::kSad;
    if (!o.depth_range.empty()) {
        const std::string e = cli::parseOptionPair("--depth", o.depth_range, cli::PairRule::kPositiveIncreasing, "in metres", "80:130",
                                                    c.depth_min_m, c.depth_max_m);
        if (!e.empty()) return e;
    } else {
        // Height of camera 1 above the site datum (elevation 0), +-30 %.
        const double h = -in.geometry.site_from_cam1.t_m.z();
        if (!(h > 0.0)) {
            return "--pose1 " + o.pose1 + ": camera 1 is not above elevation 0; give --depth MIN:MAX";
        }
        c.depth_min_m = 0.7 * h;
        c.depth_max_m = 1.3 * h;
    }
    const double f = (1.0 / c.depth_min_m - 1.0 / c.depth_max_m) * 0.5 * (c.depth_min_m + c.depth_max_m);
    c.min_parallax_px = o.min_parallax_px >= 0.0 ? o.min_parallax_px : 50.0 * f;
    const Status v = c.validate();
    if (!v.isOk()) {
        return std::string("configuration refused: ") + v.reason() + " (got " + std::to_string(v.detail()) + ")";
    }
    return "";
}

// The grid covering every valid point (terrain::HeightMap's convention: origin at the
// north-west corner, a cell holds its south and west edges), cell = --cell or one image-1
// pixel on the ground.
std::string planGrid(const DescentOptions& o, const DescentInputs& in, const FloatImage& depth, terrain::GridConfig& g) {
    const CameraModel& cam = in.geometry.camera;
    const RigidPose& pose = in.geometry.site_from_cam1;
    double nMin = 1e300, nMax = -1e300, eMin = 1e300, eMax = -1e300, dSum = 0.0;
    std::size_t count = 0;
    for (std::int32_t y = 0; y < depth.height; ++y) {
        for (std::int32_t x = 0; x < depth.width; ++x) {
            const float d = depth.at(x, y);
            if (!std::isfinite(d)) continue;
            const Vec3 ray((x - cam.cx_px) / cam.fx_px, (y - cam.cy_px) / cam.fy_px, 1.0);
            const Vec3 p = pose.R * (ray * static_cast<double>(d)) + pose.t_m;
            nMin = std::min(nMin, p.x());
            nMax = std::max(nMax, p.x());
            eMin = std::min(eMin, p.y());
            eMax = std::max(eMax, p.y());
            dSum += static_cast<double>(d);
            ++count;
        }
    }
    if (count == 0U) return "no pixel got a depth (texture, overlap or --depth range?)";
    g.cell_m = o.cell_m > 0.0 ? o.cell_m : (dSum / static_cast<double>(count)) / cam.fx_px;
    g.north_edge_m = (std::floor(nMax / g.cell_m) + 1.0) * g.cell_m;  // beyond nMax: the north edge is open
    g.west_edge_m = std::floor(eMin / g.cell_m) * g.cell_m;
    const double rows = std::floor((g.north_edge_m - nMin) / g.cell_m) + 1.0;
    const double cols = std::floor((eMax - g.west_edge_m) / g.cell_m) + 1.0;
    if (rows > terrain::kMaxGridSide || cols > terrain::kMaxGridSide) {
        return "--cell " + std::to_string(g.cell_m) + ": the grid would exceed 4096 cells per side";
    }
    g.rows = static_cast<std::int32_t>(rows);
    g.cols = static_cast<std::int32_t>(cols);
    return "";
}

std::string writeOutputs(const DescentOptions& o, const FloatImage& depth, const FloatImage& elevation) {
    ground::Outcome w = ground::writePfm(o.out_pfm, elevation);
    if (w.ok && !o.depth_pfm.empty()) w = ground::writePfm(o.depth_pfm, depth);
    if (w.ok && !o.color_png.empty()) {
        float lo = std::numeric_limits<float>::infinity();
        float hi = -lo;
        for (const float v : elevation.pixels) {
            if (std::isfinite(v)) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        }
        w = ground::writePng(o.color_png, ground::colorizeDisparity(elevation, lo, hi));
    }
    return w.ok ? "" : w.error;
}

}  // namespace

CLI::App* addDescentCommand(CLI::App& app, DescentOptions& o) {
    CLI::App* cmd = app.add_subcommand("descent", "elevation map from two descent images (plane sweep, flight module)");
    cmd->add_option("IMG1", o.image1, "earlier (higher) frame: 8- or 12-bit grey PNG or PGM")->required();
    cmd->add_option("IMG2", o.image2, "later (closer) frame, same size")->required();
    cmd->add_option("--camera", o.camera, "camera model file (undistorted pinhole)")->required();
    cmd->add_option("--pose1", o.pose1, "pose of camera 1: FILE or FILE:INDEX (vtm-camera-poses 1)")->required();
    cmd->add_option("--pose2", o.pose2, "pose of camera 2: FILE or FILE:INDEX")->required();
    cmd->add_option("--planes", o.planes, "planes, 3..256 (default 64)");
    cmd->add_option("--depth", o.depth_range, "depth range MIN:MAX, metres along camera 1's axis "
                                              "(default: camera 1's height above elevation 0, +-30 %)");
    cmd->add_option("--score", o.score, "window score: ncc or sad (default ncc)");
    cmd->add_option("--window", o.window, "window side, odd, 3..31 px (default 11)");
    cmd->add_option("--min-parallax", o.min_parallax_px, "focus-of-expansion mask threshold, image-2 px");
    cmd->add_option("--cell", o.cell_m, "grid cell, metres (default: one image-1 pixel on the ground)");
    cmd->add_option("--out", o.out_pfm, "elevation grid as PFM (metres, NaN = NO_DATA, north up)")->required();
    cmd->add_option("--color", o.color_png, "colour-coded elevation PNG (red = high ... purple = low, black = none)");
    cmd->add_option("--depth-out", o.depth_pfm, "per-pixel depth of IMG1 as PFM (metres, NaN = none)");
    return cmd;
}

int runDescent(const DescentOptions& o) {
    DescentInputs in;
    std::string error = loadInputs(o, in);
    error = error.empty() ? makeConfig(o, in) : error;
    if (!error.empty()) return failCommand("descent", kExitInputError, error);
    std::vector<std::byte> pool(descent::PlaneSweep::workspaceBytes(in.config));
    Arena arena(pool.data(), pool.size());
    descent::PlaneSweep sweep;
    const Status init = sweep.init(in.config, arena);
    if (!init.isOk()) return failCommand("descent", kExitInputError, std::string("PlaneSweep::init: ") + init.reason());
    FloatImage depth(in.image1.width, in.image1.height);
    descent::SweepStats stats;
    const Status s = sweep.compute(in.image1.view(), in.image2.view(), in.geometry,
                                   descent::SweepOutput{depth.view(), {}, {}}, &stats);
    if (!s.isOk()) {
        return failCommand("descent", kExitInputError, std::string(s.reason()) + " (" + o.image1 + ", " + o.image2 + ", " + o.camera +
                                         "; detail " + std::to_string(s.detail()) + ")");
    }
    terrain::HeightMapConfig mc;
    mc.reducer = terrain::Reducer::kMean;
    error = planGrid(o, in, depth, mc.grid);
    if (!error.empty()) return failCommand("descent", kExitInputError, error);
    std::vector<std::byte> map_pool(terrain::HeightMap::workspaceBytes(mc));
    Arena map_arena(map_pool.data(), map_pool.size());
    terrain::HeightMap map;
    Status e = map.init(mc, map_arena);
    if (e.isOk()) e = descent::addDepthToHeightMap(depth.view(), in.geometry.camera, in.geometry.site_from_cam1, map);
    if (!e.isOk()) return failCommand("descent", kExitInputError, std::string("elevation grid: ") + e.reason());
    const FloatImage elevation = ground::elevationImage(map);
    const terrain::GridConfig& g = map.grid();
    error = writeOutputs(o, depth, elevation);
    if (!error.empty()) return failCommand("descent", kExitInputError, error);
    const double px = static_cast<double>(depth.pixels.size());
    std::printf("vtm descent: %s + %s, %dx%d, %d planes %.1f..%.1f m, scale %.3f\n", o.image1.c_str(),
                o.image2.c_str(), depth.width, depth.height, in.config.planes, in.config.depth_min_m,
                in.config.depth_max_m, stats.scale);
    std::printf("  valid %.2f %%, low parallax %.2f %%, out of view %.2f %%\n", 100.0 * stats.valid_pixels / px,
                100.0 * stats.reason_counts[3] / px, 100.0 * stats.reason_counts[2] / px);
    std::printf("  grid %dx%d cells of %.3f m, north edge %.3f m, west edge %.3f m\n", g.cols, g.rows, g.cell_m,
                g.north_edge_m, g.west_edge_m);
    return kExitOk;
}

}  // namespace vtm::tools
