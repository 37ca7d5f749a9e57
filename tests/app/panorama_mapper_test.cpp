// app::PanoramaMapper (fsw/app, docs/app.md "PanoramaMapper") on the small simulated mast
// panorama (sim/scenarios/test_panorama_small.scn: 8 columns x 2 tiers = 16 stations, under qemu the first tier only; 128 x
// 128 eyes, 60 deg): its products against the simulator's truth (image RMS after the
// adjustment, the kriged elevation against the terrain near the mast, the orthophoto's
// coverage and seams), the dense stereo's gain over the tie points alone, refusals with
// named reasons, no heap after init. Under qemu the comparison with the tie points alone
// and the second full request are left out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/clock.hpp"
#include "no_heap_guard.hpp"
#include "panorama_world.hpp"
#include "scenario_text.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/app/panorama_mapper.hpp"

namespace vtm::app {
namespace {

using World = test::PanoramaWorld;

std::string scenarioText() {
    std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/test_panorama_small.scn", std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// Under qemu the mapper gets the first tier only (8 stations, one ring): the same stages at
// half the emulated time; the two-tier network runs on the host.
#if defined(VTM_TEST_UNDER_EMULATOR)
constexpr bool kFirstTierOnly = true;
#else
constexpr bool kFirstTierOnly = false;
#endif

// The world once per process (rendering is the cost under qemu).
const World& world() {
    static std::unique_ptr<World> w;
    if (w != nullptr) return *w;
    w = std::make_unique<World>();
    // The first tier: the scenario's 8 columns (a partial ring would be refused by ring_stations).
    EXPECT_TRUE(test::buildPanoramaWorld(scenarioText(), *w, kFirstTierOnly ? 8 : -1));
    return *w;
}

// The mapper's configuration for the small panorama: 16 stations of 128 x 128, the tiers
// as rings, a 16 m square elevation grid at 0.25 m centred on the mast.
PanoramaMapperConfig smallConfig(const World& w) {
    PanoramaMapperConfig c;
    c.max_stations = 16;
    c.image_width = w.side;
    c.image_height = w.side;
    c.max_observations = 4096;
    c.ring_stations = w.panorama.columns;
    c.tiepoints.detector.grid_cols = 8;
    c.tiepoints.detector.grid_rows = 8;
    c.tiepoints.detector.per_cell = 2;
    c.tiepoints.detector.max_features = 128;
    c.tiepoints.matcher.pyramid_levels = 1;
    c.tiepoints.intra_grid.cols = c.tiepoints.intra_grid.rows = 8;
    c.tiepoints.inter_grid.cols = c.tiepoints.inter_grid.rows = 8;
    c.tiepoints.parallax.max_radius_px = 50.0;
    c.tiepoints.map_side = 48;
    c.range_min_m = 1.0;
    c.range_max_m = 30.0;
    c.stereo.coarse_disparities = 32;
    c.stereo.coarse_window = 7;
    c.stereo.fine_radius_px = 4;
    const Vec3 mast = w.panorama.rover.position_site_m;
    c.kriging.grid.cell_m = 0.25;
    c.kriging.grid.cols = c.kriging.grid.rows = 64;
    c.kriging.grid.north_edge_m = mast.x() + 8.0;
    c.kriging.grid.west_edge_m = mast.y() - 8.0;
    return c;
}

struct Figures {
    double rms_near = 0.0, rms_far = 0.0;           // kriged elevation - terrain, 1-4 m, 4-8 m from the mast
    double coverage_near = 0.0, coverage_far = 0.0;  // nodes estimated there
    double good_near = 0.0, good_far = 0.0;          // nodes estimated within 0.1 m of the terrain
    double ortho_near = 0.0;                        // orthophoto nodes filled at 1-4 m
    double seam_ratio = 0.0;                        // grey step across source borders / within one source
};

double rmsOf(const std::vector<double>& v) {
    double s = 0.0;
    for (const double x : v) s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

Figures measure(const World& w, const PanoramaProducts& p) {
    Figures f;
    const kriging::KrigedMap& map = *p.elevation;
    const terrain::GridConfig& g = map.grid();
    const Vec3 mast = w.panorama.rover.position_site_m;
    std::vector<double> near, far;
    std::int32_t n_near = 0, n_far = 0, good_near = 0, good_far = 0, ortho_near = 0;
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c < g.cols; ++c) {
            const double n = map.centreNorthM(r), e = map.centreEastM(c);
            const double d = std::hypot(n - mast.x(), e - mast.y());
            if (d < 1.0 || d > 8.0) continue;  // under the rover no camera sees the ground
            const bool is_near = d <= 4.0;
            (is_near ? n_near : n_far) += 1;
            if (is_near && p.source.row(r)[c] != kriging::kNoSource) ++ortho_near;
            if (map.reason(c, r) != kriging::NodeReason::kEstimated) continue;
            const double err = static_cast<double>(map.elevation(c, r)) - w.terrain.elevationAt(n, e);
            (is_near ? near : far).push_back(err);
            if (std::fabs(err) <= 0.1) (is_near ? good_near : good_far) += 1;
        }
    }
    f.rms_near = rmsOf(near);
    f.rms_far = rmsOf(far);
    f.coverage_near = static_cast<double>(near.size()) / n_near;
    f.coverage_far = static_cast<double>(far.size()) / n_far;
    f.good_near = static_cast<double>(good_near) / n_near;
    f.good_far = static_cast<double>(good_far) / n_far;
    f.ortho_near = static_cast<double>(ortho_near) / n_near;
    f.seam_ratio = kriging::measureSeamSteps(p.orthophoto, p.source).ratio();
    return f;
}

struct Mapping {
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    hal::ManualClock clock;
    std::unique_ptr<hal::EventLog> events = std::make_unique<hal::EventLog>();
    std::unique_ptr<PanoramaMapper> mapper = std::make_unique<PanoramaMapper>();
    Status init(const PanoramaMapperConfig& c) {
        pool.assign(PanoramaMapper::workspaceBytes(c), std::byte{0});
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        return mapper->init(c, *arena, clock, *events);
    }
    Status map(const World& w) {
        return mapper->map(Span<const NetworkStation>(w.approx.data(), w.approx.size()),
                           Span<const StationImages>(w.images.data(), w.images.size()));
    }
};

void printFigures(const char* label, const PanoramaProducts& p, const Figures& f) {
    std::printf("[ panorama ] %s: %u tie points, %d observations, image RMS %.3f -> %.3f px; %d dense samples "
                "(%d dropped by the gate) from %d points (%d stations with points, %d around their tie points' plane), %d tie samples; kriged "
                "RMS vs terrain %.3f m at 1-4 m (%.0f %% estimated, %.0f %% within 0.1 m), %.3f m at 4-8 m (%.0f %%, %.0f %%); "
                "orthophoto %.0f %% at 1-4 m, seam ratio %.2f\n",
                label, p.points, static_cast<int>(p.observations.size()), p.bundle.rms_before_px,
                p.bundle.rms_after_px, p.dense_samples, p.dense_rejected, p.dense_points, p.dense_stations, p.plane_stations, p.tie_samples,
                f.rms_near,
                100.0 * f.coverage_near, 100.0 * f.good_near, f.rms_far, 100.0 * f.coverage_far, 100.0 * f.good_far,
                100.0 * f.ortho_near, f.seam_ratio);
}

TEST(PanoramaMapper, SmallPanoramaAgainstTheTruthWithoutHeapAfterInit) {
    const World& w = world();
    ASSERT_FALSE(::testing::Test::HasFailure());
    Mapping run;
    ASSERT_TRUE(run.init(smallConfig(w)).isOk());
    EXPECT_EQ(run.mapper->products(), nullptr);
    EXPECT_LE(run.mapper->memoryBytes(), PanoramaMapper::workspaceBytes(smallConfig(w)));
    std::printf("[ panorama ] memory: workspaceBytes %zu, init took %zu, mapper object %zu bytes\n",
                PanoramaMapper::workspaceBytes(smallConfig(w)), run.mapper->memoryBytes(), sizeof(PanoramaMapper));
    Status st;
    {
        test::NoHeapScope guard;
        st = run.map(w);
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    const StageRecord* failed = run.mapper->stages().failed();
    ASSERT_TRUE(st.isOk()) << (failed != nullptr ? stageName(failed->stage) : "") << ": " << st.reason();
    const PanoramaProducts* p = run.mapper->products();
    ASSERT_NE(p, nullptr);
    ASSERT_EQ(run.mapper->stages().size(), 5U);
    EXPECT_EQ(run.mapper->stages().at(0).stage, Stage::kTiePoints);
    EXPECT_EQ(run.mapper->stages().at(4).stage, Stage::kOrthophoto);
    const Figures f = measure(w, *p);
    printFigures("dense + tie points", *p, f);
    EXPECT_EQ(p->rings, static_cast<std::int32_t>(w.approx.size()) / w.panorama.columns);
    EXPECT_LE(p->bundle.rms_after_px, 0.5);
    EXPECT_LT(p->bundle.rms_after_px, p->bundle.rms_before_px);
    EXPECT_GT(p->dense_samples, 0);
    EXPECT_LE(f.rms_near, 0.1);
    EXPECT_GE(f.coverage_near, 0.8);
    EXPECT_GE(f.ortho_near, 0.8);
    EXPECT_LE(f.seam_ratio, 1.5);
}

// Issue 23 item 4: the dense elevation from the adjusted network adds coverage over the tie
// points alone: the nodes 1-8 m from the mast whose kriged elevation lies within 0.1 m of
// the terrain, with and without the dense stage, in the same run, with a 0.5 m
// neighbourhood (at the default 2 m the tie points of this panorama already reach every node).
TEST(PanoramaMapper, DenseStereoAddsCoverageOverTheTiePointsAlone) {
#if defined(VTM_TEST_UNDER_EMULATOR)
    GTEST_SKIP() << "host only: two more requests; the stages' bits on every target come from the first test";
#endif
    const World& w = world();
    ASSERT_FALSE(::testing::Test::HasFailure());
    Mapping dense;
    Mapping ties;
    PanoramaMapperConfig c = smallConfig(w);
    c.kriging.search_radius_m = 0.5;  // 2 m: the tie points alone estimate every node 1-8 m from the mast
    ASSERT_TRUE(dense.init(c).isOk());
    c.dense_stereo = false;
    ASSERT_TRUE(ties.init(c).isOk());
    EXPECT_LT(ties.mapper->memoryBytes(), dense.mapper->memoryBytes());
    ASSERT_TRUE(dense.map(w).isOk());
    const Status st = ties.map(w);
    ASSERT_TRUE(st.isOk()) << st.reason();
    EXPECT_EQ(ties.mapper->stages().size(), 4U);  // no dense stage
    const Figures fd = measure(w, *dense.mapper->products());
    const Figures ft = measure(w, *ties.mapper->products());
    printFigures("dense + tie points", *dense.mapper->products(), fd);
    printFigures("tie points alone", *ties.mapper->products(), ft);
    EXPECT_EQ(ties.mapper->products()->dense_samples, 0);
    EXPECT_GT(fd.good_near + fd.good_far, ft.good_near + ft.good_far);
    EXPECT_LE(fd.rms_near, 0.05);
}

void expectRefused(const PanoramaMapperConfig& c, const char* field) {
    const Status st = c.validate();
    EXPECT_EQ(st.code(), StatusCode::kInvalidConfig) << field;
    EXPECT_NE(std::string(st.reason()).find(field), std::string::npos) << st.reason();
    EXPECT_EQ(PanoramaMapper::workspaceBytes(c), 0U) << field;
    std::vector<std::byte> pool(1024);
    Arena arena(pool.data(), pool.size());
    hal::ManualClock clock;
    auto events = std::make_unique<hal::EventLog>();
    auto mapper = std::make_unique<PanoramaMapper>();
    EXPECT_EQ(mapper->init(c, arena, clock, *events).code(), StatusCode::kInvalidConfig) << field;
}

TEST(PanoramaMapper, BadConfigsAreRefusedNamingTheField) {
    PanoramaMapperConfig c;
    EXPECT_TRUE(c.validate().isOk()) << c.validate().reason();
    std::printf("[ panorama ] default configuration: workspaceBytes %zu\n", PanoramaMapper::workspaceBytes(c));
    c.max_stations = 1;
    expectRefused(c, "max_stations");
    c = PanoramaMapperConfig{};
    c.image_width = 8;
    expectRefused(c, "image_width");
    c = PanoramaMapperConfig{};
    c.ring_stations = 2;
    expectRefused(c, "ring_stations");
    c = PanoramaMapperConfig{};
    c.range_min_m = 50.0;
    expectRefused(c, "range_min_m");
    c = PanoramaMapperConfig{};
    c.sample_cell_m = 0.0;
    expectRefused(c, "sample_cell_m");
    c = PanoramaMapperConfig{};
    c.dense_gate_m = -1.0;
    expectRefused(c, "dense_gate_m");
    c = PanoramaMapperConfig{};
    c.dense_range_max_m = 100.0;
    expectRefused(c, "dense_range_max_m");
    c = PanoramaMapperConfig{};
    c.max_point_sigma_m = std::nan("");
    expectRefused(c, "max_point_sigma_m");
    c = PanoramaMapperConfig{};
    c.kriging.grid.cell_m = 0.0;
    expectRefused(c, "cell_m");
    c = PanoramaMapperConfig{};
    c.bundle.sigma_px = 0.0;
    expectRefused(c, "sigma_px");
    c = PanoramaMapperConfig{};
    c.dense_stereo = false;
    c.sample_cell_m = 0.0;  // not read without the dense stage
    EXPECT_TRUE(c.validate().isOk());
}

TEST(PanoramaMapper, BadInputsAreRefusedNamingTheInputAndNothingIsPublished) {
    const World& w = world();
    ASSERT_FALSE(::testing::Test::HasFailure());
    Mapping fresh;
    EXPECT_EQ(fresh.mapper->map(Span<const NetworkStation>(), Span<const StationImages>()).code(),
              StatusCode::kNotInitialized);
    Mapping run;
    ASSERT_TRUE(run.init(smallConfig(w)).isOk());
    const Span<const NetworkStation> all(w.approx.data(), w.approx.size());
    const Span<const StationImages> images(w.images.data(), w.images.size());
    const auto expect = [&](const Status& st, StatusCode code, const char* words) {
        EXPECT_EQ(st.code(), code) << st.reason();
        EXPECT_NE(std::string(st.reason()).find(words), std::string::npos) << st.reason();
        EXPECT_EQ(run.mapper->products(), nullptr);
        ASSERT_NE(run.mapper->stages().failed(), nullptr);
        EXPECT_EQ(run.mapper->stages().failed()->stage, Stage::kTiePoints);
    };
    expect(run.mapper->map(Span<const NetworkStation>(all.data(), 1), Span<const StationImages>(images.data(), 1)),
           StatusCode::kInvalidArgument, "stations");
    const std::size_t n = all.size();
    expect(run.mapper->map(all, Span<const StationImages>(images.data(), n - 1)), StatusCode::kInvalidArgument, "images");
    // Three quarters of the stations: not a whole number of rings.
    expect(run.mapper->map(Span<const NetworkStation>(all.data(), 3 * n / 4), Span<const StationImages>(images.data(), 3 * n / 4)),
           StatusCode::kInvalidArgument, "ring_stations");
    // Images larger than the capacity.
    PanoramaMapperConfig small = smallConfig(w);
    small.image_width = small.image_height = 64;
    small.stereo.coarse_window = 5;
    Mapping tiny;
    ASSERT_TRUE(tiny.init(small).isOk());
    const Status st = tiny.map(w);
    EXPECT_EQ(st.code(), StatusCode::kSizeMismatch) << st.reason();
    EXPECT_NE(std::string(st.reason()).find("image_width"), std::string::npos) << st.reason();
#if !defined(VTM_TEST_UNDER_EMULATOR)  // a full request more (the cost under qemu)
    // A request that fails after one that succeeded withdraws the products.
    ASSERT_TRUE(run.map(w).isOk());
    ASSERT_NE(run.mapper->products(), nullptr);
    expect(run.mapper->map(all, Span<const StationImages>(images.data(), n - 1)), StatusCode::kInvalidArgument, "images");
#endif
}

}  // namespace
}  // namespace vtm::app
