// The bundle adjustment's refusals: bad configuration fields named, the workspace formula,
// inputs beyond the capacity or malformed, tie points that cannot be triangulated.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "panorama_network.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"

namespace vtm::bundle {
namespace {

BundleConfig smallConfig() {
    BundleConfig c;
    c.max_stations = 12;
    c.max_points = 512;
    c.max_observations = 4096;
    return c;
}

struct Small {
    Small() : pool(BundleAdjuster::workspaceBytes(smallConfig())), arena(pool.data(), pool.size()) {
        EXPECT_TRUE(adj.init(smallConfig(), arena).isOk());
        spec.candidate_points = 150;
        net = test::makeNetwork(spec);
    }
    Status run(std::uint32_t points) {
        return adj.adjust(Span<const NetworkStation>(net.approx.data(), net.approx.size()),
                          Span<const TieObservation>(net.observations.data(), net.observations.size()), points, result);
    }
    Status run() { return run(static_cast<std::uint32_t>(net.points_m.size())); }
    std::vector<std::byte> pool;
    Arena arena;
    BundleAdjuster adj;
    test::NetworkSpec spec;
    test::Network net;
    BundleResult result;
};

TEST(BundleConfig, EveryBadFieldIsNamedAndTheWorkspaceFits) {
    EXPECT_TRUE(BundleConfig{}.validate().isOk());
    struct Case {
        void (*spoil)(BundleConfig&);
        const char* field;
    };
    const Case cases[] = {
        {[](BundleConfig& c) { c.max_stations = 65; }, "bundle.max_stations"},
        {[](BundleConfig& c) { c.max_points = 0; }, "bundle.max_points"},
        {[](BundleConfig& c) { c.max_observations = 1; }, "bundle.max_observations"},
        {[](BundleConfig& c) { c.datum_station = 32; }, "bundle.datum_station"},
        {[](BundleConfig& c) { c.use_pointing_prior = false; }, "bundle.datum_station"},
        {[](BundleConfig& c) { c.sigma_px = 0.0; }, "bundle.sigma_px"},
        {[](BundleConfig& c) { c.loss = static_cast<RobustLoss>(7); }, "bundle.loss"},
        {[](BundleConfig& c) { c.robust_k = std::numeric_limits<double>::quiet_NaN(); }, "bundle.robust_k"},
        {[](BundleConfig& c) { c.outlier_sigmas = 1.0; }, "bundle.outlier_sigmas"},
        {[](BundleConfig& c) { c.max_rejection_rounds = 11; }, "bundle.max_rejection_rounds"},
        {[](BundleConfig& c) { c.max_iterations = 0; }, "bundle.max_iterations"},
        {[](BundleConfig& c) { c.max_attempts = 0; }, "bundle.max_attempts"},
        {[](BundleConfig& c) { c.initial_lambda = -1.0; }, "bundle.initial_lambda"},
        {[](BundleConfig& c) { c.converge_rotation_rad = 0.0; }, "bundle.converge_rotation_rad"},
        {[](BundleConfig& c) { c.converge_translation_m = 0.0; }, "bundle.converge_translation_m"},
        {[](BundleConfig& c) { c.min_parallax_rad = 2.0; }, "bundle.min_parallax_rad"},
    };
    for (const Case& k : cases) {
        BundleConfig c;
        k.spoil(c);
        const Status s = c.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << k.field;
        EXPECT_EQ(std::strncmp(s.reason(), k.field, std::strlen(k.field)), 0) << s.reason();
        EXPECT_EQ(BundleAdjuster::workspaceBytes(c), 0U);
    }
    // An arena of exactly workspaceBytes suffices at any alignment; half of it does not.
    const BundleConfig c = smallConfig();
    const std::size_t bytes = BundleAdjuster::workspaceBytes(c);
    std::vector<std::byte> pool(bytes + 16U);
    for (std::size_t offset = 0; offset < 16U; offset += 5U) {
        Arena arena(pool.data() + offset, bytes);
        BundleAdjuster a;
        EXPECT_TRUE(a.init(c, arena).isOk()) << offset;
    }
    Arena half(pool.data(), bytes / 2U);
    BundleAdjuster a;
    const Status s = a.init(c, half);
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(s.detail(), static_cast<std::int64_t>(bytes));
    std::printf("[ MEASURED ] workspace: default config %zu bytes, test config %zu bytes\n",
                BundleAdjuster::workspaceBytes(BundleConfig{}), bytes);
}

TEST(BundleAdjuster, InputsBeyondTheCapacityOrMalformedAreRefusedByName) {
    Small t;
    BundleResult r;
    {
        BundleAdjuster fresh;
        EXPECT_EQ(fresh.adjust(Span<const NetworkStation>(t.net.approx.data(), 2U), Span<const TieObservation>(), 0U, r).code(),
                  StatusCode::kNotInitialized);
    }
    ASSERT_TRUE(t.run().isOk());
    std::vector<NetworkStation> many(13U, t.net.approx[0]);
    Status s = t.adj.adjust(Span<const NetworkStation>(many.data(), many.size()), Span<const TieObservation>(), 0U, r);
    EXPECT_STREQ(s.reason(), "bundle.adjust: more stations than max_stations");
    EXPECT_EQ(s.detail(), 13);
    s = t.run(513U);
    EXPECT_STREQ(s.reason(), "bundle.adjust: more points than max_points");
    std::vector<TieObservation> tooMany(4097U, t.net.observations[0]);
    s = t.adj.adjust(Span<const NetworkStation>(t.net.approx.data(), t.net.approx.size()),
                     Span<const TieObservation>(tooMany.data(), tooMany.size()), 1U, r);
    EXPECT_STREQ(s.reason(), "bundle.adjust: more observations than max_observations");
    EXPECT_EQ(t.adj.stations().size(), 0U);  // nothing published

    t.net.observations[7].image.station = 12;
    s = t.run();
    EXPECT_STREQ(s.reason(), "bundle.adjust: an observation names a station (or eye) out of range");
    EXPECT_EQ(s.detail(), 7);
    t.net.observations[7].image.station = 0;
    s = t.run(t.net.observations[9].point);  // observation 9 names a point beyond the count
    EXPECT_STREQ(s.reason(), "bundle.adjust: an observation names a point out of range");
    t.net.observations[5].pixel_px.x() = std::numeric_limits<double>::infinity();
    s = t.run();
    EXPECT_STREQ(s.reason(), "bundle.adjust: an observation's pixel is not finite");
    EXPECT_EQ(s.detail(), 5);
    t.net.observations[5].pixel_px.x() = 100.0;

    const NetworkStation keep = t.net.approx[3];
    t.net.approx[3].site_from_a.R(0, 0) += 1e-3;
    s = t.run();
    EXPECT_STREQ(s.reason(), "network station: site_from_a is not rigid");
    EXPECT_EQ(s.detail(), 3);
    t.net.approx[3] = keep;
    // A prior with attitude and position perfectly correlated: singular, not a fixed parameter.
    t.net.approx[4].prior_covariance(0, 3) = std::sqrt(t.net.approx[4].prior_covariance(0, 0) * t.net.approx[4].prior_covariance(3, 3));
    t.net.approx[4].prior_covariance(3, 0) = t.net.approx[4].prior_covariance(0, 3);
    t.net.approx[4].prior_covariance(1, 3) = 0.0;
    t.net.approx[4].prior_covariance(3, 1) = 0.0;
    t.net.approx[4].prior_covariance(2, 3) = 0.0;
    t.net.approx[4].prior_covariance(3, 2) = 0.0;
    t.net.approx[4].prior_covariance(3, 4) = 0.0;
    t.net.approx[4].prior_covariance(4, 3) = 0.0;
    t.net.approx[4].prior_covariance(3, 5) = 0.0;
    t.net.approx[4].prior_covariance(5, 3) = 0.0;
    s = t.run();
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(s.detail(), 4);
    t.net.approx[4] = t.net.truth[4];
    t.net.approx[4].prior_covariance.row(5).setZero();  // a fixed height: fine
    t.net.approx[4].prior_covariance.col(5).setZero();
    s = t.run();
    EXPECT_TRUE(s.isOk()) << s.reason();
    EXPECT_EQ(t.result.fixed_parameters, 1);
    EXPECT_EQ(t.adj.stations()[4].site_from_a.t_m.z(), t.net.truth[4].site_from_a.t_m.z());
}

TEST(BundleAdjuster, TiePointsThatCannotBeTriangulatedAreExcludedWithTheirReason) {
    Small t;
    // Point A: seen once. Point B: twice in the same image at the same pixel (parallel rays).
    const auto a = static_cast<std::uint32_t>(t.net.points_m.size());
    TieObservation o = t.net.observations[0];
    o.point = a;
    t.net.observations.push_back(o);
    o.point = a + 1U;
    t.net.observations.push_back(o);
    t.net.observations.push_back(o);
    const Status s = t.run(a + 3U);  // point a + 2: never seen
    ASSERT_TRUE(s.isOk()) << s.reason();
    EXPECT_EQ(t.adj.points()[a].state, PointState::kSingleSighting);
    EXPECT_EQ(t.adj.points()[a + 1U].state, PointState::kNotTriangulated);
    EXPECT_EQ(t.adj.points()[a + 2U].state, PointState::kUnused);
    EXPECT_EQ(t.result.single_sighting, 1);
    EXPECT_EQ(t.result.not_triangulated, 1);
    EXPECT_EQ(t.result.points_excluded, 2);
    EXPECT_EQ(t.result.points_adjusted, static_cast<std::int32_t>(a));
    const std::size_t n = t.net.observations.size();
    for (std::size_t i = n - 3U; i < n; ++i) {
        EXPECT_EQ(t.adj.residuals()[i].state, ObservationState::kPointExcluded);
    }
    // Every point seen once only: nothing to adjust.
    std::vector<TieObservation> single;
    for (std::uint32_t p = 0; p < 4U; ++p) {
        o.point = p;
        single.push_back(o);
    }
    BundleResult r;
    const Status none = t.adj.adjust(Span<const NetworkStation>(t.net.approx.data(), t.net.approx.size()),
                                     Span<const TieObservation>(single.data(), single.size()), 4U, r);
    EXPECT_EQ(none.code(), StatusCode::kNoData);
    EXPECT_EQ(none.detail(), 4);
}

}  // namespace
}  // namespace vtm::bundle
