// vtm panorama (panorama_command.hpp, docs/panorama-cli.md).
#include "panorama_command.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "option_pair.hpp"
#include "panorama_setup.hpp"
#include "vtm/app/panorama_mapper.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/rotation.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/geotiff.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/panorama_stations.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::tools {
namespace {

namespace fs = std::filesystem;
using ground::GreyImage;

static_assert(ground::kMaxPanoramaFileStations == bundle::kMaxStationsLimit,
              "the stations file's limit is the bundle adjustment's capacity");

std::string fixedText(double v, const char* format = "%.3f") {
    char b[48];
    std::snprintf(b, sizeof b, format, v);
    return b;
}

// Everything read from the files: the stations as the executive takes them.
struct PanoramaInputs {
    ground::PanoramaStationsFile file;
    std::vector<GreyImage> eyes;  // 2k left, 2k + 1 right
    std::vector<NetworkStation> stations;
    std::vector<StationImages> images;
    std::int32_t width = 0, height = 0;  // the largest eye model
};

std::string resolve(const std::string& dir, const std::string& name) {
    return (fs::path(name).is_absolute() || dir.empty()) ? name : (fs::path(dir) / name).string();
}

// One eye: 8-bit as it is; 16-bit shifted right by bit_depth - 8 (a 12-bit camera's
// 0..4095 to 0..255), clamped; refused when the file says bit_depth 8.
ground::Result<GreyImage> loadEye(const std::string& path, int bit_depth) {
    ground::Result<GreyImage> eight = ground::loadGrey8(path);
    if (eight.ok) return eight;
    const ground::Result<ground::Grey16Image> wide = ground::loadGrey16(path);
    if (!wide.ok) return eight;  // not readable at all: the 8-bit reader's reason
    if (bit_depth == 8) {
        return ground::Result<GreyImage>::failure(path + ": 16-bit image but the stations file says bit_depth 8");
    }
    GreyImage out(wide.value.width, wide.value.height);
    const int shift = bit_depth - 8;
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        out.pixels[i] = static_cast<std::uint8_t>(std::min(255, wide.value.pixels[i] >> shift));
    }
    return ground::Result<GreyImage>::success(std::move(out));
}

std::string loadStations(const std::string& path, PanoramaInputs& in) {
    ground::Result<ground::PanoramaStationsFile> f = ground::readPanoramaStationsFile(path);
    if (!f.ok) return f.error;
    in.file = std::move(f.value);
    const std::string dir = fs::path(path).parent_path().string();
    CameraPair rig;
    rig.b_from_a = in.file.right_from_left;
    for (int e = 0; e < 2; ++e) {
        const std::string cam = resolve(dir, e == 0 ? in.file.left_camera : in.file.right_camera);
        const ground::Outcome m = ground::readCameraModelFile(cam, e == 0 ? rig.model_a : rig.model_b);
        if (!m.ok) return path + ": " + (e == 0 ? "left_camera " : "right_camera ") + m.error;
    }
    in.width = static_cast<std::int32_t>(std::max(rig.model_a.width_px, rig.model_b.width_px));
    in.height = static_cast<std::int32_t>(std::max(rig.model_a.height_px, rig.model_b.height_px));
    for (std::size_t k = 0; k < in.file.stations.size(); ++k) {
        const ground::PanoramaStationRecord& s = in.file.stations[k];
        const std::string where = path + ": line " + std::to_string(s.images_line) + ": station " + std::to_string(k);
        for (int e = 0; e < 2; ++e) {
            const std::string image = resolve(dir, e == 0 ? s.left_image : s.right_image);
            ground::Result<GreyImage> g = loadEye(image, in.file.bit_depth);
            if (!g.ok) return where + ": " + g.error;
            const CameraModel& m = e == 0 ? rig.model_a : rig.model_b;
            if (g.value.width != static_cast<std::int32_t>(m.width_px) ||
                g.value.height != static_cast<std::int32_t>(m.height_px)) {
                return where + ": " + image + " is " + std::to_string(g.value.width) + "x" +
                       std::to_string(g.value.height) + " but the " + (e == 0 ? "left" : "right") +
                       " camera model is " + std::to_string(m.width_px) + "x" + std::to_string(m.height_px);
            }
            in.eyes.push_back(std::move(g.value));
        }
        NetworkStation st;
        st.rig = rig;
        st.site_from_a = s.approx;
        st.prior_covariance = s.prior;
        const Status v = validateNetworkStation(st);
        if (!v.isOk()) return path + ": station " + std::to_string(k) + ": " + v.reason();
        in.stations.push_back(st);
    }
    for (std::size_t k = 0; k < in.stations.size(); ++k) {
        in.images.push_back(StationImages{in.eyes[2 * k].view(), in.eyes[2 * k + 1].view()});
    }
    return "";
}

