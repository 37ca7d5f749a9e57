#include "run_panorama.hpp"
#include "command_support.hpp"
#include "panorama_setup.hpp"

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

namespace vtm::tools {
namespace {

// The executive's configuration for the scenario's panorama (panorama_setup.hpp); the
// elevation grid: a 20 m square at 0.25 m centred on the mast.
app::PanoramaMapperConfig configFor(const sim::Panorama& pano, std::int32_t side) {
    PanoramaGrid grid;
    grid.centre_north_m = pano.rover.position_site_m.x();
    grid.centre_east_m = pano.rover.position_site_m.y();
    return panoramaMapperConfig(pano.count, pano.columns, side, side, grid);
}

struct Band {
    double lo, hi;
    std::vector<double> err;
    std::int32_t nodes = 0;
};

struct PanoramaMeasures {
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

PanoramaMeasures measure(const ground::SimWorld& w, const sim::Panorama& pano, const app::PanoramaProducts& p) {
    PanoramaMeasures m;
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
    const kriging::SeamSteps seams = kriging::measureSeamSteps(p.orthophoto, p.source);
    m.step_across = seams.across_dn;
    m.step_within = seams.within_dn;
    m.seam_ratio = seams.ratio();
    return m;
}

std::string sectionOf(const app::PanoramaMapperConfig& c, const sim::Panorama& pano, std::int32_t side,
                      const app::PanoramaMapper& mapper, const PanoramaMeasures* m, double render_s, double map_s,
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
    md << "\n### Time per stage (ms, hal::MonotonicClock on this host)\n\n" << panoramaStageTable(mapper);
    md << "\n### Products\n\n"
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
    const PanoramaMeasures m = measure(world, *pano, *p);
    const std::string w = writePanoramaRasters(out_dir, "panorama_", *p, images[0]);
    if (!w.empty()) return w;
    std::fprintf(stderr, "vtm run: panorama mapped in %.1f s: %u tie points, image RMS %.3f -> %.3f px\n", map_s,
                 p->points, p->bundle.rms_before_px, p->bundle.rms_after_px);
    section = sectionOf(config, *pano, side, *mapper, &m, render_s, map_s, "");
    return "";
}

}  // namespace vtm::tools
