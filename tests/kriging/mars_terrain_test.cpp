// Kriging of the simulator's Mars terrain sampled at scattered points, as stereo gives
// them: the error against the terrain at the grid nodes by sample density, beside the peer
// (inverse-distance weighting of the same neighbours).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "kriging_fixtures.hpp"
#include "no_heap_guard.hpp"
#include "sim_scene.hpp"

namespace vtm::kriging {
namespace {

TEST(MarsTerrain, KrigingErrorFallsWithSampleDensityAndStaysBelowThePeers) {
    const sim::Terrain& terrain = test::smallMarsTerrain();
    ASSERT_TRUE(terrain.built());
    const auto truth = [&terrain](double n, double e) { return terrain.elevationAt(n, e); };
    KrigingConfig config;
    config.grid.north_edge_m = 2.56;
    config.grid.west_edge_m = -2.56;
    config.grid.cell_m = 0.08;
    config.grid.cols = 64;
    config.grid.rows = 64;
    config.neighbours = 12;
    config.search_radius_m = 1.0;
    config.variogram_max_lag_m = 2.5;
    config.variogram_bins = 20;
    // The terrain's own spread over the grid, the scale of the errors below.
    double mean = 0.0, sq = 0.0;
    for (std::int32_t row = 0; row < 64; ++row) {
        for (std::int32_t col = 0; col < 64; ++col) {
            const double h = truth(2.56 - (row + 0.5) * 0.08, -2.56 + (col + 0.5) * 0.08);
            mean += h;
            sq += h * h;
        }
    }
    mean /= 4096.0;
    const double spread_m = std::sqrt(sq / 4096.0 - mean * mean);
    const double area_m2 = 5.6 * 5.6;
    double previous_rms = 1e9;
    for (const double density : {25.0, 50.0, 100.0}) {  // samples per square metre
        const auto count = static_cast<std::size_t>(density * area_m2);
        const auto samples = test::samplesOf(test::scatteredPositions(count, -2.8, 2.8, 61U), truth);
        test::Kriger k(config);
        ASSERT_TRUE(k.kriging.setSamples(Span<const Vec3>(samples.data(), samples.size())).isOk());
        Variogram v;
        KrigingStats stats;
        {
            vtm::test::NoHeapScope guard;
            ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
            ASSERT_TRUE(k.kriging.krigeGrid(v, &stats).isOk());
            EXPECT_EQ(guard.heapCalls(), 0U);
        }
        EXPECT_EQ(stats.estimated, 4096);
        double sk = 0.0, si = 0.0;
        for (std::int32_t row = 0; row < 64; ++row) {
            for (std::int32_t col = 0; col < 64; ++col) {
                const double n = k.kriging.map().centreNorthM(row);
                const double e = k.kriging.map().centreEastM(col);
                const double ek = static_cast<double>(k.kriging.map().elevation(col, row)) - truth(n, e);
                const double ei = test::idwEstimate(samples, n, e, config.neighbours, config.search_radius_m) -
                                  truth(n, e);
                sk += ek * ek;
                si += ei * ei;
            }
        }
        const double rms = std::sqrt(sk / 4096.0);
        const double idw = std::sqrt(si / 4096.0);
        std::printf("Mars terrain (spread %.3f m), %.0f samples/m^2 (%zu): kriging RMS %.4f m, IDW RMS %.4f m; "
                    "%s range %.2f m sill %.3g m^2 nugget %.3g m^2\n",
                    spread_m, density, count, rms, idw,
                    v.model == VariogramModel::kSpherical ? "spherical" : "exponential", v.range_m, v.sillM2(),
                    v.nugget_m2);
        EXPECT_LT(rms, previous_rms);
        EXPECT_LT(rms, idw);
        EXPECT_LT(rms, 0.15 * spread_m);
        previous_rms = rms;
    }
}

}  // namespace
}  // namespace vtm::kriging
