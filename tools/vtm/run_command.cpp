#include "run_command.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include "build_info.hpp"
#include "default_scenarios.hpp"
#include "run_drivers.hpp"
#include "run_panorama.hpp"
#include "run_rover.hpp"
#include "run_target.hpp"
#include "run_traverse.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "hal/event_log.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/app/descent_mapper.hpp"
#include "vtm/ground/disparity_colormap.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/sim_world.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {
namespace {

namespace fs = std::filesystem;
using ground::FloatImage;
using ground::GreyImage;

using World = ground::SimWorld;

// A scenario of kind traverse (flown by flyTraverse, not by a HAL executive).
bool isTraverse(const std::string& text) {
    sim::Scenario probe;
    return sim::parseScenario(text, probe).isOk() && probe.kind == sim::ScenarioKind::kTraverse;
}

// Reads the scenario named on the command line: a built-in name or a file.
std::string scenarioText(const std::string& name, std::string& text, std::string& label) {
    if (name == "descent") {
        text = kDefaultDescentScenario;
        label = "built-in descent (sim/scenarios/descent.scn)";
        return "";
    }
    if (name == "rover") {
        text = kDefaultRoverScenario;
        label = "built-in rover pair (sim/scenarios/rover_wide_baseline.scn)";
        return "";
    }
    if (name == "traverse") {
        text = kDefaultTraverseScenario;
        label = "built-in traverse (sim/scenarios/traverse.scn) and a descent over its terrain";
        return "";
    }
    if (name == "panorama") {
        text = kDefaultPanoramaScenario;
        label = "built-in panorama (sim/scenarios/panorama.scn at " + std::to_string(kPanoramaSidePx) + " px)";
        return "";
    }
    std::ifstream in(name, std::ios::binary);
    if (!in) {
        return name + ": cannot open (a scenario file, or one of the built-ins: rover, descent, panorama, traverse)";
    }
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
    label = name;
    return "";
}

std::string buildWorld(const RunOptions& o, std::string text, const std::string& label, World& w) {
    if (o.size_px > 0) {
        if (o.size_px < 64 || o.size_px > 2048) return "--size " + std::to_string(o.size_px) + ": must be 64..2048";
        if (!ground::setScenarioValue(text, "width_px", std::to_string(o.size_px)) ||
            !ground::setScenarioValue(text, "height_px", std::to_string(o.size_px))) {
            return label + ": no camera width_px / height_px to override with --size";
        }
    }
    std::fprintf(stderr, "vtm run: building the world of %s\n", label.c_str());
    const std::string built = ground::buildSimWorld(text, w);
    return built.empty() ? "" : label + ": " + built;
}

// The mapper's configuration for the scenario's camera: the flight defaults at 1024 x 1024
// (docs/app.md); smaller frames get a smaller window, one pyramid level and a coarser
// feature grid.
app::DescentMapperConfig configFor(const World& w) {
    const sim::ScenarioFrame& f = w.frames->frames[0];
    app::DescentMapperConfig c;
    const std::int32_t width = f.model.width_px;
    const std::int32_t height = f.model.height_px;
    c.sweep.max_width = width;  // the frame size; the refinement's capacity follows from it
    c.sweep.max_height = height;
    if (std::max(width, height) < 512) {
        c.sweep.window = 7;
        c.sweep.planes = 32;
        c.refine.matcher.pyramid_levels = 1;
        c.refine.detector.grid_cols = c.refine.detector.grid_rows = 8;
        c.refine.detector.per_cell = 4;
        c.refine.match_margin_px = c.refine.visibility_margin_px = 8.0;
    }
    c.grid_cells = std::max<std::int32_t>(16, std::max(width, height) / 2);  // cells of two pixels: the footprint
    c.mount = cameraMountOf(f);  // the calibration: the simulator's camera pose in its vehicle frame
    return c;
}

// Accuracy of one published request against the renderer's truth of image 1.
struct Accuracy {
    double valid_fraction = 0.0;
    double median_depth_rel = 0.0;
    double p90_depth_rel = 0.0;
    double elevation_rms_m = 0.0;     // map elevation - true elevation, site frame
    double elevation_bias_m = 0.0;    // its mean: the navigation's position error
    double elevation_shape_rms_m = 0.0;  // RMS about the mean: the map's own error
    double altitude_m = 0.0;  // median true depth
};

Accuracy measure(const World& w, const app::DescentProducts& p, std::vector<Vec3>& points) {
    Accuracy a;
    const sim::ScenarioFrame* f1 = ground::frameAt(w, p.frame1.timestamp_ns);
    if (f1 == nullptr) return a;
    const std::int32_t W = p.depth_m.width(), H = p.depth_m.height();
    std::vector<float> depth(static_cast<std::size_t>(W) * H), pts(3U * depth.size());
    std::vector<std::uint16_t> img(depth.size());
    sim::FrameOutput o;
    o.image16 = ImageView<std::uint16_t>(img.data(), W, H);
    o.truth.depth_m = ImageView<float>(depth.data(), W, H);
    o.truth.point_site_m = ImageView<float>(pts.data(), 3 * W, H);
    if (!sim::renderFrame(sim::scenarioFrameRequest(w.scenario, w.terrain, *f1), o, nullptr).isOk()) return a;
    const CameraModel& cam = p.geometry.camera;
    const RigidPose& pose = p.geometry.site_from_cam1;
    std::vector<double> rel, sorted_depth;
    double sum = 0.0, sum2 = 0.0;
    for (std::int32_t y = 0; y < H; ++y) {
        for (std::int32_t x = 0; x < W; ++x) {
            const auto i = static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x);
            if (std::isfinite(depth[i])) sorted_depth.push_back(depth[i]);
            const float d = p.depth_m.row(y)[x];
            if (!std::isfinite(d)) continue;
            const Vec3 ray((x - cam.cx_px) / cam.fx_px, (y - cam.cy_px) / cam.fy_px, 1.0);
            const Vec3 site = pose.R * (ray * static_cast<double>(d)) + pose.t_m;
            points.push_back(site);
            if (!std::isfinite(depth[i])) continue;
            rel.push_back(std::fabs(static_cast<double>(d - depth[i])) / depth[i]);
            const double e = static_cast<double>(pts[3 * i + 2]) - site.z();  // elevation = -z
            sum += e;
            sum2 += e * e;
        }
    }
    if (!sorted_depth.empty()) {
        std::nth_element(sorted_depth.begin(), sorted_depth.begin() + static_cast<std::ptrdiff_t>(sorted_depth.size() / 2),
                         sorted_depth.end());
        a.altitude_m = sorted_depth[sorted_depth.size() / 2];
    }
    a.valid_fraction = static_cast<double>(rel.size()) / static_cast<double>(depth.size());
    if (!rel.empty()) {
        std::sort(rel.begin(), rel.end());
        a.median_depth_rel = rel[rel.size() / 2];
        a.p90_depth_rel = rel[rel.size() * 9 / 10];
        const double n = static_cast<double>(rel.size());
        a.elevation_rms_m = std::sqrt(sum2 / n);
        a.elevation_bias_m = sum / n;
        const double var = sum2 / n - a.elevation_bias_m * a.elevation_bias_m;
        a.elevation_shape_rms_m = std::sqrt(var > 0.0 ? var : 0.0);
    }
    return a;
}

