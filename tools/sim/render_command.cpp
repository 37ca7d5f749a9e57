// vtm-sim render (render_command.hpp). Ground side: heap, std::string and stdio are fine
// here; the world itself (sim/) is built into one byte buffer given to an Arena.
#include "render_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "vtm/ground/exit_codes.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/ground/sim_world.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::simtool {
namespace {

namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;

// An error for the user: one line, and the exit code.
struct Error {
    std::string message;
    int exit_code = tools::kExitInputError;
};

std::string number(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", v);
    return buffer;
}

double secondsSince(SteadyClock::time_point start) {
    return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

std::string cameraName(const sim::Scenario& s, sim::FrameRole role) {
    switch (role) {
        case sim::FrameRole::kStereoLeft: return "stereo_left";
        case sim::FrameRole::kStereoRight: return "stereo_right";
        default: return (s.kind == sim::ScenarioKind::kDescent) ? "nadir" : "mast";
    }
}

std::string frameStem(const sim::Scenario& s, const sim::ScenarioFrame& f) {
    char seq[16];
    std::snprintf(seq, sizeof(seq), "_%03u", static_cast<unsigned>(f.sequence));
    return cameraName(s, f.role) + seq;
}

// "--frames 0,2": the selected frame indices; empty = all.
bool parseFrameList(const std::string& list, int count, std::vector<bool>& selected, Error& error) {
    selected.assign(static_cast<std::size_t>(count), list.empty());
    std::stringstream in(list);
    std::string item;
    while (!list.empty() && std::getline(in, item, ',')) {
        char* end = nullptr;
        const long k = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || end != item.c_str() + item.size() || k < 0 || k >= count) {
            error = {"vtm-sim: --frames: '" + item + "' is not a frame index 0.." + std::to_string(count - 1),
                     tools::kExitUsageError};
            return false;
        }
        selected[static_cast<std::size_t>(k)] = true;
    }
    return true;
}

// The manifest's "model ..." line (docs/hal-file.md).
std::string modelLine(const CameraModel& m) {
    std::string line = "model ";
    if (m.kind == CameraModelKind::kPinholeBrown) {
        line += "pinhole";
        for (const double v : {m.fx_px, m.fy_px, m.cx_px, m.cy_px, m.k1, m.k2, m.k3, m.p1, m.p2}) line += " " + number(v);
        return line;
    }
    line += (m.kind == CameraModelKind::kCahv) ? "cahv" : "cahvor";
    const double* vectors[] = {m.c, m.a, m.h, m.v, m.o, m.r};
    const int n = (m.kind == CameraModelKind::kCahv) ? 4 : 6;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < 3; ++j) line += " " + number(vectors[i][j]);
    }
    return line;
}

bool writeText(const std::string& path, const std::string& text, Error& error) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
        error = {"vtm-sim: " + path + ": cannot write"};
        return false;
    }
    return true;
}

bool check(const ground::Outcome& outcome, Error& error) {
    if (!outcome.ok) {
        error = {"vtm-sim: " + outcome.error};
    }
    return outcome.ok;
}

// Sky / no-data pixels: the renderer's NaN becomes +inf in the files (pfm.hpp convention).
ground::FloatImage skyAsInfinity(ground::FloatImage image) {
    for (float& v : image.pixels) {
        if (std::isnan(v)) v = std::numeric_limits<float>::infinity();
    }
    return image;
}

using World = ground::SimWorld;

bool loadWorld(const std::string& path, World& w, Error& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = {"vtm-sim: " + path + ": cannot open the scenario file"};
        return false;
    }
    std::stringstream text;
    text << in.rdbuf();
    const std::string e = ground::buildSimWorld(text.str(), w);
    if (!e.empty()) {
        error = {"vtm-sim: " + path + ": " + e};
        return false;
    }
    return true;
}

struct FrameReport {
    std::string stem;
    double seconds = 0.0;
    sim::RenderStats stats;
};

