// Determinism section "kriging" (fsw/kriging, docs/kriging.md): the variogram of 600
// scattered samples of an analytic surface (random pair subsample and all pairs), ordinary
// kriging of a 32 x 32 grid (every elevation, variance and reason) and the orthophoto of
// the kriged grid from two nadir pinhole images of a generated texture, then with a low
// oblique third view that the relief partly hides (grey, source, occluded views).
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "determinism_suite.hpp"
#include "vtm/core/hasher.hpp"
#include "sim/render.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"
#include "vtm/kriging/orthophoto.hpp"

namespace vtm::determinism {
namespace {

void hashVariogram(const Status& s, const kriging::Variogram& v, Hasher& h) noexcept {
    h.addI64(static_cast<std::int64_t>(s.code()));
    h.addI64(static_cast<std::int64_t>(v.model));
    h.addDouble(v.nugget_m2);
    h.addDouble(v.partial_sill_m2);
    h.addDouble(v.range_m);
    h.addDouble(v.fit_cost);
}

// The orthophoto of the kriged grid from two nadir pinholes 3 m up over a generated texture,
// then with a third, low oblique view whose lines of sight the relief cuts (occlusion test).
void hashOrthophoto(const kriging::KrigedMap& map, Hasher& h) noexcept {
    constexpr std::int32_t kW = 64;
    static std::uint8_t texture[2][kW * kW];
    for (std::int32_t i = 0; i < 2; ++i) {
        for (std::int32_t y = 0; y < kW; ++y) {
            for (std::int32_t x = 0; x < kW; ++x) {
                texture[i][y * kW + x] = static_cast<std::uint8_t>((x * 7 + y * 13 + i * 50 + ((x * y) & 31)) & 255);
            }
        }
    }
    NetworkStation stations[3];
    StationImages images[3];
    for (std::int32_t i = 0; i < 3; ++i) {
        stations[i].rig.model_a = makePinhole(kW, kW, 80.0);
        stations[i].rig.model_b = stations[i].rig.model_a;
        stations[i].rig.b_from_a.t_m = Vec3(-0.3, 0.0, 0.0);
        // Optical axis down (site +z), image +x east, +y south.
        stations[i].site_from_a.R << 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0;
        stations[i].site_from_a.t_m = Vec3(4.0, 2.5 + 3.0 * i, -3.0);
        images[i].left = ImageView<const std::uint8_t>(texture[i % 2], kW, kW);
    }
    stations[2].site_from_a = sim::poseLookingAt(Vec3(4.0, -1.0, -0.4), Vec3(4.0, 4.0, 0.3));
    static std::uint8_t grey[32 * 32];
    static std::uint16_t source[32 * 32];
    for (const std::size_t count : {std::size_t{2}, std::size_t{3}}) {
        kriging::OrthophotoStats stats;
        const Status s = kriging::buildOrthophoto(
            kriging::OrthophotoConfig{}, map.grid(), map.elevations(), Span<const NetworkStation>(stations, count),
            Span<const StationImages>(images, count), ImageView<std::uint8_t>(grey, 32, 32),
            ImageView<std::uint16_t>(source, 32, 32), &stats);
        h.addI64(static_cast<std::int64_t>(s.code()));
        h.addI64(stats.filled);
        h.addI64(stats.not_seen);
        h.addI64(stats.occluded_views);
        for (std::int32_t k = 0; k < 32 * 32; ++k) {
            h.addU64(grey[k]);
            h.addU64(source[k]);
        }
    }
}

}  // namespace

std::uint64_t krigingSection() noexcept {
    static Vec3 samples[600];
    Random rng(23U);
    for (Vec3& p : samples) {
        const double n = 8.0 * rng.uniform01();
        const double e = 11.0 * rng.uniform01();
        p = Vec3(n, e, -(0.5 * math::sin(0.7 * n) * math::cos(0.5 * e) + 0.05 * n));
    }
    kriging::KrigingConfig c;
    c.grid.north_edge_m = 8.0;
    c.grid.west_edge_m = 0.0;
    c.grid.cell_m = 0.25;
    c.grid.cols = 32;
    c.grid.rows = 32;
    c.max_samples = 1024;
    c.search_radius_m = 2.0;
    c.variogram_max_pairs = 5000;  // fewer than the 179,700 pairs: the random subsample
    static std::byte pool[256U << 10U];
    Arena arena(pool, sizeof pool);
    static kriging::OrdinaryKriging k;
    Hasher h;
    h.addI64(static_cast<std::int64_t>(k.init(c, arena).code()));
    h.addI64(static_cast<std::int64_t>(k.setSamples(Span<const Vec3>(samples, 600)).code()));
    kriging::Variogram v;
    hashVariogram(k.fitVariogram(v), v, h);
    kriging::KrigingStats stats;
    h.addI64(static_cast<std::int64_t>(k.krigeGrid(v, &stats).code()));
    h.addI64(stats.estimated);
    h.addI64(stats.no_samples);
    for (std::int32_t row = 0; row < 32; ++row) {
        for (std::int32_t col = 0; col < 32; ++col) {
            h.addFloat(k.map().elevation(col, row));
            h.addFloat(k.map().variance(col, row));
            h.addU64(static_cast<std::uint64_t>(k.map().reason(col, row)));
        }
    }
    hashOrthophoto(k.map(), h);
    // All pairs, the spherical model, the nugget held at zero.
    kriging::ExperimentalVariogram ev;
    kriging::PairSampling all;
    static double north[600], east[600], up[600];
    for (std::size_t i = 0; i < 600U; ++i) {
        north[i] = samples[i].x();
        east[i] = samples[i].y();
        up[i] = -samples[i].z();
    }
    all.max_lag_m = 5.0;
    all.max_pairs = 200000;
    h.addI64(static_cast<std::int64_t>(kriging::experimentalVariogram(Span<const double>(north, 600),
                                                                      Span<const double>(east, 600),
                                                                      Span<const double>(up, 600), all, ev)
                                           .code()));
    for (std::int32_t b = 0; b < ev.bins; ++b) {
        h.addDouble(ev.lag_m[b]);
        h.addDouble(ev.gamma_m2[b]);
        h.addI64(ev.pairs[b]);
    }
    kriging::Variogram sph;
    hashVariogram(kriging::fitVariogramModel(ev, kriging::ModelChoice::kSpherical, true, 1e-6, sph), sph, h);
    return h.value();
}

}  // namespace vtm::determinism