// The grid and the ring from the options; "" or the error (a usage error).
std::string planOptions(const PanoramaOptions& o, const PanoramaInputs& in, PanoramaGrid& grid, std::int32_t& ring,
                        double& range_min, double& range_max) {
    if (!(o.cell_m > 0.0 && o.cell_m <= 100.0)) return "--cell " + fixedText(o.cell_m, "%g") + ": expected (0, 100] metres";
    const double cells = std::round(o.extent_m / o.cell_m);
    if (!(o.extent_m > 0.0) || !(cells >= 2.0 && cells <= terrain::kMaxGridSide)) {
        return "--extent " + fixedText(o.extent_m, "%g") + ": expected 2.." + std::to_string(terrain::kMaxGridSide) +
               " cells of --cell a side";
    }
    grid.cell_m = o.cell_m;
    grid.extent_m = o.extent_m;
    if (!o.centre.empty()) {
        const std::string e = cli::parseOptionPair("--centre", o.centre, cli::PairRule::kAny, "site metres north:east",
                                                   "1.5:-2", grid.centre_north_m, grid.centre_east_m);
        if (!e.empty()) return e;
    } else {
        for (const NetworkStation& s : in.stations) {
            grid.centre_north_m += s.site_from_a.t_m.x() / static_cast<double>(in.stations.size());
            grid.centre_east_m += s.site_from_a.t_m.y() / static_cast<double>(in.stations.size());
        }
    }
    const auto n = static_cast<std::int32_t>(in.stations.size());
    ring = o.ring >= 0 ? o.ring : (in.file.columns > 0 && in.file.columns < n ? in.file.columns : 0);
    if (ring != 0 && (ring < 3 || ring > bundle::kMaxStationsLimit || n % ring != 0)) {
        return "--ring " + std::to_string(ring) + ": " + std::to_string(n) +
               " stations are not whole rings of 3..64 stations (0: one ring)";
    }
    return cli::parseOptionPair("--range", o.range, cli::PairRule::kPositiveIncreasing, "in metres", "1:80", range_min,
                                range_max);
}

std::string writeText(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    f.close();
    return f ? "" : path + ": cannot write";
}

// panorama_poses.txt: the adjusted eyes (vtm-camera-poses 1; frame 2k left, 2k + 1 right).
std::string posesText(const app::PanoramaProducts& p) {
    std::vector<ground::SimCameraPose> poses;
    for (std::size_t k = 0; k < p.adjusted.size(); ++k) {
        for (int e = 0; e < 2; ++e) {
            ground::SimCameraPose r;
            r.frame_index = static_cast<std::uint32_t>(2 * k + static_cast<std::size_t>(e));
            r.camera = e == 0 ? "stereo_left" : "stereo_right";
            ground::setSiteFromCam(r, siteFromEye(p.adjusted[k], e == 0 ? Eye::kLeft : Eye::kRight));
            poses.push_back(r);
        }
    }
    return ground::formatCameraPoses(poses);
}

