// The variogram: the fit recovers known models, the experimental semivariogram of a process
// realisation recovers its range and sill, flat samples fall back, refusals are named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "kriging_fixtures.hpp"
#include "no_heap_guard.hpp"
#include "vtm/kriging/variogram.hpp"

namespace vtm::kriging {
namespace {

using test::ExponentialProcess;
using test::Kriger;

// An experimental variogram that IS the model at the bin centres (100 pairs a bin).
ExperimentalVariogram exactBins(const Variogram& v, std::int32_t bins, double max_lag_m) {
    ExperimentalVariogram ev;
    ev.bins = bins;
    ev.max_lag_m = max_lag_m;
    ev.bin_width_m = max_lag_m / bins;
    for (std::int32_t b = 0; b < bins; ++b) {
        ev.lag_m[b] = (b + 0.5) * ev.bin_width_m;
        ev.gamma_m2[b] = v.gamma(ev.lag_m[b]);
        ev.pairs[b] = 100;
    }
    return ev;
}

TEST(Variogram, TheFitRecoversAModelFromItsOwnBinsAndPicksTheRightShape) {
    for (const VariogramModel model : {VariogramModel::kSpherical, VariogramModel::kExponential}) {
        Variogram truth;
        truth.model = model;
        truth.nugget_m2 = 0.01;
        truth.partial_sill_m2 = 0.2;
        truth.range_m = 6.0;
        const ExperimentalVariogram ev = exactBins(truth, 20, 15.0);
        Variogram fit;
        vtm::test::NoHeapScope guard;
        const Status s = fitVariogramModel(ev, ModelChoice::kBest, false, 1e-6, fit);
        EXPECT_EQ(guard.heapCalls(), 0U);
        ASSERT_TRUE(s.isOk()) << s.reason();
        EXPECT_EQ(fit.model, model);
        EXPECT_FALSE(fit.fallback);
        EXPECT_NEAR(fit.range_m, 6.0, 6.0 * 1e-4);
        EXPECT_NEAR(fit.nugget_m2, 0.01, 1e-5);
        EXPECT_NEAR(fit.partial_sill_m2, 0.2, 1e-5);
    }
}

TEST(Variogram, ZeroNuggetHoldsTheNuggetAtZero) {
    Variogram truth;
    truth.model = VariogramModel::kExponential;
    truth.nugget_m2 = 0.05;
    truth.partial_sill_m2 = 0.2;
    truth.range_m = 4.0;
    Variogram fit;
    ASSERT_TRUE(fitVariogramModel(exactBins(truth, 16, 12.0), ModelChoice::kExponential, true, 1e-6, fit).isOk());
    EXPECT_EQ(fit.nugget_m2, 0.0);
    EXPECT_GT(fit.partial_sill_m2, 0.2);  // the sill absorbs what the nugget may not take
}

// One realisation of an exponential-covariance process (sigma 0.5 m, L = 1 m: sill 0.25 m^2,
// practical range 3 m) sampled at 2000 scattered points of a 32 m square.
TEST(Variogram, TheFittedVariogramOfAProcessRealisationRecoversItsRangeAndSill) {
    const ExponentialProcess process(0.5, 1.0, 400, 7U);
    const auto samples = test::samplesOf(test::scatteredPositions(2000, 0.0, 32.0, 11U), process);
    KrigingConfig config;
    config.grid = test::testGrid();
    config.variogram_bins = 20;
    config.variogram_max_lag_m = 10.0;
    config.model = ModelChoice::kExponential;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(Span<const Vec3>(samples.data(), samples.size())).isOk());
    Variogram fit;
    vtm::test::NoHeapScope guard;
    const Status s = k.kriging.fitVariogram(fit);
    EXPECT_EQ(guard.heapCalls(), 0U);
    ASSERT_TRUE(s.isOk()) << s.reason();
    // Tolerances: a single realisation over about (32 / 3)^2 = 110 ranges' worth of area
    // carries a sampling error of the sill of about sqrt(2 / 110) = 13 %.
    EXPECT_NEAR(fit.range_m, 3.0, 3.0 * 0.35);
    EXPECT_NEAR(fit.sillM2(), 0.25, 0.25 * 0.30);
    EXPECT_LT(fit.nugget_m2, 0.1 * fit.sillM2());
    std::printf("process realisation: fitted exponential range %.3f m (true 3.0), sill %.4f m^2 (true 0.25), "
                "nugget %.4f m^2\n", fit.range_m, fit.sillM2(), fit.nugget_m2);
    // With the choice left open, the fit names one of the two models and a sill near the truth.
    KrigingConfig best = config;
    best.model = ModelChoice::kBest;
    Kriger kb(best);
    ASSERT_TRUE(kb.kriging.setSamples(Span<const Vec3>(samples.data(), samples.size())).isOk());
    Variogram either;
    ASSERT_TRUE(kb.kriging.fitVariogram(either).isOk());
    EXPECT_NEAR(either.sillM2(), 0.25, 0.25 * 0.30);
    std::printf("best of both: %s, range %.3f m, sill %.4f m^2 (exponential cost %.4g, chosen cost %.4g)\n",
                either.model == VariogramModel::kSpherical ? "spherical" : "exponential", either.range_m,
                either.sillM2(), fit.fit_cost, either.fit_cost);
    EXPECT_LE(either.fit_cost, fit.fit_cost);
}

TEST(Variogram, FlatSamplesGiveTheDocumentedMinimumVariogram) {
    const auto flat = test::samplesOf(test::scatteredPositions(200, 0.0, 10.0, 3U),
                                      [](double, double) { return 1.25; });
    KrigingConfig config;
    config.grid = test::testGrid();
    config.min_sill_m2 = 1e-6;
    Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(Span<const Vec3>(flat.data(), flat.size())).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    EXPECT_TRUE(v.fallback);
    EXPECT_EQ(v.model, VariogramModel::kExponential);
    EXPECT_EQ(v.nugget_m2, 0.0);
    EXPECT_EQ(v.partial_sill_m2, 1e-6);
    EXPECT_GT(v.range_m, 0.0);
    // Kriging a flat field with it gives the flat elevation.
    NodeEstimate e;
    ASSERT_TRUE(k.kriging.estimateAt(5.3, 4.1, v, e).isOk());
    ASSERT_EQ(e.reason, NodeReason::kEstimated);
    EXPECT_NEAR(e.elevation_m, 1.25, 1e-9);
}

TEST(Variogram, RefusalsNameTheirInput) {
    KrigingConfig config;
    config.grid = test::testGrid();
    config.min_samples = 16;
    Kriger k(config);
    Variogram v;
    EXPECT_EQ(k.kriging.fitVariogram(v).code(), StatusCode::kNoData);  // no samples yet
    const auto few = test::samplesOf(test::scatteredPositions(15, 0.0, 10.0, 3U), test::analyticSurface);
    const Status s = k.kriging.setSamples(Span<const Vec3>(few.data(), few.size()));
    EXPECT_EQ(s.code(), StatusCode::kNoData);
    EXPECT_NE(std::strstr(s.reason(), "min_samples"), nullptr) << s.reason();
    // All samples at one position: no distance to bin.
    std::vector<Vec3> one(20, Vec3(3.0, 4.0, -1.0));
    ASSERT_TRUE(k.kriging.setSamples(Span<const Vec3>(one.data(), one.size())).isOk());
    const Status d = k.kriging.fitVariogram(v);
    EXPECT_EQ(d.code(), StatusCode::kDegenerate) << d.reason();
    // Fewer than three usable bins.
    ExperimentalVariogram ev;
    ev.bins = 8;
    ev.max_lag_m = 8.0;
    ev.bin_width_m = 1.0;
    ev.pairs[0] = 100;
    ev.gamma_m2[0] = 0.1;
    ev.lag_m[0] = 0.5;
    const Status few_bins = fitVariogramModel(ev, ModelChoice::kBest, false, 1e-6, v);
    EXPECT_EQ(few_bins.code(), StatusCode::kDegenerate);
    EXPECT_NE(std::strstr(few_bins.reason(), "three bins"), nullptr) << few_bins.reason();
    // A non-finite sample is named by its index.
    std::vector<Vec3> bad = test::samplesOf(test::scatteredPositions(40, 0.0, 10.0, 5U), test::analyticSurface);
    bad[17].z() = std::nan("");
    const Status nf = k.kriging.setSamples(Span<const Vec3>(bad.data(), bad.size()));
    EXPECT_EQ(nf.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(nf.detail(), 17);
    EXPECT_EQ(k.kriging.sampleCount(), 0U);
}

TEST(KrigingConfig, EachBadFieldIsNamed) {
    const auto reasonOf = [](const KrigingConfig& c) { return std::string(c.validate().reason()); };
    KrigingConfig c;
    EXPECT_TRUE(c.validate().isOk());
    c.neighbours = 17;
    EXPECT_NE(reasonOf(c).find("neighbours"), std::string::npos);
    c = KrigingConfig{};
    c.search_radius_m = 0.0;
    EXPECT_NE(reasonOf(c).find("search_radius_m"), std::string::npos);
    c = KrigingConfig{};
    c.variogram_bins = 65;
    EXPECT_NE(reasonOf(c).find("variogram_bins"), std::string::npos);
    c = KrigingConfig{};
    c.min_sill_m2 = -1.0;
    EXPECT_NE(reasonOf(c).find("min_sill_m2"), std::string::npos);
    c = KrigingConfig{};
    c.min_samples = c.max_samples + 1;
    EXPECT_NE(reasonOf(c).find("min_samples"), std::string::npos);
    c = KrigingConfig{};
    c.grid.cell_m = 0.0;
    EXPECT_EQ(c.validate().code(), StatusCode::kInvalidConfig);
    EXPECT_EQ(OrdinaryKriging::workspaceBytes(c), 0U);
    c = KrigingConfig{};
    c.variogram_max_pairs = 10;
    EXPECT_NE(reasonOf(c).find("variogram_max_pairs"), std::string::npos);
}

}  // namespace
}  // namespace vtm::kriging
