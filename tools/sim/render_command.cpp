// vtm-sim render (render_command.hpp). Ground side: heap, std::string and stdio are fine
// here; the world itself (sim/) is built into one byte buffer given to an Arena.
#include "render_command.hpp"
#include "vtm/ground/number_text.hpp"

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
#include "sim/orbital.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/ground/sim_world.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/panorama_stations.hpp"
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
        for (const double v : {m.fx_px, m.fy_px, m.cx_px, m.cy_px, m.k1, m.k2, m.k3, m.p1, m.p2}) line += " " + ground::exactNumber(v);
        return line;
    }
    line += (m.kind == CameraModelKind::kCahv) ? "cahv" : "cahvor";
    const double* vectors[] = {m.c, m.a, m.h, m.v, m.o, m.r};
    const int n = (m.kind == CameraModelKind::kCahv) ? 4 : 6;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < 3; ++j) line += " " + ground::exactNumber(vectors[i][j]);
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

// The fixed pair's true disparity needs two undistorted pinholes (panorama eyes may be any model).
bool isRectifiedPinhole(const CameraModel& m) {
    return m.kind == CameraModelKind::kPinholeBrown && m.k1 == 0.0 && m.k2 == 0.0 && m.k3 == 0.0 && m.p1 == 0.0 &&
           m.p2 == 0.0;
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
           (f.role != sim::FrameRole::kStereoLeft || !isRectifiedPinhole(f.model) ||
            writeStereoTruth(w, f, base, format, error));
}

const char* modalityName(sim::OrbitalModality m) {
    return m == sim::OrbitalModality::kThermal ? "thermal" : "visible";
}

// orbital.geo: the georeference of orbital.<fmt> (docs/sim-scenarios.md "Output files").
std::string orbitalGeoText(const sim::Scenario& s, const sim::OrbitalParams& p, const std::string& image) {
    const sim::OrbitalGeoreference geo = sim::orbitalGeoreference(p);
    std::string t = "vtm-orbital-geo 1\n";
    t += "# " + std::string(s.name) + ": orbital view (vtm-sim render). Pixel (col, row), (0, 0) = centre of the "
         "north-west pixel:\n# north_m = north0_m - row * cell_m, east_m = east0_m + col * cell_m (site frame, "
         "x north, y east, z down)\n";
    t += "image " + image + "\n";
    t += "north0_m " + ground::exactNumber(geo.north0_m) + "\neast0_m " + ground::exactNumber(geo.east0_m) + "\ncell_m " + ground::exactNumber(geo.cell_m) +
         "\n";
    t += "width_px " + std::to_string(geo.width_px) + "\nheight_px " + std::to_string(geo.height_px) + "\n";
    t += "axes col_east row_south\n";
    t += "modality " + std::string(modalityName(p.modality)) + "\n";
    t += "bit_depth " + std::to_string(p.bit_depth) + "\n";
    t += "sun_azimuth_deg " + ground::exactNumber(s.orbital.sun_azimuth_deg) + "\nsun_elevation_deg " +
         ground::exactNumber(s.orbital.sun_elevation_deg) + "\n";
    t += "to_sun_site " + ground::exactNumber(p.to_sun_site.x()) + " " + ground::exactNumber(p.to_sun_site.y()) + " " +
         ground::exactNumber(p.to_sun_site.z()) + "\n";
    if (p.modality == sim::OrbitalModality::kThermal) {
        t += "thermal_scale_k " + ground::exactNumber(p.thermal.scale_min_k) + " " + ground::exactNumber(p.thermal.scale_max_k) + "\n";
    }
    return t;
}

