// Ordinary kriging against analytic truth and against inverse-distance weighting (the peer).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "kriging_fixtures.hpp"
#include "no_heap_guard.hpp"
#include "vtm/kriging/kriging_system.hpp"

namespace vtm::kriging {
namespace {

using test::Kriger;

KrigingConfig smoothConfig() {
    KrigingConfig c;
    c.grid = test::testGrid();
    c.neighbours = 12;
    c.search_radius_m = 4.0;
    c.variogram_bins = 16;
    c.variogram_max_lag_m = 12.0;
    return c;
}

Span<const Vec3> spanOf(const std::vector<Vec3>& v) { return Span<const Vec3>(v.data(), v.size()); }

struct GridErrors {
    double kriging_rms_m = 0.0;
    double idw_rms_m = 0.0;
    double normalised_rms = 0.0;  // error / sqrt(kriging variance)
    int nodes = 0;
};

template <typename Surface>
GridErrors gridErrors(const KrigedMap& map, const std::vector<Vec3>& samples, const Surface& truth, int k,
                      double radius_m) {
    GridErrors g;
    double sk = 0.0, si = 0.0, sz = 0.0;
    for (std::int32_t row = 0; row < map.grid().rows; ++row) {
        for (std::int32_t col = 0; col < map.grid().cols; ++col) {
            if (map.reason(col, row) != NodeReason::kEstimated) {
                continue;
            }
            const double n = map.centreNorthM(row);
            const double e = map.centreEastM(col);
            const double t = truth(n, e);
            const double ek = static_cast<double>(map.elevation(col, row)) - t;
            const double ei = test::idwEstimate(samples, n, e, k, radius_m) - t;
            sk += ek * ek;
            si += ei * ei;
            sz += ek * ek / static_cast<double>(map.variance(col, row));
            ++g.nodes;
        }
    }
    g.kriging_rms_m = std::sqrt(sk / g.nodes);
    g.idw_rms_m = std::sqrt(si / g.nodes);
    g.normalised_rms = std::sqrt(sz / g.nodes);
    return g;
}

TEST(OrdinaryKriging, ReproducesTheSamplesAtTheirPositionsWithZeroNugget) {
    const auto samples = test::samplesOf(test::scatteredPositions(1500, -1.0, 33.0, 21U), test::analyticSurface);
    KrigingConfig config = smoothConfig();
    config.zero_nugget = true;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    EXPECT_EQ(v.nugget_m2, 0.0);
    double worst_m = 0.0;
    double worst_var = 0.0;
    vtm::test::NoHeapScope guard;
    for (std::size_t i = 0; i < 300; ++i) {
        NodeEstimate e;
        ASSERT_TRUE(k.kriging.estimateAt(samples[i].x(), samples[i].y(), v, e).isOk());
        ASSERT_EQ(e.reason, NodeReason::kEstimated);
        worst_m = std::max(worst_m, std::fabs(e.elevation_m + samples[i].z()));
        worst_var = std::max(worst_var, e.variance_m2);
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_LT(worst_m, 1e-9);                   // metres, on a surface of about 1 m relief
    EXPECT_LT(worst_var, 1e-9 * v.sillM2());    // no uncertainty where the sample is
}

TEST(OrdinaryKriging, BeatsInverseDistanceWeightingOnASmoothSurface) {
    const auto samples = test::samplesOf(test::scatteredPositions(1500, -1.0, 33.0, 21U), test::analyticSurface);
    const KrigingConfig config = smoothConfig();
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    KrigingStats stats;
    {
        vtm::test::NoHeapScope guard;
        ASSERT_TRUE(k.kriging.krigeGrid(v, &stats).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(stats.estimated, 64 * 64);
    EXPECT_EQ(stats.truncated, 0);
    const GridErrors g = gridErrors(k.kriging.map(), samples, test::analyticSurface, config.neighbours,
                                    config.search_radius_m);
    std::printf("smooth surface, 1500 samples (0.88 m apart on average): kriging RMS %.4f m, IDW RMS %.4f m "
                "(%s, range %.2f m, sill %.4f m^2, nugget %.2g m^2)\n",
                g.kriging_rms_m, g.idw_rms_m, v.model == VariogramModel::kSpherical ? "spherical" : "exponential",
                v.range_m, v.sillM2(), v.nugget_m2);
    // Kriging within 6 % of the surface's own standard deviation at the nodes, and at most
    // half the peer's error.
    double sum = 0.0, sq = 0.0;
    for (std::int32_t row = 0; row < 64; ++row) {
        for (std::int32_t col = 0; col < 64; ++col) {
            const double h = test::analyticSurface(k.kriging.map().centreNorthM(row), k.kriging.map().centreEastM(col));
            sum += h;
            sq += h * h;
        }
    }
    const double spread_m = std::sqrt(sq / 4096.0 - (sum / 4096.0) * (sum / 4096.0));
    std::printf("smooth surface spread %.3f m\n", spread_m);
    EXPECT_LT(g.kriging_rms_m, 0.06 * spread_m);
    EXPECT_LT(g.kriging_rms_m, 0.5 * g.idw_rms_m);
}

TEST(OrdinaryKriging, TheKrigingVarianceIsCalibratedOnAProcessRealisation) {
    const test::ExponentialProcess process(0.5, 1.0, 400, 7U);
    const auto samples = test::samplesOf(test::scatteredPositions(2000, -1.0, 33.0, 31U), process);
    KrigingConfig config = smoothConfig();
    config.variogram_bins = 20;
    config.variogram_max_lag_m = 10.0;
    config.neighbours = 16;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    ASSERT_TRUE(k.kriging.krigeGrid(v).isOk());
    const GridErrors g = gridErrors(k.kriging.map(), samples, process, config.neighbours, config.search_radius_m);
    std::printf("exponential process (sigma 0.5 m, practical range 3 m), 2000 samples: normalised error RMS %.3f, "
                "kriging RMS %.4f m, IDW RMS %.4f m (%s wins)\n",
                g.normalised_rms, g.kriging_rms_m, g.idw_rms_m, g.kriging_rms_m < g.idw_rms_m ? "kriging" : "IDW");
    EXPECT_GT(g.normalised_rms, 0.7);
    EXPECT_LT(g.normalised_rms, 1.4);
    // A rough process leaves less to gain: kriging no worse than the peer by more than 5 %.
    EXPECT_LT(g.kriging_rms_m, 1.05 * g.idw_rms_m);
}

TEST(OrdinaryKriging, NodesWithoutSamplesInTheRadiusAreNoData) {
    // Samples only in the western half (east < 12 m); radius 2 m.
    const auto samples = test::samplesOf(test::scatteredPositions(800, 0.0, 12.0, 41U), test::analyticSurface);
    KrigingConfig config = smoothConfig();
    config.search_radius_m = 2.0;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    KrigingStats stats;
    ASSERT_TRUE(k.kriging.krigeGrid(v, &stats).isOk());
    const KrigedMap& map = k.kriging.map();
    int expected_empty = 0;
    for (std::int32_t row = 0; row < 64; ++row) {
        for (std::int32_t col = 0; col < 64; ++col) {
            const bool none = std::isnan(test::idwEstimate(samples, map.centreNorthM(row), map.centreEastM(col), 1,
                                                           config.search_radius_m));
            expected_empty += none ? 1 : 0;
            EXPECT_EQ(map.reason(col, row) == NodeReason::kNoSamples, none) << col << " " << row;
            EXPECT_EQ(terrain::isNoData(map.elevation(col, row)), none);
            EXPECT_EQ(terrain::isNoData(map.variance(col, row)), none);
        }
    }
    EXPECT_GT(expected_empty, 64 * 30);
    EXPECT_EQ(stats.no_samples, expected_empty);
    EXPECT_EQ(stats.estimated, 64 * 64 - expected_empty);
}

TEST(OrdinaryKriging, SamplesAtOnePositionMakeSingularNodesNotWrongOnes) {
    std::vector<Vec3> twice;
    for (const Vec3& p : test::samplesOf(test::scatteredPositions(20, 0.0, 32.0, 51U), test::analyticSurface)) {
        twice.push_back(p);
        twice.push_back(p + Vec3(0.0, 0.0, 0.1));  // the same position, another height
    }
    KrigingConfig config = smoothConfig();
    config.search_radius_m = 64.0;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(twice)).isOk());
    Variogram v;
    v.model = VariogramModel::kExponential;
    v.partial_sill_m2 = 0.2;
    v.range_m = 5.0;
    KrigingStats stats;
    ASSERT_TRUE(k.kriging.krigeGrid(v, &stats).isOk());
    EXPECT_EQ(stats.singular, 64 * 64);
    EXPECT_EQ(k.kriging.map().reason(10, 10), NodeReason::kSingular);
    EXPECT_TRUE(terrain::isNoData(k.kriging.map().elevation(10, 10)));
}

TEST(OrdinaryKriging, RefusalsAreNamed) {
    KrigingConfig config = smoothConfig();
    OrdinaryKriging idle;
    Variogram v;
    v.partial_sill_m2 = 1.0;
    NodeEstimate e;
    EXPECT_EQ(idle.estimateAt(1.0, 1.0, v, e).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(idle.krigeGrid(v).code(), StatusCode::kNotInitialized);
    std::vector<std::byte> small(64);
    Arena arena(small.data(), small.size());
    EXPECT_EQ(idle.init(config, arena).code(), StatusCode::kOutOfMemory);
    Kriger k(config);
    EXPECT_EQ(k.kriging.estimateAt(1.0, 1.0, v, e).code(), StatusCode::kNoData);
    const auto samples = test::samplesOf(test::scatteredPositions(100, 0.0, 32.0, 3U), test::analyticSurface);
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    Variogram bad;  // partial sill 0
    const Status s = k.kriging.estimateAt(1.0, 1.0, bad, e);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::strstr(s.reason(), "variogram"), nullptr);
    EXPECT_EQ(k.kriging.estimateAt(std::nan(""), 1.0, v, e).code(), StatusCode::kInvalidArgument);
    std::vector<Vec3> many(static_cast<std::size_t>(config.max_samples) + 1U, Vec3::Zero());
    EXPECT_EQ(k.kriging.setSamples(spanOf(many)).code(), StatusCode::kSizeMismatch);
    terrain::GridConfig big = config.grid;
    big.cols = 65;
    ASSERT_TRUE(k.kriging.setSamples(spanOf(samples)).isOk());
    EXPECT_EQ(k.kriging.krigeGrid(big, v).code(), StatusCode::kSizeMismatch);
}

TEST(OrdinaryKriging, SameBitsTwiceAndTheHeightMapTakesTheResult) {
    const auto samples = test::samplesOf(test::scatteredPositions(1500, -1.0, 33.0, 21U), test::analyticSurface);
    const KrigingConfig config = smoothConfig();
    Kriger a(config);
    Kriger b(config);
    Variogram va, vb;
    ASSERT_TRUE(a.kriging.setSamples(spanOf(samples)).isOk());
    ASSERT_TRUE(b.kriging.setSamples(spanOf(samples)).isOk());
    ASSERT_TRUE(a.kriging.fitVariogram(va).isOk());
    ASSERT_TRUE(b.kriging.fitVariogram(vb).isOk());
    EXPECT_EQ(std::memcmp(&va.range_m, &vb.range_m, sizeof(double)), 0);
    ASSERT_TRUE(a.kriging.krigeGrid(va).isOk());
    ASSERT_TRUE(b.kriging.krigeGrid(vb).isOk());
    const Span<const float> ea = a.kriging.map().elevations();
    const Span<const float> eb = b.kriging.map().elevations();
    ASSERT_EQ(ea.size(), eb.size());
    EXPECT_EQ(std::memcmp(ea.data(), eb.data(), ea.size() * sizeof(float)), 0);
    // Into the project's elevation product, node for node.
    terrain::HeightMapConfig hc;
    hc.grid = config.grid;
    std::vector<std::byte> pool(terrain::HeightMap::workspaceBytes(hc) + Arena::kDefaultAlignment);
    Arena arena(pool.data(), pool.size());
    terrain::HeightMap hm;
    ASSERT_TRUE(hm.init(hc, arena).isOk());
    ASSERT_TRUE(a.kriging.map().writeTo(hm).isOk());
    EXPECT_EQ(hm.elevation(5, 7), a.kriging.map().elevation(5, 7));
    EXPECT_EQ(hm.centreNorthM(7), a.kriging.map().centreNorthM(7));
    EXPECT_EQ(hm.filledCells(), 64 * 64);
}

// The solver against Eigen's pivoted LU on kriging-shaped systems (a zero on the diagonal).
TEST(KrigingSystem, SolvesAsEigensLuAndRefusesASingularSystem) {
    Random r(5U);
    for (int trial = 0; trial < 20; ++trial) {
        KrigingSystem s;
        s.n = kMaxSystemSize;
        Eigen::Matrix<double, kMaxSystemSize, kMaxSystemSize> a;
        Eigen::Matrix<double, kMaxSystemSize, 1> b;
        for (int i = 0; i < s.n; ++i) {
            for (int j = 0; j < s.n; ++j) {
                a(i, j) = (i == s.n - 1 || j == s.n - 1) ? 1.0 : std::exp(-std::fabs(i - j) * (0.2 + 0.05 * trial));
            }
            b(i) = r.uniform01();
        }
        a(s.n - 1, s.n - 1) = 0.0;
        b(s.n - 1) = 1.0;
        for (int i = 0; i < s.n; ++i) {
            s.b[i] = b(i);
            for (int j = 0; j < s.n; ++j) {
                s.a[i][j] = a(i, j);
            }
        }
        double x[kMaxSystemSize]{};
        ASSERT_TRUE(solveKrigingSystem(s, x));
        const Eigen::Matrix<double, kMaxSystemSize, 1> ref = a.fullPivLu().solve(b);
        for (int i = 0; i < kMaxSystemSize; ++i) {
            EXPECT_NEAR(x[i], ref(i), 1e-9 * (1.0 + std::fabs(ref(i))));
        }
    }
    KrigingSystem singular;
    singular.n = 3;
    singular.a[0][0] = singular.a[0][1] = singular.a[1][0] = singular.a[1][1] = 1.0;
    singular.a[0][2] = singular.a[1][2] = singular.a[2][0] = singular.a[2][1] = 1.0;
    double x[kMaxSystemSize]{};
    EXPECT_FALSE(solveKrigingSystem(singular, x));
}

}  // namespace
}  // namespace vtm::kriging
