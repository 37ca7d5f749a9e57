#include "integrate_command.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "integrate_inputs.hpp"
#include "option_pair.hpp"
#include "vtm/app/terrain_integrator.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/geotiff.hpp"
#include "vtm/ground/ply_mesh.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::tools {
namespace {

constexpr double kMarginM = 4.0;            // room around the inputs for the navigation's drift
constexpr double kRegistrationCellM = 0.2;  // the registration grid: the finest level with cells >= this

std::string shortText(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

// "--cells": ascending after sorting; each the finest times a power of two (k_out[i]).
std::string parseCells(const std::string& text, std::vector<double>& cells, std::vector<int>& k_out) {
    std::istringstream s(text);
    std::string item;
    while (std::getline(s, item, ',')) {
        std::istringstream v(item);
        double c = 0.0;
        if (!(v >> c) || !v.eof() || !(c > 0.0) || !std::isfinite(c)) {
            return "--cells '" + text + "': expected metres > 0 separated by commas, e.g. 0.25,1,4";
        }
        cells.push_back(c);
    }
    std::sort(cells.begin(), cells.end());
    if (cells.empty() || cells.size() > static_cast<std::size_t>(octree::kMaxProducts)) {
        return "--cells '" + text + "': 1 to 6 cell sizes";
    }
    for (const double c : cells) {
        const int k = static_cast<int>(std::lround(std::log2(c / cells[0])));
        if (std::fabs(std::ldexp(cells[0], k) - c) > 1e-9 * c || (k == 0 && c != cells[0]) ||
            (!k_out.empty() && k == k_out.back())) {
            return "--cells '" + text + "': each cell must be the finest times a distinct power of two";
        }
        k_out.push_back(k);
    }
    return "";
}

// The octree's cube around every input's points (moved by its pose), the products' levels
// and the registration grid (docs/tools.md "vtm integrate": the plan).
std::string planConfig(const std::vector<IntegrateInput>& inputs, const std::vector<double>& cells,
                       const std::vector<int>& k, app::IntegratorConfig& c) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    std::size_t total = 0U, largest = 0U;
    for (const IntegrateInput& in : inputs) {
        for (const Vec3& p : in.points_m) {
            const Vec3 q = in.map_from_model.R * p + in.map_from_model.t_m;
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
        total += in.points_m.size();
        largest = std::max(largest, in.points_m.size());
    }
    const double finest = cells[0];
    const double span = (hi - lo).maxCoeff() + 2.0 * kMarginM + finest;
    int depth = std::max(k.back(), 0);
    while (std::ldexp(finest, depth) < span && depth <= octree::kMaxProductLevel) ++depth;
    if (depth > octree::kMaxProductLevel || !std::isfinite(span)) {
        return "the inputs span " + shortText(span) + " m: more than 4096 cells of " + shortText(finest) +
               " m; use a coarser --cells";
    }
    c.octree.side_m = std::ldexp(finest, depth);
    c.octree.max_depth = depth;
    c.octree.north_edge_m = std::ceil((hi.x() + kMarginM) / finest) * finest;
    c.octree.west_edge_m = std::floor((lo.y() - kMarginM) / finest) * finest;
    c.octree.top_z_m = std::floor((lo.z() - kMarginM) / finest) * finest;
    c.octree.max_nodes = static_cast<std::int32_t>(std::min<std::size_t>(octree::kMaxNodes, 4U * total + 4096U));
    c.products.count = static_cast<std::int32_t>(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {  // levels ascending: cells descending
        c.products.levels[i] = depth - k[cells.size() - 1U - i];
    }
    int reg = 0;
    while (reg < depth && std::ldexp(c.octree.side_m, -(reg + 1)) >= kRegistrationCellM) ++reg;
    c.registration_level = reg;
    const double r = std::ldexp(c.octree.side_m, -reg);
    c.icp.normal_radius_m = 3.0 * r;
    c.icp.min_gate_m = 1.6 * r;
    c.icp.initial_gate_m = std::max(1.5, 6.0 * r);
    c.max_input_points = static_cast<std::int32_t>(std::min<std::size_t>(largest, app::kMaxInputPointsLimit));
    return "";
}

std::string reportLine(std::size_t i, const IntegrateInput& in, const app::AddResult& r, bool reference) {
    char b[512];
    const std::string what =
        reference ? "reference" : !r.registered ? "not registered (--no-register)" : "registered";
    std::snprintf(b, sizeof b, "model %zu %s: %s, %zu points, source %d", i, in.path.c_str(), what.c_str(),
                  in.points_m.size(), in.source);
    std::string line = b;
    if (r.registered) {
        std::snprintf(b, sizeof b, ", change %.4f deg %.4f m, overlap %.3f, rms %.4f m, %d map points", 
                      r.correction_rad * kDegPerRad, r.correction_m, r.icp.overlap, r.icp.rms_residual_m,
                      r.map_model_points);
        line += b;
    }
    std::snprintf(b, sizeof b, ", inserted %lld, outside %lld, status ok\n", static_cast<long long>(r.inserted),
                  static_cast<long long>(r.refused_outside));
    return line + b;
}

// GeoTIFF per product, the finest as a PLY mesh, the registered poses.
std::string writeOutputs(const IntegrateOptions& o, const std::vector<double>& cells,
                         const octree::HeightProducts& products, const std::vector<ground::SimCameraPose>& poses,
                         std::string& text) {
    ground::GeoTiffOptions geo;
    double lat = 0.0, lon = 0.0;
    (void)cli::parseOptionPair("--site", o.site, cli::PairRule::kAny, "in degrees", "", lat, lon);  // checked before
    geo.site = {lat, lon};
    geo.source = "vtm integrate";
    for (std::int32_t p = 0; p < products.count(); ++p) {
        const double cell = cells[cells.size() - 1U - static_cast<std::size_t>(p)];
        const std::string path = o.out_dir + "/height_" + shortText(cell) + "m.tif";
        const terrain::HeightMap& map = products.map(p);
        const ground::Outcome w = ground::writeHeightMapGeoTiff(path, map, geo, ground::HeightMapBands{true, true});
        if (!w.ok) return w.error;
        text += "product " + shortText(cell) + " m: " + std::to_string(map.grid().cols) + "x" +
                std::to_string(map.grid().rows) + " cells, " + std::to_string(map.filledCells()) + " with data -> " +
                path + "\n";
    }
    const ground::Outcome mesh = ground::writeMeshPly(o.out_dir + "/mesh.ply", products.map(products.count() - 1));
    if (!mesh.ok) return mesh.error;
    std::FILE* f = std::fopen((o.out_dir + "/poses.txt").c_str(), "w");
    const std::string posesText = ground::formatCameraPoses(poses);
    if (f == nullptr || std::fputs(posesText.c_str(), f) < 0 || std::fclose(f) != 0) {
        return o.out_dir + "/poses.txt: cannot write";
    }
    return "";
}

}  // namespace

CLI::App* addIntegrateCommand(CLI::App& app, IntegrateOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "integrate", "register terrain models to the first and fuse them (octree, ICP): height maps, mesh, report");
    cmd->add_option("INPUT", o.inputs,
                    "PATH[,pose=SPEC][,geo=FILE][,footprint=M][,source=N]: a PLY cloud or a PFM elevation map "
                    "(with geo=); the first is the reference")
        ->required();
    cmd->add_option("--out-dir", o.out_dir, "height_<cell>m.tif per cell, mesh.ply, poses.txt, report.txt")->required();
    cmd->add_option("--cells", o.cells, "product cells, metres, the finest times powers of two (default 0.25,1,4)");
    cmd->add_option("--reducer", o.reducer, "a bin's elevation: highest (default, the paper's) or mean");
    cmd->add_option("--site", o.site, "site origin LAT:LON, planetocentric degrees (default 0:0)");
    cmd->add_flag("--no-register", o.no_register, "insert every model with its pose (no ICP)");
    return cmd;
}

int runIntegrate(const IntegrateOptions& o) {
    std::vector<double> cells;
    std::vector<int> k;
    std::string bad = parseCells(o.cells, cells, k);
    double lat = 0.0, lon = 0.0;
    if (bad.empty()) bad = cli::parseOptionPair("--site", o.site, cli::PairRule::kAny, "in degrees", "-4.5:137.4", lat, lon);
    if (bad.empty() && o.reducer != "highest" && o.reducer != "mean") bad = "--reducer '" + o.reducer + "': highest or mean";
    if (bad.empty() && o.inputs.size() > static_cast<std::size_t>(octree::kMaxSources)) bad = "at most 16 inputs";
    if (!bad.empty()) return failCommand("integrate", kExitUsageError, bad);
    std::vector<IntegrateInput> inputs;
    for (std::size_t i = 0; i < o.inputs.size(); ++i) {
        ground::Result<IntegrateInput> in = loadIntegrateInput(o.inputs[i], static_cast<int>(i));
        if (!in.ok) return failCommand("integrate", kExitInputError, in.error);
        inputs.push_back(std::move(in.value));
    }
    app::IntegratorConfig config;
    config.products.reducer = o.reducer == "mean" ? terrain::Reducer::kMean : terrain::Reducer::kHighest;
    bad = planConfig(inputs, cells, k, config);
    if (!bad.empty()) return failCommand("integrate", kExitInputError, bad);
    std::vector<std::byte> pool(app::TerrainIntegrator::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    hal::ManualClock clock;
    hal::EventLog events;
    auto integrator = std::make_unique<app::TerrainIntegrator>();
    const Status init = integrator->init(config, arena, clock, events);
    if (!init.isOk()) return failCommand("integrate", kExitInputError, std::string("TerrainIntegrator::init: ") + init.reason());
    std::string text = "# vtm integrate: " + std::to_string(inputs.size()) + " models, cube " +
                       shortText(config.octree.side_m) + " m, registration cell " +
                       shortText(std::ldexp(config.octree.side_m, -config.registration_level)) + " m\n";
    std::vector<ground::SimCameraPose> poses;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const IntegrateInput& in = inputs[i];
        app::ModelInput m;
        m.points_m = Span<const Vec3>(in.points_m.data(), in.points_m.size());
        m.map_from_model_guess = in.map_from_model;
        m.footprint.footprint_m = in.footprint_m;
        m.source = static_cast<std::uint8_t>(in.source);
        m.register_model = i > 0U && !o.no_register;
        app::AddResult r;
        const Status st = integrator->addModel(m, r);
        if (!st.isOk()) {
            return failCommand("integrate", kExitInputError, in.spec + ": not integrated: " + st.reason() + " (" +
                                             std::to_string(st.detail()) + ")");
        }
        text += reportLine(i, in, r, i == 0U);
        ground::SimCameraPose pose;
        pose.frame_index = static_cast<std::uint32_t>(i);
        pose.camera = "model";
        ground::setSiteFromCam(pose, r.map_from_model);
        poses.push_back(pose);
    }
    const Status ex = integrator->extractProducts();
    if (!ex.isOk()) return failCommand("integrate", kExitInputError, std::string("products: ") + ex.reason());
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) return failCommand("integrate", kExitInputError, o.out_dir + ": cannot create (" + ec.message() + ")");
    bad = writeOutputs(o, cells, *integrator->products(), poses, text);
    if (!bad.empty()) return failCommand("integrate", kExitInputError, bad);
    std::fputs(text.c_str(), stdout);
    std::FILE* f = std::fopen((o.out_dir + "/report.txt").c_str(), "w");
    if (f == nullptr || std::fputs(text.c_str(), f) < 0 || std::fclose(f) != 0) {
        return failCommand("integrate", kExitInputError, o.out_dir + "/report.txt: cannot write");
    }
    return kExitOk;
}

}  // namespace vtm::tools