FloatImage copyOf(const ImageView<const float>& v) {
    FloatImage out(v.width(), v.height());
    for (std::int32_t y = 0; y < v.height(); ++y) {
        for (std::int32_t x = 0; x < v.width(); ++x) out.at(x, y) = v.row(y)[x];
    }
    return out;
}

GreyImage grey8Of(const ImageView<const std::uint16_t>& v, std::uint8_t bit_depth) {
    GreyImage out(v.width(), v.height());
    const int shift = bit_depth > 8 ? bit_depth - 8 : 0;
    for (std::int32_t y = 0; y < v.height(); ++y) {
        for (std::int32_t x = 0; x < v.width(); ++x) {
            out.at(x, y) = static_cast<std::uint8_t>(std::min(255, v.row(y)[x] >> shift));
        }
    }
    return out;
}

struct PairRow {
    int index = 0;
    bool ok = false;
    std::string failure;    // "stage: reason"
    Accuracy accuracy;
    double camera_height_m = 0.0;  // as the poses said
    int matches = 0, inliers = 0;
    double rot_deg = 0.0, dir_deg = 0.0;
    int planes = 0;  // swept (descent::Config::max_plane_step_px)
    long long cells = 0;
    std::vector<std::pair<std::string, double>> stage_ms;
    double seconds = 0.0;
    std::string prefix;     // file name prefix of its products
};