bool writeImage(const std::string& base, const std::string& format, const sim::ScenarioFrame& f,
                const ground::GreyImage& img8, const ground::Grey16Image& img16, Error& error) {
    const bool eight = f.sensor.bit_depth == 8;
    if (format == "png") {
        return check(eight ? ground::writePng(base + ".png", img8) : ground::writePng16(base + ".png", img16), error);
    }
    return check(eight ? ground::writePgm8(base + ".pgm", img8) : ground::writePgm16(base + ".pgm", img16, 4095), error);
}

// The true disparity of the fixed stereo pair, with the left frame.
bool writeStereoTruth(const World& w, const sim::ScenarioFrame& f, const std::string& base, const std::string& format,
                      Error& error) {
    const int width = f.model.width_px;
    const int height = f.model.height_px;
    ground::FloatImage disparity(width, height);
    ground::GreyImage code(width, height);
    sim::StereoTruthRequest request;
    request.terrain = &w.terrain;
    request.left_model = f.model;
    request.left_pose = f.camera_pose;
    request.baseline_m = f.stereo_baseline_m;
    sim::StereoTruthOutput out;
    out.disparity_px = disparity.view();
    out.code = code.view();
    const Status st = sim::rectifiedDisparity(request, out);
    if (!st.isOk()) {
        error = {"vtm-sim: frame " + std::to_string(f.index) + ": true disparity: " + st.reason()};
        return false;
    }
    return check(ground::writePfm(base + "_disparity.pfm", skyAsInfinity(disparity)), error) &&
           check(format == "png" ? ground::writePng(base + "_disparity_code.png", code)
                                 : ground::writePgm8(base + "_disparity_code.pgm", code),
                 error);
}

bool renderOne(const World& w, const sim::ScenarioFrame& f, const std::string& outdir, const std::string& format,
               FrameReport& report, Error& error) {
    const int width = f.model.width_px;
    const int height = f.model.height_px;
    ground::GreyImage img8(f.sensor.bit_depth == 8 ? width : 0, f.sensor.bit_depth == 8 ? height : 0);
    ground::Grey16Image img16(f.sensor.bit_depth == 8 ? 0 : width, f.sensor.bit_depth == 8 ? 0 : height);
    ground::FloatImage depth(width, height);
    ground::FloatImage range(width, height);
    const sim::FrameRequest request = sim::scenarioFrameRequest(w.scenario, w.terrain, f);
    sim::FrameOutput out;
    out.image8 = img8.empty() ? ImageView<std::uint8_t>() : img8.view();
    out.image16 = img16.empty() ? ImageView<std::uint16_t>() : img16.view();
    out.truth.depth_m = depth.view();
    out.truth.range_m = range.view();
    report.stem = frameStem(w.scenario, f);
    const auto start = SteadyClock::now();
    const Status st = sim::renderFrame(request, out, &report.stats);
    report.seconds = secondsSince(start);
    if (!st.isOk()) {
        error = {"vtm-sim: frame " + std::to_string(f.index) + ": render: " + st.reason()};
        return false;
    }
    const std::string base = outdir + "/" + report.stem;
    return writeImage(base, format, f, img8, img16, error) &&
           check(ground::writePfm(base + "_depth.pfm", skyAsInfinity(depth)), error) &&
           check(ground::writePfm(base + "_range.pfm", skyAsInfinity(range)), error) &&
           (f.role != sim::FrameRole::kStereoLeft || writeStereoTruth(w, f, base, format, error));
}

ground::SimPose toGround(const sim::VehiclePose& p) {
    ground::SimPose g;
    g.timestamp_ns = p.timestamp_ns;
    std::copy(p.position_m, p.position_m + 3, g.position_m);
    std::copy(p.attitude_wxyz, p.attitude_wxyz + 4, g.attitude_wxyz);
    std::copy(p.covariance, p.covariance + 36, g.covariance);
    return g;
}