std::string tiePointsText(const app::PanoramaProducts& p) {
    std::string t = "# vtm panorama tie points: id north_m east_m down_m sigma_m sightings state (site frame; "
                    "sigma = sqrt(trace(covariance)); state 1 adjusted, 2 single sighting, 3 not triangulated, 4 "
                    "behind a camera, 5 too few inliers)\n";
    char b[200];
    for (std::size_t i = 0; i < p.tie_points.size(); ++i) {
        const bundle::PointSolution& s = p.tie_points[i];
        if (s.state == bundle::PointState::kUnused) continue;
        std::snprintf(b, sizeof b, "%zu %.4f %.4f %.4f %.4f %u %d\n", i, s.position_m.x(), s.position_m.y(),
                      s.position_m.z(), std::sqrt(std::max(0.0, s.covariance.trace())), s.sightings,
                      static_cast<int>(s.state));
        t += b;
    }
    t += "# observations: point station eye x_px y_px residual_x_px residual_y_px weight\n";
    for (std::size_t i = 0; i < p.observations.size(); ++i) {
        const TieObservation& o = p.observations[i];
        const bundle::ObservationResidual& r = p.residuals[i];
        std::snprintf(b, sizeof b, "obs %u %u %d %.3f %.3f %.4f %.4f %.3f\n", o.point, o.image.station,
                      static_cast<int>(o.image.eye), o.pixel_px.x(), o.pixel_px.y(), r.residual_px.x(),
                      r.residual_px.y(), r.weight);
        t += b;
    }
    return t;
}

// Rotation (deg) and position (m) errors of the stations against the file's true poses:
// the mean and the largest, before (approx) and after (adjusted). "" without true poses.
std::string truthText(const PanoramaInputs& in, const app::PanoramaProducts& p) {
    double rot[2] = {0.0, 0.0}, pos[2] = {0.0, 0.0}, rot_max[2] = {0.0, 0.0}, pos_max[2] = {0.0, 0.0};
    const double n = static_cast<double>(in.stations.size());
    for (std::size_t k = 0; k < in.stations.size(); ++k) {
        const ground::PanoramaStationRecord& s = in.file.stations[k];
        if (!s.has_truth) return "";
        const RigidPose* est[2] = {&s.approx, &p.adjusted[k].site_from_a};
        for (int i = 0; i < 2; ++i) {
            const double r = 57.29577951308232 * rotationLog(est[i]->R * s.truth.R.transpose()).norm();
            const double d = (est[i]->t_m - s.truth.t_m).norm();
            rot[i] += r / n;
            pos[i] += d / n;
            rot_max[i] = std::max(rot_max[i], r);
            pos_max[i] = std::max(pos_max[i], d);
        }
    }
    return "| left eye against the file's true poses | before (approx) | after (adjusted) |\n|---|---|---|\n"
           "| rotation error, mean / max, deg | " + fixedText(rot[0]) + " / " + fixedText(rot_max[0]) + " | " +
           fixedText(rot[1]) + " / " + fixedText(rot_max[1]) + " |\n| position error, mean / max, m | " +
           fixedText(pos[0], "%.4f") + " / " + fixedText(pos_max[0], "%.4f") + " | " + fixedText(pos[1], "%.4f") + " / " +
           fixedText(pos_max[1], "%.4f") + " |\n\n";
}