std::string writeProducts(const std::string& dir, const app::DescentProducts& p, const std::vector<Vec3>& points,
                          PairRow& row) {
    char name[32];
    std::snprintf(name, sizeof name, "pair%d", row.index);
    row.prefix = name;
    const std::string base = dir + "/" + row.prefix;
    const FloatImage elevation = ground::elevationImage(*p.height_map);
    const FloatImage depth = copyOf(p.depth_m);
    float dlo = 1e30f, dhi = -1e30f;
    for (const float v : depth.pixels) {
        if (std::isfinite(v)) { dlo = std::min(dlo, v); dhi = std::max(dhi, v); }
    }
    ground::Outcome r = ground::writePfm(base + "_elevation.pfm", elevation);
    if (r.ok) r = ground::writePng(base + "_elevation.png", ground::shadedRelief(ground::cropToFinite(elevation), p.height_map->grid().cell_m));
    if (r.ok) r = ground::writePfm(base + "_depth.pfm", depth);
    // Depth coloured like disparity: near (small depth) red, far purple.
    FloatImage inverse(depth.width, depth.height, 1, std::nanf(""));
    for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
        if (std::isfinite(depth.pixels[i])) inverse.pixels[i] = 1.0f / depth.pixels[i];
    }
    if (r.ok) r = ground::writePng(base + "_depth.png", ground::colorizeDisparity(inverse, 1.0f / dhi, 1.0f / dlo));
    if (r.ok) r = ground::writePng(base + "_image1.png", grey8Of(p.image1, p.frame1.bit_depth));
    if (r.ok) r = ground::writePng(base + "_image2.png", grey8Of(p.image2, p.frame2.bit_depth));
    if (r.ok) r = ground::writePly(base + "_points.ply", points);
    return r.ok ? "" : r.error;
}

std::string descentSection(const app::DescentMapperConfig& c, std::size_t memory, const std::vector<PairRow>& rows,
                           double total_s) {
    std::ostringstream md;
    md << "## Descent\n\n"
       << "The executive `DescentMapper` (fsw/app) on the descent camera's frames (SimCamera), the poses from "
          "SimOdometry with its navigation errors; figures against the renderer's depth and points of image 1.\n\n"
       << "Frames " << c.sweep.max_width << " x " << c.sweep.max_height << ", up to " << c.sweep.planes
       << " planes (at most " << c.sweep.max_plane_step_px << " px between neighbours where the parallax is largest), window "
       << c.sweep.window << ", grid " << c.grid_cells << " cells; mapper memory planned at init: " << memory
       << " bytes. Total " << total_s << " s.\n\n"
       << "| pair | camera 1 height m (navigation) | true altitude m | matches / inliers | correction rot / dir deg | "
          "planes swept | valid % | median depth error % | p90 % | elevation error: mean m / RMS about it m (% of "
          "altitude) | grid cells | time s |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    char b[512];
    for (const PairRow& r : rows) {
        if (!r.ok) {
            md << "| " << r.index << " | request failed: " << r.failure << " |||||||||||\n";
            continue;
        }
        const Accuracy& a = r.accuracy;
        std::snprintf(b, sizeof b,
                      "| %d | %.1f | %.1f | %d / %d | %.3f / %.3f | %d | %.1f | %.3f | %.3f | %+.2f / %.3f (%.3f %%) | "
                      "%lld | %.2f |\n",
                      r.index, r.camera_height_m, a.altitude_m, r.matches, r.inliers, r.rot_deg, r.dir_deg, r.planes,
                      100.0 * a.valid_fraction, 100.0 * a.median_depth_rel, 100.0 * a.p90_depth_rel, a.elevation_bias_m,
                      a.elevation_shape_rms_m, a.altitude_m > 0.0 ? 100.0 * a.elevation_shape_rms_m / a.altitude_m : 0.0,
                      r.cells, r.seconds);
        md << b;
    }
    md << "\nThe elevation map is placed by the navigation's pose of camera 1: its mean error is the navigation's "
          "position error (the images fix the relative pose, not the absolute one); the RMS about it is the map's "
          "own error.\n";
    md << "\n### Time per stage (ms, hal::MonotonicClock on this host)\n\n| pair |";
    const PairRow* first = nullptr;
    for (const PairRow& r : rows) {
        if (r.ok) { first = &r; break; }
    }
    if (first != nullptr) {
        for (const auto& s : first->stage_ms) md << " " << s.first << " |";
        md << "\n|---|";
        for (std::size_t i = 0; i < first->stage_ms.size(); ++i) md << "---|";
        md << "\n";
        for (const PairRow& r : rows) {
            if (!r.ok) continue;
            md << "| " << r.index << " |";
            for (const auto& s : r.stage_ms) { std::snprintf(b, sizeof b, " %.1f |", s.second); md << b; }
            md << "\n";
        }
    }
    md << "\n### Products\n\n";
    for (const PairRow& r : rows) {
        if (!r.ok) continue;
        md << "#### Pair " << r.index << "\n\n"
           << "Image 1, image 2 (closer), depth of image 1 (near red ... far purple, black: no depth), shaded "
              "elevation (high red ... low purple, north up):\n\n"
           << "![image 1](" << r.prefix << "_image1.png) ![image 2](" << r.prefix << "_image2.png)\n"
           << "![depth](" << r.prefix << "_depth.png) ![elevation](" << r.prefix << "_elevation.png)\n\n"
           << "Files: `" << r.prefix << "_elevation.pfm` (metres, NaN = NO_DATA), `" << r.prefix
           << "_depth.pfm`, `" << r.prefix << "_points.ply` (site frame).\n\n";
    }
    return md.str();
}

