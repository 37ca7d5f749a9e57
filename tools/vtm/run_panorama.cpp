#include "run_panorama.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "vtm/app/panorama_mapper.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {
namespace {

using ground::FloatImage;
using ground::GreyImage;

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The executive's configuration for the scenario's panorama: the flight defaults
// (docs/app.md) from 512 px up; smaller eyes get the small detector grid, one matcher level
// and small stereo windows (as tests/app/panorama_mapper_test.cpp). The elevation grid: a
// 20 m square at 0.25 m centred on the mast.
app::PanoramaMapperConfig configFor(const sim::Panorama& pano, std::int32_t side) {
    app::PanoramaMapperConfig c;
    c.max_stations = pano.count;
    c.image_width = side;
    c.image_height = side;
    c.max_observations = 16384;
    c.ring_stations = pano.columns;
    c.range_min_m = 1.0;
    c.range_max_m = 80.0;
    if (side < 512) {
        c.tiepoints.detector.grid_cols = c.tiepoints.detector.grid_rows = 8;
        c.tiepoints.detector.per_cell = 2;
        c.tiepoints.detector.max_features = 128;
        c.tiepoints.matcher.pyramid_levels = 1;
        c.tiepoints.intra_grid.cols = c.tiepoints.intra_grid.rows = 8;
        c.tiepoints.inter_grid.cols = c.tiepoints.inter_grid.rows = 8;
        c.tiepoints.parallax.max_radius_px = 50.0;
        c.tiepoints.map_side = 48;
        c.stereo.coarse_disparities = 64;
        c.stereo.coarse_window = 7;
        c.stereo.fine_radius_px = 4;
        c.stereo.matcher.window = 9;
    }
    const Vec3 mast = pano.rover.position_site_m;
    c.kriging.grid.cell_m = 0.25;
    c.kriging.grid.cols = c.kriging.grid.rows = 80;
    c.kriging.grid.north_edge_m = mast.x() + 10.0;
    c.kriging.grid.west_edge_m = mast.y() - 10.0;
    return c;
}

struct Band {
    double lo, hi;
    std::vector<double> err;
    std::int32_t nodes = 0;
};

struct Measured {
    std::vector<Band> bands;
    double ortho_coverage = 0.0;  // orthophoto nodes filled, 1-10 m from the mast
    double seam_ratio = 0.0;
    double step_across = 0.0, step_within = 0.0;
};

double rms(const std::vector<double>& v) {
    double s = 0.0;
    for (const double x : v) s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

Measured measure(const ground::SimWorld& w, const sim::Panorama& pano, const app::PanoramaProducts& p) {
    Measured m;
    m.bands = {{1.0, 2.0, {}, 0}, {2.0, 4.0, {}, 0}, {4.0, 6.0, {}, 0}, {6.0, 10.0, {}, 0}};
    const kriging::KrigedMap& map = *p.elevation;
    const terrain::GridConfig& g = map.grid();
    const Vec3 mast = pano.rover.position_site_m;
    std::int32_t seen = 0, nodes = 0;
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c < g.cols; ++c) {
            const double n = map.centreNorthM(r), e = map.centreEastM(c);
            const double d = std::hypot(n - mast.x(), e - mast.y());
            for (Band& b : m.bands) {
                if (d < b.lo || d >= b.hi) continue;
                ++b.nodes;
                ++nodes;
                seen += p.source.row(r)[c] != kriging::kNoSource ? 1 : 0;
                if (map.reason(c, r) == kriging::NodeReason::kEstimated) {
                    b.err.push_back(static_cast<double>(map.elevation(c, r)) - w.terrain.elevationAt(n, e));
                }
            }
        }
    }
    m.ortho_coverage = nodes > 0 ? static_cast<double>(seen) / nodes : 0.0;
    double across = 0.0, within = 0.0;
    std::int32_t n_across = 0, n_within = 0;
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c + 1 < g.cols; ++c) {
            const std::uint16_t a = p.source.row(r)[c], b = p.source.row(r)[c + 1];
            if (a == kriging::kNoSource || b == kriging::kNoSource) continue;
            const double step = std::fabs(static_cast<double>(p.orthophoto.row(r)[c]) - p.orthophoto.row(r)[c + 1]);
            (a == b ? within : across) += step;
            (a == b ? n_within : n_across) += 1;
        }
    }
    m.step_across = n_across > 0 ? across / n_across : 0.0;
    m.step_within = n_within > 0 ? within / n_within : 0.0;
    m.seam_ratio = m.step_within > 0.0 ? m.step_across / m.step_within : 0.0;
    return m;
}