std::string reportText(const PanoramaOptions& o, const PanoramaInputs& in, const app::PanoramaMapperConfig& c,
                       const app::PanoramaMapper& mapper, double load_s, double map_s) {
    const app::PanoramaProducts& p = *mapper.products();
    const terrain::GridConfig& g = p.elevation->grid();
    const std::int32_t nodes = g.cols * g.rows;
    std::string t = "# vtm panorama\n\nStations file `" + o.stations + "`: " + std::to_string(in.stations.size()) +
                    " stations, " + std::to_string(p.rings) + " ring(s) of " +
                    std::to_string(c.ring_stations == 0 ? static_cast<std::int32_t>(in.stations.size())
                                                        : c.ring_stations) +
                    ", eyes " + std::to_string(in.width) + " x " + std::to_string(in.height) + " px, dense stereo " +
                    (c.dense_stereo ? "on" : "off") + ". Elevation grid " + std::to_string(g.cols) + " x " +
                    std::to_string(g.rows) + " cells of " + fixedText(g.cell_m, "%g") + " m, north-west corner (" +
                    fixedText(g.north_edge_m) + ", " + fixedText(g.west_edge_m) + ") m. Executive memory planned at init: " +
                    std::to_string(mapper.memoryBytes()) + " bytes. Reading the files " + fixedText(load_s, "%.2f") +
                    " s, mapping " + fixedText(map_s, "%.2f") + " s.\n\n";
    t += "| tie points | observations | inliers / outliers | image RMS before -> after, px | dense points | dense "
         "samples (gate dropped) | tie samples | nodes estimated | orthophoto nodes |\n"
         "|---|---|---|---|---|---|---|---|---|\n| " +
         std::to_string(p.points) + " | " + std::to_string(p.observations.size()) + " | " +
         std::to_string(p.bundle.inliers) + " / " + std::to_string(p.bundle.outliers) + " | " +
         fixedText(p.bundle.rms_before_px) + " -> " + fixedText(p.bundle.rms_after_px) + " | " +
         std::to_string(p.dense_points) + " | " + std::to_string(p.dense_samples) + " (" +
         std::to_string(p.dense_rejected) + ") | " + std::to_string(p.tie_samples) + " | " +
         std::to_string(p.kriging.estimated) + " of " + std::to_string(nodes) + " | " +
         std::to_string(p.ortho.filled) + " |\n\n";
    t += truthText(in, p);
    t += "Time per stage (ms, hal::MonotonicClock on this host):\n\n" + panoramaStageTable(mapper) + "\n";
    t += "Files: `panorama_elevation.tif` (GeoTIFF, band 1 elevation up, m), `panorama_elevation.pfm` (m, NaN = no "
         "estimate), `panorama_elevation.png` (shaded), `panorama_variance.pfm` (kriging variance, m^2), "
         "`panorama_orthophoto.png` and `.tif`, `panorama_poses.txt` (adjusted eyes, vtm-camera-poses 1), "
         "`panorama_tiepoints.txt`.\n";
    return t;
}

std::string writeGeoTiffs(const PanoramaOptions& o, const app::PanoramaProducts& p) {
    ground::GeoTiffOptions geo;
    double lat = 0.0, lon = 0.0;
    (void)cli::parseOptionPair("--site", o.site, cli::PairRule::kAny, "in degrees", "", lat, lon);  // checked before
    geo.site = {lat, lon};
    geo.source = "vtm panorama";
    const terrain::GridConfig& g = p.elevation->grid();
    terrain::HeightMapConfig hc;
    hc.grid = g;
    std::vector<std::byte> pool(terrain::HeightMap::workspaceBytes(hc) + 64U);
    Arena arena(pool.data(), pool.size());
    terrain::HeightMap map;
    if (!map.init(hc, arena).isOk() || !p.elevation->writeTo(map).isOk()) return "the elevation map's GeoTIFF grid";
    const std::string base = o.out_dir + "/panorama_";
    ground::Outcome w = ground::writeHeightMapGeoTiff(base + "elevation.tif", map, geo);
    if (!w.ok) return w.error;
    GreyImage ortho(g.cols, g.rows);
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c < g.cols; ++c) ortho.at(c, r) = p.orthophoto.row(r)[c];
    }
    w = ground::writeOrthophotoGeoTiff(base + "orthophoto.tif", ortho, g, geo);
    return w.ok ? "" : w.error;
}

}  // namespace

CLI::App* addPanoramaCommand(CLI::App& app, PanoramaOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "panorama", "map a mast panorama from files: tie points, bundle adjustment, kriged elevation, orthophoto");
    cmd->add_option("STATIONS", o.stations, "vtm-panorama-stations 1 file (docs/panorama-cli.md)")->required();
    cmd->add_option("--out,--out-dir", o.out_dir, "output directory (created if missing)")->required();
    cmd->add_option("--cell", o.cell_m, "elevation grid cell, metres (default 0.25)");
    cmd->add_option("--extent", o.extent_m, "elevation grid side, metres (default 20)");
    cmd->add_option("--centre", o.centre, "grid centre N:E, site metres (default: the mean left-eye position)");
    cmd->add_option("--ring", o.ring, "stations per closed ring (default: the file's columns; 0: one ring)");
    cmd->add_flag("--no-dense", o.no_dense, "krige the tie points alone (no dense stereo)");
    cmd->add_option("--range", o.range, "terrain range along a ray MIN:MAX, metres (default 1:80)");
    cmd->add_option("--site", o.site, "site origin LAT:LON for the GeoTIFFs, planetocentric degrees (default 0:0)");
    return cmd;
}