void writeReport(const std::string& dir, const std::string& md) {
    std::ofstream(dir + "/report.md") << md;
    // HTML: the same text with the pictures inline (a small Markdown subset rendered here).
    std::ostringstream html;
    html << "<!doctype html><html><head><meta charset=\"utf-8\"><title>VTM run</title><style>body{font-family:sans-serif;"
            "max-width:1200px;margin:auto}table{border-collapse:collapse}td,th{border:1px solid #999;padding:2px 6px}"
            "img{width:24%;margin:2px}</style></head><body>\n";
    std::istringstream lines(md);
    std::string line;
    bool in_table = false;
    while (std::getline(lines, line)) {
        const bool table = !line.empty() && line[0] == '|';
        if (table && line.find("|---") == 0) continue;
        if (table && !in_table) { html << "<table>\n"; in_table = true; }
        if (!table && in_table) { html << "</table>\n"; in_table = false; }
        if (table) {
            html << "<tr>";
            std::size_t p = 1;
            while (p < line.size()) {
                const std::size_t q = line.find('|', p);
                if (q == std::string::npos) break;
                html << "<td>" << line.substr(p, q - p) << "</td>";
                p = q + 1;
            }
            html << "</tr>\n";
        } else if (line.rfind("#### ", 0) == 0) {
            html << "<h4>" << line.substr(5) << "</h4>\n";
        } else if (line.rfind("### ", 0) == 0) {
            html << "<h3>" << line.substr(4) << "</h3>\n";
        } else if (line.rfind("## ", 0) == 0) {
            html << "<h2>" << line.substr(3) << "</h2>\n";
        } else if (line.rfind("# ", 0) == 0) {
            html << "<h1>" << line.substr(2) << "</h1>\n";
        } else if (line.rfind("![", 0) == 0) {
            std::size_t p = 0;
            while ((p = line.find("](", p)) != std::string::npos) {
                const std::size_t q = line.find(')', p);
                html << "<img src=\"" << line.substr(p + 2, q - p - 2) << "\">";
                p = q;
            }
            html << "\n";
        } else if (!line.empty()) {
            html << "<p>" << line << "</p>\n";
        }
    }
    if (in_table) html << "</table>\n";
    html << "</body></html>\n";
    std::ofstream(dir + "/report.html") << html.str();
}