// Pose logs: one pose per distinct vehicle station, in time order.
bool writePoseLogs(const World& w, const std::string& outdir, Error& error) {
    std::vector<ground::SimPose> truth;
    std::vector<ground::SimPose> odometry;
    for (int k = 0; k < w.frames->count; ++k) {
        const sim::ScenarioFrame& f = w.frames->frames[k];
        bool seen = false;
        for (const ground::SimPose& p : truth) seen = seen || p.timestamp_ns == f.timestamp_ns;
        if (!seen) {
            truth.push_back(toGround(f.true_pose));
            odometry.push_back(toGround(f.odometry_pose));
        }
    }
    std::sort(truth.begin(), truth.end(), [](const auto& a, const auto& b) { return a.timestamp_ns < b.timestamp_ns; });
    std::sort(odometry.begin(), odometry.end(),
              [](const auto& a, const auto& b) { return a.timestamp_ns < b.timestamp_ns; });
    const std::string name = w.scenario.name;
    return writeText(outdir + "/truth.poses", ground::formatPoseLog(truth, name + ": true vehicle poses"), error) &&
           writeText(outdir + "/odometry.poses",
                     ground::formatPoseLog(odometry, name + ": odometry (seeded error model, docs/sim-scenarios.md)"),
                     error);
}

bool writeCameraFiles(const World& w, const std::vector<bool>& selected, const std::string& outdir,
                      const std::string& format, Error& error) {
    std::vector<ground::SimCameraPose> poses;
    const sim::FrameRole roles[] = {sim::FrameRole::kMain, sim::FrameRole::kStereoLeft, sim::FrameRole::kStereoRight};
    for (const sim::FrameRole role : roles) {
        std::string manifest;
        for (int k = 0; k < w.frames->count; ++k) {
            const sim::ScenarioFrame& f = w.frames->frames[k];
            if (f.role != role) continue;
            if (manifest.empty()) {
                manifest = "vtm-frames 1\n# " + std::string(w.scenario.name) + ", camera " + cameraName(w.scenario, role) +
                           " (vtm-sim render)\ncamera_id " + std::to_string(f.camera_id) + "\nwidth_px " +
                           std::to_string(f.model.width_px) + "\nheight_px " + std::to_string(f.model.height_px) +
                           "\nbit_depth " + std::to_string(f.sensor.bit_depth) + "\n" + modelLine(f.model) + "\n";
                if (!check(ground::writeCameraModelFile(outdir + "/" + cameraName(w.scenario, role) + ".cmod", f.model),
                           error)) {
                    return false;
                }
            }
            if (selected[static_cast<std::size_t>(k)]) {
                const auto exposure_us = static_cast<unsigned long long>(std::llround(f.sensor.exposure_s * 1e6));
                manifest += "frame " + std::to_string(f.sequence) + " " + std::to_string(f.timestamp_ns) + " " +
                            std::to_string(exposure_us) + " " + frameStem(w.scenario, f) + "." + format + "\n";
            }
            ground::SimCameraPose p;
            p.frame_index = f.index;
            p.camera = cameraName(w.scenario, role);
            p.timestamp_ns = f.timestamp_ns;
            ground::setSiteFromCam(p, f.camera_pose);
            poses.push_back(p);
        }
        if (!manifest.empty() && !writeText(outdir + "/" + cameraName(w.scenario, role) + ".frames", manifest, error)) {
            return false;
        }
    }
    return writeText(outdir + "/camera_poses.txt", ground::formatCameraPoses(poses), error);
}

const char* kindName(sim::ScenarioKind kind) {
    switch (kind) {
        case sim::ScenarioKind::kRoverPair: return "rover_pair";
        case sim::ScenarioKind::kDescent: return "descent";
        default: return "traverse";
    }
}