// panorama_elevation.pfm/.png (kriged, shaded), panorama_variance.pfm, panorama_orthophoto.png,
// panorama_left0.png (the first station's left eye).
std::string writeProducts(const std::string& dir, const app::PanoramaProducts& p, const StationImages& first) {
    const kriging::KrigedMap& map = *p.elevation;
    const terrain::GridConfig& g = map.grid();
    FloatImage elevation(g.cols, g.rows, 1, std::nanf(""));
    FloatImage variance(g.cols, g.rows, 1, std::nanf(""));
    GreyImage ortho(g.cols, g.rows);
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c < g.cols; ++c) {
            elevation.at(c, r) = map.elevation(c, r);
            variance.at(c, r) = map.variance(c, r);
            ortho.at(c, r) = p.orthophoto.row(r)[c];
        }
    }
    GreyImage left(first.left.width(), first.left.height());
    for (std::int32_t y = 0; y < left.height; ++y) {
        for (std::int32_t x = 0; x < left.width; ++x) left.at(x, y) = first.left.row(y)[x];
    }
    const std::string base = dir + "/panorama_";
    ground::Outcome o = ground::writePfm(base + "elevation.pfm", elevation);
    if (o.ok) o = ground::writePng(base + "elevation.png", ground::shadedRelief(elevation, g.cell_m));
    if (o.ok) o = ground::writePfm(base + "variance.pfm", variance);
    if (o.ok) o = ground::writePng(base + "orthophoto.png", ortho);
    if (o.ok) o = ground::writePng(base + "left0.png", left);
    return o.ok ? "" : o.error;
}

std::string sectionOf(const app::PanoramaMapperConfig& c, const sim::Panorama& pano, std::int32_t side,
                      const app::PanoramaMapper& mapper, const Measured* m, double render_s, double map_s,
                      const std::string& failure) {
    std::ostringstream md;
    char b[512];
    md << "## Panorama\n\n"
       << "The executive `PanoramaMapper` (fsw/app) on a simulated mast panorama: " << pano.count << " stations ("
       << pano.columns << " columns x " << pano.tiers << " tiers), two " << side << " x " << side
       << " eyes each, handed in with the telemetry's pointing and its prior covariance (the encoder, mast and "
          "rover-attitude error model of the scenario); tie points per tier, bundle adjustment, dense stereo of each "
          "adjusted rig pair, ordinary kriging on a "
       << c.kriging.grid.cols << " x " << c.kriging.grid.rows << " grid of " << c.kriging.grid.cell_m
       << " m around the mast, orthophoto. Executive memory planned at init: " << mapper.memoryBytes()
       << " bytes. Rendering " << render_s << " s, mapping " << map_s << " s.\n\n";
    if (m == nullptr) {
        md << "The request failed: " << failure << ".\n\n";
        return md.str();
    }
    const app::PanoramaProducts& p = *mapper.products();
    std::snprintf(b, sizeof b,
                  "| tie points | observations | outliers | image RMS before -> after, px | dense samples (gate dropped) | "
                  "tie samples | variogram (sill m^2, range m) | orthophoto nodes 1-10 m | seam ratio (grey step across "
                  "/ within one image, DN) |\n|---|---|---|---|---|---|---|---|---|\n"
                  "| %u | %zu | %d | %.3f -> %.3f | %d (%d) | %d | %.4f, %.2f | %.1f %% | %.2f (%.2f / %.2f) |\n\n",
                  p.points, p.observations.size(), p.bundle.outliers, p.bundle.rms_before_px, p.bundle.rms_after_px,
                  p.dense_samples, p.dense_rejected, p.tie_samples, p.variogram.sillM2(), p.variogram.range_m,
                  100.0 * m->ortho_coverage, m->seam_ratio, m->step_across, m->step_within);
    md << b << "Kriged elevation against the simulator's terrain by distance from the mast:\n\n"
       << "| band m | nodes | estimated % | RMS m | within 0.1 m % |\n|---|---|---|---|---|\n";
    for (const Band& band : m->bands) {
        const auto good = std::count_if(band.err.begin(), band.err.end(), [](double e) { return std::fabs(e) <= 0.1; });
        std::snprintf(b, sizeof b, "| %.0f-%.0f | %d | %.1f | %.3f | %.1f |\n", band.lo, band.hi, band.nodes,
                      band.nodes > 0 ? 100.0 * static_cast<double>(band.err.size()) / band.nodes : 0.0, rms(band.err),
                      band.nodes > 0 ? 100.0 * static_cast<double>(good) / band.nodes : 0.0);
        md << b;
    }
    md << "\n### Time per stage (ms, hal::MonotonicClock on this host)\n\n|";
    for (std::size_t i = 0; i < mapper.stages().size(); ++i) md << " " << app::stageName(mapper.stages().at(i).stage) << " |";
    md << "\n|";
    for (std::size_t i = 0; i < mapper.stages().size(); ++i) md << "---|";
    md << "\n|";
    for (std::size_t i = 0; i < mapper.stages().size(); ++i) {
        std::snprintf(b, sizeof b, " %.1f |", 1e-6 * static_cast<double>(mapper.stages().at(i).duration_ns));
        md << b;
    }
    md << "\n\n### Products\n\n"
       << "The first station's left eye, the kriged elevation (shaded, high red ... low purple, north up, black: no "
          "estimate) and the orthophoto (north up):\n\n"
       << "![left eye](panorama_left0.png) ![elevation](panorama_elevation.png) ![orthophoto](panorama_orthophoto.png)\n\n"
       << "Files: `panorama_elevation.pfm` (metres, NaN = no estimate), `panorama_variance.pfm` (kriging variance, "
          "m^2), `panorama_orthophoto.png`.\n\n";
    return md.str();
}

}  // namespace