int runPanorama(const PanoramaOptions& o) {
    double lat = 0.0, lon = 0.0;
    const std::string site = cli::parseOptionPair("--site", o.site, cli::PairRule::kAny, "in degrees", "-4.5:137.4",
                                                  lat, lon);
    if (!site.empty()) return failCommand("panorama", tools::kExitUsageError, site);
    const auto t0 = std::chrono::steady_clock::now();
    auto in = std::make_unique<PanoramaInputs>();
    std::string e = loadStations(o.stations, *in);
    if (!e.empty()) return failCommand("panorama", kExitInputError, e);
    PanoramaGrid grid;
    std::int32_t ring = 0;
    double range_min = 0.0, range_max = 0.0;
    e = planOptions(o, *in, grid, ring, range_min, range_max);
    if (!e.empty()) return failCommand("panorama", kExitUsageError, e);
    app::PanoramaMapperConfig c = panoramaMapperConfig(static_cast<std::int32_t>(in->stations.size()), ring,
                                                       in->width, in->height, grid);
    c.dense_stereo = !o.no_dense;
    c.range_min_m = range_min;
    c.range_max_m = range_max;
    const Status v = c.validate();
    if (!v.isOk()) return failCommand("panorama", kExitInputError, std::string("configuration refused: ") + v.reason());
    const double load_s = secondsSince(t0);
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec) return failCommand("panorama", kExitInputError, o.out_dir + ": cannot create the directory: " + ec.message());
    hal::MonotonicClock clock;
    auto events = std::make_unique<hal::EventLog>();
    std::vector<std::byte> pool(app::PanoramaMapper::workspaceBytes(c) + 64U);
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::PanoramaMapper>();
    Status st = mapper->init(c, arena, clock, *events);
    if (!st.isOk()) return failCommand("panorama", kExitInputError, std::string("PanoramaMapper::init: ") + st.reason());
    arena.freeze();
    const auto tm = std::chrono::steady_clock::now();
    st = mapper->map(Span<const NetworkStation>(in->stations.data(), in->stations.size()),
                     Span<const StationImages>(in->images.data(), in->images.size()));
    const double map_s = secondsSince(tm);
    const app::PanoramaProducts* p = mapper->products();
    if (!st.isOk() || p == nullptr) {
        const app::StageRecord* f = mapper->stages().failed();
        return failCommand("panorama", kExitInputError, o.stations + ": stage " + (f != nullptr ? app::stageName(f->stage) : "?") +
                                         " failed: " + st.reason() + " (" + std::to_string(st.detail()) + ")");
    }
    e = writePanoramaRasters(o.out_dir, "panorama_", *p, in->images[0]);
    if (e.empty()) e = writeGeoTiffs(o, *p);
    if (e.empty()) e = writeText(o.out_dir + "/panorama_poses.txt", posesText(*p));
    if (e.empty()) e = writeText(o.out_dir + "/panorama_tiepoints.txt", tiePointsText(*p));
    if (e.empty()) e = writeText(o.out_dir + "/panorama_report.md", reportText(o, *in, c, *mapper, load_s, map_s));
    if (!e.empty()) return failCommand("panorama", kExitInputError, e);
    std::printf("vtm panorama: %zu stations mapped in %.2f s: %u tie points, image RMS %.3f -> %.3f px, %d of %d "
                "nodes estimated -> %s\n",
                in->stations.size(), map_s, p->points, p->bundle.rms_before_px, p->bundle.rms_after_px,
                p->kriging.estimated, p->elevation->grid().cols * p->elevation->grid().rows, o.out_dir.c_str());
    return kExitOk;
}

}  // namespace vtm::tools