// orbital.<fmt>, orbital_elevation.pfm and orbital.geo of a scenario with [orbital].
bool renderOrbitalView(const World& w, const std::string& outdir, const std::string& format, double& seconds,
                       sim::OrbitalStats& stats, Error& error) {
    const sim::OrbitalParams p = sim::scenarioOrbitalParams(w.scenario);
    const bool eight = p.bit_depth == 8;
    ground::GreyImage img8(eight ? p.width_px : 0, eight ? p.height_px : 0);
    ground::Grey16Image img16(eight ? 0 : p.width_px, eight ? 0 : p.height_px);
    ground::FloatImage elevation(p.width_px, p.height_px);
    sim::OrbitalOutput out;
    out.image8 = eight ? img8.view() : ImageView<std::uint8_t>();
    out.image16 = eight ? ImageView<std::uint16_t>() : img16.view();
    out.elevation_m = elevation.view();
    const auto start = SteadyClock::now();
    const Status st = sim::renderOrbital(w.terrain, p, out, &stats);
    seconds = secondsSince(start);
    if (!st.isOk()) {
        error = {"vtm-sim: orbital: " + std::string(st.reason())};
        return false;
    }
    const std::string base = outdir + "/orbital";
    bool ok = false;
    if (format == "png") {
        ok = check(eight ? ground::writePng(base + ".png", img8) : ground::writePng16(base + ".png", img16), error);
    } else {
        ok = check(eight ? ground::writePgm8(base + ".pgm", img8) : ground::writePgm16(base + ".pgm", img16, 65535),
                   error);
    }
    return ok && check(ground::writePfm(base + "_elevation.pfm", elevation), error) &&
           writeText(base + ".geo", orbitalGeoText(w.scenario, p, "orbital." + format), error);
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

// panorama_stations.txt (docs/panorama-cli.md, docs/sim-scenarios.md "Panorama"): the file
// `vtm panorama` reads, with the rig's camera files, every station's image files (frames
// 2k and 2k + 1 are station k's eyes), approximate (telemetry) and true left-eye pose and
// prior covariance.
std::string panoramaStationsText(const World& w, const sim::Panorama& p, const std::string& format) {
    ground::PanoramaStationsFile file;
    file.left_camera = cameraName(w.scenario, sim::FrameRole::kStereoLeft) + ".cmod";
    file.right_camera = cameraName(w.scenario, sim::FrameRole::kStereoRight) + ".cmod";
    file.right_from_left = p.stations[0].approx.rig.b_from_a;
    file.bit_depth = w.scenario.sensor.bit_depth;
    file.tiers = p.tiers;
    file.columns = p.columns;
    for (int k = 0; k < p.count; ++k) {
        const sim::PanoramaStation& s = p.stations[k];
        ground::PanoramaStationRecord r;
        r.left_image = frameStem(w.scenario, w.frames->frames[2 * k]) + "." + format;
        r.right_image = frameStem(w.scenario, w.frames->frames[2 * k + 1]) + "." + format;
        r.approx = s.approx.site_from_a;
        r.has_truth = true;
        r.truth = s.truth.site_from_a;
        r.prior = s.approx.prior_covariance;
        r.tier = s.tier;
        r.column = s.column;
        r.pan_deg = s.pan_deg;
        r.tilt_deg = s.tilt_deg;
        file.stations.push_back(r);
    }
    return ground::formatPanoramaStations(
        file, {std::string(w.scenario.name) + " (vtm-sim render): the input of `vtm panorama` (docs/panorama-cli.md).",
               "Poses: T_site_from_left, x y z [m, site north east down] qw qx qy qz; approx = telemetry, true = "
               "truth;",
               "prior: 6x6 row-major covariance of (dtheta [rad], dt [m]), R_true = rotationExp(dtheta) R_approx, "
               "t_true = t_approx + dt."});
}

bool writePanoramaStations(const World& w, const std::string& outdir, const std::string& format, Error& error) {
    if (w.scenario.kind != sim::ScenarioKind::kPanorama) {
        return true;
    }
    auto panorama = std::make_unique<sim::Panorama>();
    const Status st = sim::buildPanorama(w.scenario, w.terrain, *panorama);
    if (!st.isOk()) {
        error = {"vtm-sim: panorama: " + std::string(st.reason())};
        return false;
    }
    return writeText(outdir + "/panorama_stations.txt", panoramaStationsText(w, *panorama, format), error);
}

const char* kindName(sim::ScenarioKind kind) {
    switch (kind) {
        case sim::ScenarioKind::kRoverPair: return "rover_pair";
        case sim::ScenarioKind::kDescent: return "descent";
        case sim::ScenarioKind::kPanorama: return "panorama";
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
    r += "| `camera_poses.txt` | T_site_from_camera per frame |\n";
    if (w.scenario.kind == sim::ScenarioKind::kPanorama) {
        r += "| `panorama_stations.txt` | panorama: true and approximate (telemetry) left-eye pose and prior "
             "covariance per station; `stereo_left_<k>`/`stereo_right_<k>` are the eyes of station k; "
             "`stereo_left_<k>_disparity.pfm` the pair's true disparity |\n";
    }
    if (w.scenario.orbital.enabled) {
        r += "| `orbital." + format + "`, `orbital.geo`, `orbital_elevation.pfm` | orbital view (nadir, orthographic, " +
             std::string(modalityName(w.scenario.orbital.modality)) +
             "), its georeference, the terrain elevation at each pixel centre (m) |\n";
    }
    r += "\n";
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
    if (w.scenario.orbital.enabled) {
        double seconds = 0.0;
        sim::OrbitalStats stats;
        if (!renderOrbitalView(w, options.outdir, options.format, seconds, stats, error)) {
            return fail(error);
        }
        std::printf("orbital %s %dx%d at %.3g m/px: %.3f s (%lld shadowed sub-samples)\n",
                    modalityName(w.scenario.orbital.modality), w.scenario.orbital.width_px,
                    w.scenario.orbital.height_px, w.scenario.orbital.cell_m, seconds,
                    static_cast<long long>(stats.shadowed_subsamples));
    }
    const bool ok = writePoseLogs(w, options.outdir, error) &&
                    writeCameraFiles(w, selected, options.outdir, options.format, error) &&
                    writePanoramaStations(w, options.outdir, options.format, error) &&
                    writeText(options.outdir + "/scenario.scn", w.text, error) &&
                    writeText(options.outdir + "/README.md", readme(w, reports, options.format), error);
    return ok ? tools::kExitOk : fail(error);
}

}  // namespace vtm::simtool