std::string flyPanorama(const ground::SimWorld& world, const std::string& out_dir, std::string& section,
                        bool& mapped) {
    mapped = false;
    const auto t0 = std::chrono::steady_clock::now();
    auto pano = std::make_unique<sim::Panorama>();
    Status st = sim::buildPanorama(world.scenario, world.terrain, *pano);
    if (!st.isOk()) return std::string("panorama: ") + st.reason();
    const std::int32_t n = world.frames->count;
    if (n != 2 * pano->count) return "panorama: the frames are not two per station";
    const std::int32_t side = world.frames->frames[0].model.width_px;
    const std::int32_t height = world.frames->frames[0].model.height_px;
    const auto px = static_cast<std::size_t>(side) * static_cast<std::size_t>(height);
    std::vector<std::vector<std::uint8_t>> pixels(static_cast<std::size_t>(n), std::vector<std::uint8_t>(px, 0U));
    for (std::int32_t k = 0; k < n; ++k) {  // frame k: station k / 2, eye k % 2
        sim::FrameOutput out;
        out.image8 = ImageView<std::uint8_t>(pixels[static_cast<std::size_t>(k)].data(), side, height);
        st = sim::renderFrame(sim::scenarioFrameRequest(world.scenario, world.terrain, world.frames->frames[k]), out,
                              nullptr);
        if (!st.isOk()) return "panorama: rendering frame " + std::to_string(k) + ": " + st.reason();
    }
    std::vector<NetworkStation> stations;
    std::vector<StationImages> images;
    for (std::int32_t s = 0; s < pano->count; ++s) {
        stations.push_back(pano->stations[s].approx);
        StationImages im;
        im.left = ImageView<const std::uint8_t>(pixels[static_cast<std::size_t>(2 * s)].data(), side, height);
        im.right = ImageView<const std::uint8_t>(pixels[static_cast<std::size_t>(2 * s + 1)].data(), side, height);
        images.push_back(im);
    }
    const double render_s = secondsSince(t0);
    const app::PanoramaMapperConfig config = configFor(*pano, std::max(side, height));
    hal::MonotonicClock clock;
    auto events = std::make_unique<hal::EventLog>();
    std::vector<std::byte> pool(app::PanoramaMapper::workspaceBytes(config) + 64U);
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::PanoramaMapper>();
    st = mapper->init(config, arena, clock, *events);
    if (!st.isOk()) return std::string("PanoramaMapper::init: ") + st.reason();
    arena.freeze();
    const auto tm = std::chrono::steady_clock::now();
    st = mapper->map(Span<const NetworkStation>(stations.data(), stations.size()),
                     Span<const StationImages>(images.data(), images.size()));
    const double map_s = secondsSince(tm);
    const app::PanoramaProducts* p = mapper->products();
    if (!st.isOk() || p == nullptr) {
        const app::StageRecord* f = mapper->stages().failed();
        const std::string failure = std::string(f != nullptr ? app::stageName(f->stage) : "?") + ": " + st.reason();
        std::fprintf(stderr, "vtm run: the panorama failed at %s\n", failure.c_str());
        section = sectionOf(config, *pano, side, *mapper, nullptr, render_s, map_s, failure);
        return "";
    }
    mapped = true;
    const Measured m = measure(world, *pano, *p);
    const std::string w = writeProducts(out_dir, *p, images[0]);
    if (!w.empty()) return w;
    std::fprintf(stderr, "vtm run: panorama mapped in %.1f s: %u tie points, image RMS %.3f -> %.3f px\n", map_s,
                 p->points, p->bundle.rms_before_px, p->bundle.rms_after_px);
    section = sectionOf(config, *pano, side, *mapper, &m, render_s, map_s, "");
    return "";
}

}  // namespace vtm::tools