// The descent: one request per pair of frames (0+1, 2+3, ...). Appends the report's
// section; counts the requests and the failed ones.
std::string flyDescent(const World& world, hal::Camera& camera, hal::Odometry& odometry, const std::string& out_dir,
                       std::string& section, int& requests, int& failures) {
    const auto t0 = std::chrono::steady_clock::now();
    hal::MonotonicClock clock;
    auto events = std::make_unique<hal::EventLog>();
    const app::DescentMapperConfig config = configFor(world);
    std::vector<std::byte> pool(app::DescentMapper::workspaceBytes(config) + 64U);
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::DescentMapper>();
    Status st = mapper->init(config, arena, camera, odometry, clock, *events);
    if (!st.isOk()) return std::string("DescentMapper::init: ") + st.reason();
    arena.freeze();
    requests = world.frames->count / 2;
    failures = 0;
    std::vector<PairRow> rows;
    for (int k = 0; k < requests; ++k) {
        PairRow row;
        row.index = k;
        const auto tp = std::chrono::steady_clock::now();
        st = mapper->map();
        row.seconds = secondsSince(tp);
        const app::DescentProducts* p = mapper->products();
        for (std::size_t i = 0; i < mapper->stages().size(); ++i) {
            const app::StageRecord& r = mapper->stages().at(i);
            row.stage_ms.emplace_back(app::stageName(r.stage), 1e-6 * static_cast<double>(r.duration_ns));
        }
        if (!st.isOk() || p == nullptr) {
            const app::StageRecord* f = mapper->stages().failed();
            row.failure = std::string(f != nullptr ? app::stageName(f->stage) : "?") + ": " + st.reason();
            std::fprintf(stderr, "vtm run: pair %d/%d failed at %s\n", k + 1, requests, row.failure.c_str());
            ++failures;
            rows.push_back(row);
            continue;
        }
        row.ok = true;
        row.camera_height_m = -p->geometry.site_from_cam1.t_m.z();
        row.matches = p->refine.matching.matched;
        row.inliers = p->refine.motion.inliers;
        row.rot_deg = p->refine.rotation_change_deg;
        row.dir_deg = p->refine.direction_change_deg;
        row.planes = p->sweep.planes;
        row.cells = static_cast<long long>(p->cells_filled);
        std::vector<Vec3> points;
        row.accuracy = measure(world, *p, points);
        const std::string w = writeProducts(out_dir, *p, points, row);
        if (!w.empty()) return w;
        std::fprintf(stderr, "vtm run: pair %d/%d mapped in %.1f s: %.1f %% of image 1, median depth error %.2f %%\n",
                     k + 1, requests, row.seconds, 100.0 * row.accuracy.valid_fraction,
                     100.0 * row.accuracy.median_depth_rel);
        rows.push_back(row);
    }
    section = descentSection(config, mapper->memoryBytes(), rows, secondsSince(t0));
    return "";
}

}  // namespace

CLI::App* addRunCommand(CLI::App& app, RunOptions& o) {
    CLI::App* cmd = app.add_subcommand("run", "fly a simulated mission in process and write products and a report");
    cmd->add_option("SCENARIO", o.scenario,
                    "scenario file, or a built-in: rover, descent, panorama, traverse (default: all four built-ins, "
                    "the rover pair first)");
    cmd->add_option("--out", o.out_dir, "output folder (default vtm-run)");
    cmd->add_option("--size", o.size_px, "override the camera's width and height, px (64..2048; quick runs)");
    cmd->add_flag("--link", o.link,
                  "fly against a separate `vtm-sim serve` process over a Unix socket (hal/link) instead of in process");
    cmd->add_option("--sim", o.sim_executable,
                    "the vtm-sim executable for --link and --target (default: the one next to vtm)");
    cmd->add_option("--target", o.target,
                    std::string("fly with the vtm cross-compiled for this target under qemu-user, against this host's "
                                "vtm-sim over the link: ") + runTargetNames())
        ->excludes("--link");
    cmd->add_option("--flight", o.flight_executable,
                    "the cross-compiled vtm for --target (default: build/TARGET/tools/vtm/vtm beside this build)")
        ->needs("--target");
    cmd->add_option("--expect-target", o.expect_target,
                    "refuse to run unless this vtm was built for this target (--target passes it on)");
    return cmd;
}