std::string readme(const World& w, const std::vector<FrameReport>& reports, const std::string& format) {
    std::string r = "# " + std::string(w.scenario.name) + " (vtm-sim render)\n\n";
    r += "Scenario kind " + std::string(kindName(w.scenario.kind)) + ", seed " + std::to_string(w.scenario.seed) +
         "; the scenario text is in scenario.scn. File formats: docs/sim-scenarios.md (\"Output files\").\n\n";
    r += "| file | contents |\n|---|---|\n";
    r += "| `<camera>_<seq>." + format + "` | frame (8-bit, or 16-bit samples 0..4095 for a 12-bit camera) |\n";
    r += "| `<camera>_<seq>_depth.pfm`, `_range.pfm` | true depth along the optical axis / range to the projection "
         "centre, metres, +inf for sky (PFM, bottom row first) |\n";
    r += "| `stereo_left_000_disparity.pfm` | rover_pair: true disparity of the fixed stereo pair, left image, "
         "x_left - x_right in pixels |\n";
    r += "| `stereo_left_000_disparity_code." + format + "` | 0 visible, 1 occluded, 2 out of the right view, 3 sky |\n";
    r += "| `<camera>.frames` | hal/file FileCamera manifest |\n| `<camera>.cmod` | camera model (parseCameraModel) |\n";
    r += "| `truth.poses`, `odometry.poses` | hal/file FileOdometry pose logs, T_site_from_vehicle |\n";
    r += "| `camera_poses.txt` | T_site_from_camera per frame |\n\n";
    char line[256];
    std::snprintf(line, sizeof(line), "Terrain built in %.2f s.\n\n| frame | time [s] | Mpixel/s | sky px | shadowed px |\n"
                  "|---|---|---|---|---|\n", w.terrain_seconds);
    r += line;
    for (const FrameReport& f : reports) {
        const double mpx = static_cast<double>(f.stats.hit_pixels + f.stats.sky_pixels) / 1e6;
        std::snprintf(line, sizeof(line), "| %s | %.3f | %.2f | %lld | %lld |\n", f.stem.c_str(), f.seconds,
                      mpx / f.seconds, static_cast<long long>(f.stats.sky_pixels),
                      static_cast<long long>(f.stats.shadowed_pixels));
        r += line;
    }
    return r;
}

int fail(const Error& error) {
    std::fprintf(stderr, "%s\n", error.message.c_str());
    return error.exit_code;
}

}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options) {
    CLI::App* cmd = app.add_subcommand("render", "render a scenario's frames and ground truth into a directory");
    cmd->add_option("scenario", options.scenario, "scenario file (sim/scenarios/*.scn)")->required();
    cmd->add_option("outdir", options.outdir, "output directory (created if missing)")->required();
    cmd->add_option("--format", options.format, "frame file format")->check(CLI::IsMember({"png", "pgm"}));
    cmd->add_option("--frames", options.frames, "comma-separated frame indices (default: all)");
    return cmd;
}

int runRender(const RenderOptions& options) {
    World w;
    Error error;
    if (!loadWorld(options.scenario, w, error)) {
        return fail(error);
    }
    std::vector<bool> selected;
    if (!parseFrameList(options.frames, w.frames->count, selected, error)) {
        return fail(error);
    }
    std::error_code ec;
    fs::create_directories(options.outdir, ec);
    if (ec) {
        return fail({"vtm-sim: " + options.outdir + ": cannot create the directory: " + ec.message()});
    }
    std::printf("%s: terrain built in %.2f s (%zu MiB)\n", w.scenario.name, w.terrain_seconds,
                w.storage.size() >> 20U);
    std::vector<FrameReport> reports;
    for (int k = 0; k < w.frames->count; ++k) {
        if (!selected[static_cast<std::size_t>(k)]) continue;
        FrameReport report;
        if (!renderOne(w, w.frames->frames[k], options.outdir, options.format, report, error)) {
            return fail(error);
        }
        const sim::ScenarioFrame& f = w.frames->frames[k];
        std::printf("frame %d %s %ux%u: %.3f s (%.2f Mpixel/s)\n", k, report.stem.c_str(), f.model.width_px,
                    f.model.height_px, report.seconds,
                    static_cast<double>(f.model.width_px) * f.model.height_px / 1e6 / report.seconds);
        reports.push_back(report);
    }
    const bool ok = writePoseLogs(w, options.outdir, error) &&
                    writeCameraFiles(w, selected, options.outdir, options.format, error) &&
                    writeText(options.outdir + "/scenario.scn", w.text, error) &&
                    writeText(options.outdir + "/README.md", readme(w, reports, options.format), error);
    return ok ? tools::kExitOk : fail(error);
}

}  // namespace vtm::simtool