int runMission(const RunOptions& o) {
    if (!o.target.empty()) return runOnTarget(o);
    if (!o.expect_target.empty() && o.expect_target != kTarget) {
        return failCommand("run", kExitInputError, "--expect-target " + o.expect_target + ": this vtm was built for " + kTarget);
    }
    const bool cross = std::string(kTarget) != "host";
    const auto t0 = std::chrono::steady_clock::now();
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec) return failCommand("run", kExitInputError, o.out_dir + ": cannot create: " + ec.message());
    std::vector<std::string> names;
    if (o.scenario.empty()) {
        names = {"rover", "descent", "panorama", "traverse"};
    } else {
        names = {o.scenario};
    }
    std::string sections;
    bool links_used = false;
    bool drivers_used = false;
    std::string labels;
    int requests = 0;
    int failures = 0;
    for (const std::string& name : names) {
        std::string text;
        std::string label;
        std::string e = scenarioText(name, text, label);
        auto world = std::make_unique<World>();
        if (e.empty() && name == "panorama" && o.size_px <= 0) {
            ground::setScenarioValue(text, "width_px", std::to_string(kPanoramaSidePx));  // the built-in's size (panorama.scn: 1024)
            ground::setScenarioValue(text, "height_px", std::to_string(kPanoramaSidePx));
        }
        if (e.empty() && isTraverse(text)) {
            // The stops' maps and the descent map are built and fused in process (no
            // camera or odometry driver: run_traverse.hpp), also with --link.
            int models = 0;
            int refused = 0;
            std::string section;
            e = flyTraverse(text, o.size_px > 0 ? o.size_px : kTraverseSidePx, o.out_dir, section, models, refused);
            if (!e.empty()) return failCommand("run", kExitInputError, label + ": " + e);
            if (o.link) section += "The traverse is flown in process also with --link.\n\n";
            labels += (labels.empty() ? "" : " + ") + label;
            requests += models;  // each model added to the map is a request of the integrator
            failures += refused;
            sections += section;
            continue;
        }
        if (e.empty()) e = buildWorld(o, text, label, *world);
        if (!e.empty()) return failCommand("run", kExitInputError, e);
        std::fprintf(stderr, "vtm run: world built in %.1f s, %d frames\n", world->terrain_seconds, world->frames->count);
        labels += (labels.empty() ? "" : " + ") + label;
        std::string section;
        if (world->scenario.kind == sim::ScenarioKind::kPanorama) {
            // Stations and their pointing priors are handed to the executive (docs/app.md
            // "PanoramaMapper"): no camera or odometry driver, in process also with --link.
            bool mapped = false;
            e = flyPanorama(*world, o.out_dir, section, mapped);
            if (!e.empty()) return failCommand("run", kExitInputError, label + ": " + e);
            if (o.link) {
                section += "The panorama is flown in process also with --link: its executive takes the stations' "
                           "images and pointing priors, not frames from hal::Camera.\n\n";
            }
            requests += 1;
            failures += mapped ? 0 : 1;
            sections += section;
            continue;
        }
        links_used = links_used || o.link;
        drivers_used = true;
        const bool rover = world->scenario.kind == sim::ScenarioKind::kRoverPair;
        RunDrivers drivers;
        if (o.link) {
            const std::string sim = o.sim_executable.empty() ? defaultSimExecutable() : o.sim_executable;
            std::fprintf(stderr, "vtm run: starting %s serve (HIL link, Unix socket)\n", sim.c_str());
            // The rover pair is the first two frames (the main camera's); a descent is every frame.
            e = drivers.startLink(sim, world->text, o.out_dir + "/" + (rover ? "rover" : "descent") + ".scn",
                                  rover ? "2" : "");
        } else {
            e = drivers.startInProcess(*world);
        }
        if (!e.empty()) return failCommand("run", kExitInputError, label + ": " + e);
        if (rover) {
            bool mapped = false;
            e = flyRover(*world, drivers.camera(), drivers.odometry(), o.out_dir, section, mapped);
            requests += 1;
            failures += mapped ? 0 : 1;
        } else {
            int n = 0;
            int failed = 0;
            e = flyDescent(*world, drivers.camera(), drivers.odometry(), o.out_dir, section, n, failed);
            requests += n;
            failures += failed;
        }
        if (e.empty()) e = drivers.finish();
        if (o.link) {
            section += "Frames and poses came over the HIL link from a separate `vtm-sim serve` process (hal/link "
                       "LinkCamera, LinkOdometry on a Unix socket); link faults counted: " +
                       std::to_string(drivers.linkFaults()) + ".\n\n";
        }
        if (!e.empty()) return failCommand("run", kExitInputError, label + ": " + e);
        sections += section;
    }
    std::ostringstream md;
    md << "# VTM run: " << labels << "\n\n"
       << (cross ? std::string("Flown by the vtm built for ") + kTarget + " (" + kCompiler + " `" + kCxxFlags +
                       "`, flight policy `" + kFlightFlags + "`), run under qemu-user on the host. "
                 : std::string())
       << "Simulated worlds and frames (sim/); "
       << (!drivers_used ? ""
           : links_used  ? "frames and poses from a separate `vtm-sim serve` process over the HIL link (hal/link), "
                           "the odometry with its navigation errors; "
                         : "frames and poses in process from SimCamera and SimOdometry (hal/sim), the odometry with "
                           "its navigation errors; ")
       << "the flight executives (fsw/app). Every figure below was measured "
          "in this run against the simulator's truth. " << (requests - failures) << " of " << requests << " requests mapped; total "
       << secondsSince(t0) << " s.\n\n"
       << sections;
    writeReport(o.out_dir, md.str());
    std::printf("%s/report.md, %s/report.html: %d of %d requests mapped\n", o.out_dir.c_str(), o.out_dir.c_str(),
                requests - failures, requests);
    return failures == 0 ? kExitOk : kExitInputError;
}

}  // namespace vtm::tools
