// TerrainIntegrator (fsw/app, docs/integrator.md): a reference DEM and three rover models
// of overlapping patches of an analytic hills-and-rocks terrain (tests/icp/icp_scene.hpp),
// each rover model in its own frame with a known navigation error. Truth: the true poses,
// the analytic surface, and a peer run of the same data inserted with the true poses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "icp_scene.hpp"
#include "no_heap_guard.hpp"
#include "vtm/app/terrain_integrator.hpp"

namespace vtm::app {
namespace {

using icp::test::motion;
using icp::test::Patch;
using icp::test::rotationErrorDeg;
using icp::test::sampleCloud;
using icp::test::terrainZ;

constexpr double kDem = 0.25;  // reference DEM post spacing = the registration grid's cell

// 32 m cube (x, y in [-16, 16), z in [-16, 16)), finest cell 0.125 m; products at 1 m,
// 0.25 m and 0.125 m (the mean, to compare with the surface); registration grid 0.25 m.
IntegratorConfig testConfig() {
    IntegratorConfig c;
    c.octree.north_edge_m = 16.0;
    c.octree.west_edge_m = -16.0;
    c.octree.top_z_m = -16.0;
    c.octree.side_m = 32.0;
    c.octree.max_depth = 8;
    c.octree.max_nodes = 32768;  // the navigation run takes 24,814
    c.products.levels = {{5, 7, 8, 0, 0, 0}};
    c.products.count = 3;
    c.products.reducer = terrain::Reducer::kMean;
    c.registration_level = 7;
    c.icp.max_model_points = 8192;
    c.icp.max_data_points = 1536;
    c.max_input_points = 8192;
    return c;
}

struct Rig {
    std::vector<std::byte> pool;
    hal::ManualClock clock;
    hal::EventLog events;
    std::unique_ptr<TerrainIntegrator> integrator = std::make_unique<TerrainIntegrator>();
    explicit Rig(const IntegratorConfig& c) : pool(TerrainIntegrator::workspaceBytes(c)) {
        Arena arena(pool.data(), pool.size());
        EXPECT_TRUE(integrator->init(c, arena, clock, events).isOk());
    }
};

// The DEM: one post per 0.25 m cell centre of x in [-12, 8), y in [-12, 12), map frame.
std::vector<Vec3> demPosts() {
    std::vector<Vec3> out;
    for (int j = 0; j < 96; ++j) {
        for (int i = 0; i < 80; ++i) {
            const double x = -12.0 + (i + 0.5) * kDem;
            const double y = -12.0 + (j + 0.5) * kDem;
            out.emplace_back(x, y, terrainZ(x, y));
        }
    }
    return out;
}

// A rover stop: its patch, true map_from_model (the rover 1.5 m above the patch centre,
// heading yaw), the navigation's error (left: guess = error * truth) and its points.
struct Stop {
    RigidPose truth;
    RigidPose guess;
    std::vector<Vec3> points;
    std::vector<float> footprints;
    Vec3 centroid = Vec3::Zero();
};

Stop makeStop(const Patch& p, double yaw_deg, const RigidPose& error, std::uint64_t seed) {
    Stop s;
    const Vec3 centre(0.5 * (p.x0_m + p.x1_m), 0.5 * (p.y0_m + p.y1_m), terrainZ(0.5 * (p.x0_m + p.x1_m), 0.5 * (p.y0_m + p.y1_m)) - 1.5);
    s.truth = motion(0.0, 0.0, yaw_deg, centre);
    s.guess.R = error.R * s.truth.R;
    s.guess.t_m = error.R * s.truth.t_m + error.t_m;
    s.points = sampleCloud(p, 0.2, seed, 0.005, s.truth);
    s.footprints.assign(s.points.size(), 0.05F);
    for (const Vec3& q : s.points) s.centroid += q;
    s.centroid /= static_cast<double>(s.points.size());
    return s;
}

const std::vector<Stop>& stops() {
    static const std::vector<Stop> all = {
        makeStop({-10.0, 2.0, -9.0, 3.0}, 30.0, motion(0.6, -0.5, 0.8, Vec3(0.15, -0.1, 0.05)), 11U),
        makeStop({-4.0, 7.5, -3.0, 9.0}, -60.0, motion(-0.7, 0.4, -1.0, Vec3(-0.2, 0.25, -0.08)), 12U),
        makeStop({-9.0, 3.0, 0.0, 11.5}, 120.0, motion(0.5, 0.8, 0.6, Vec3(0.1, 0.2, 0.1)), 13U),
    };
    return all;
}

ModelInput demInput(const std::vector<Vec3>& posts) {
    ModelInput m;
    m.points_m = Span<const Vec3>(posts.data(), posts.size());
    m.footprint.footprint_m = kDem;
    m.source = 1U;
    m.register_model = false;
    return m;
}

// Stop k: footprint rules in turn (range x pixel angle, fixed, per point), source 0.
ModelInput stopInput(const Stop& s, std::size_t k, const RigidPose& guess, bool register_it) {
    ModelInput m;
    m.points_m = Span<const Vec3>(s.points.data(), s.points.size());
    m.map_from_model_guess = guess;
    m.register_model = register_it;
    m.footprint.kind = static_cast<FootprintKind>(k % 3U);
    m.footprint.footprint_m = 0.1;
    m.footprint.per_point_m = Span<const float>(s.footprints.data(), s.footprints.size());
    m.footprint.pixel_angle_rad = 1e-3;
    return m;
}

enum class Poses { kTrue, kGuessRegistered, kGuessOnly };

struct Integration {
    std::unique_ptr<Rig> rig;
    std::vector<AddResult> results;
};

Integration integrate(Poses poses) {
    Integration run;
    run.rig = std::make_unique<Rig>(testConfig());
    static const std::vector<Vec3> posts = demPosts();
    AddResult r;
    EXPECT_TRUE(run.rig->integrator->addModel(demInput(posts), r).isOk());
    for (std::size_t k = 0; k < stops().size(); ++k) {
        const Stop& s = stops()[k];
        const ModelInput in = stopInput(s, k, poses == Poses::kTrue ? s.truth : s.guess, poses == Poses::kGuessRegistered);
        const Status st = run.rig->integrator->addModel(in, r);
        EXPECT_TRUE(st.isOk()) << "stop " << k << ": " << st.reason() << " (" << st.detail() << ")";
        run.results.push_back(r);
    }
    EXPECT_TRUE(run.rig->integrator->extractProducts().isOk());
    return run;
}

// RMS of a - b over the bins where both have data, and how many.
struct Rms {
    double rms_m = 0.0;
    std::int64_t bins = 0;
};
Rms rmsBetween(const terrain::HeightMap& a, const terrain::HeightMap& b) {
    double sum = 0.0;
    Rms out;
    for (std::int32_t row = 0; row < a.grid().rows; ++row) {
        for (std::int32_t col = 0; col < a.grid().cols; ++col) {
            const float ea = a.elevation(col, row);
            const float eb = b.elevation(col, row);
            if (terrain::isNoData(ea) || terrain::isNoData(eb)) continue;
            sum += (ea - eb) * static_cast<double>(ea - eb);
            ++out.bins;
        }
    }
    out.rms_m = out.bins > 0 ? std::sqrt(sum / static_cast<double>(out.bins)) : 0.0;
    return out;
}

// The surface's elevation (-z) at every bin centre of a product's grid, row-major.
std::vector<float> surfaceAtCentres(const terrain::HeightMap& a) {
    std::vector<float> out;
    for (std::int32_t row = 0; row < a.grid().rows; ++row) {
        for (std::int32_t col = 0; col < a.grid().cols; ++col) {
            out.push_back(static_cast<float>(-terrainZ(a.centreNorthM(row), a.centreEastM(col))));
        }
    }
    return out;
}

// RMS of the mean elevation against the surface at the bin centre.
Rms rmsAgainstSurface(const terrain::HeightMap& a, const std::vector<float>& surface) {
    double sum = 0.0;
    Rms out;
    std::size_t k = 0;
    for (std::int32_t row = 0; row < a.grid().rows; ++row) {
        for (std::int32_t col = 0; col < a.grid().cols; ++col, ++k) {
            const float e = a.elevation(col, row);
            if (terrain::isNoData(e)) continue;
            const double d = static_cast<double>(e) - static_cast<double>(surface[k]);
            sum += d * d;
            ++out.bins;
        }
    }
    out.rms_m = out.bins > 0 ? std::sqrt(sum / static_cast<double>(out.bins)) : 0.0;
    return out;
}

TEST(TerrainIntegrator, RegistersEachStopToTheMapAndFusesBetterThanTheNavigation) {
    const Integration truth = integrate(Poses::kTrue);
    const Integration reg = integrate(Poses::kGuessRegistered);
    const Integration nav = integrate(Poses::kGuessOnly);
    for (std::size_t k = 0; k < stops().size(); ++k) {
        const Stop& s = stops()[k];
        const AddResult& r = reg.results[k];
        ASSERT_TRUE(r.registered);
        const double rot = rotationErrorDeg(r.map_from_model.R, s.truth.R);
        const Vec3 at = r.map_from_model.R * s.centroid + r.map_from_model.t_m;
        const double trans = (at - (s.truth.R * s.centroid + s.truth.t_m)).norm();
        const double nav_rot = rotationErrorDeg(s.guess.R, s.truth.R);
        std::printf("[ stop %zu ] navigation %.3f deg; registered %.4f deg %.4f m at the centroid; overlap %.2f rms "
                    "%.4f m, %d map points, %d iterations; correction %.3f deg %.3f m\n",
                    k, nav_rot, rot, trans, r.icp.overlap, r.icp.rms_residual_m, r.map_model_points, r.icp.iterations,
                    r.correction_rad * 180.0 / 3.14159265358979323846, r.correction_m);
        EXPECT_LE(rot, 0.05) << "stop " << k;
        EXPECT_LE(trans, 0.01) << "stop " << k;
        EXPECT_GE(r.icp.overlap, 0.8) << "stop " << k;
        EXPECT_EQ(r.inserted, static_cast<std::int64_t>(s.points.size()));
        EXPECT_NEAR(r.correction_rad * 180.0 / 3.14159265358979323846, nav_rot, 0.05);
        EXPECT_FALSE(nav.results[k].registered);
    }
    const octree::HeightProducts* pt = truth.rig->integrator->products();
    const octree::HeightProducts* pr = reg.rig->integrator->products();
    const octree::HeightProducts* pn = nav.rig->integrator->products();
    ASSERT_NE(pt, nullptr);
    ASSERT_NE(pr, nullptr);
    ASSERT_NE(pn, nullptr);
    // Bounds per product (1 m, 0.25 m, 0.125 m): against the true-pose peer, and against the
    // surface at the bin centre no more than this above the peer's own (binning) error.
    const double peer_bound[3] = {0.005, 0.005, 0.005};
    for (std::int32_t p = 0; p < 3; ++p) {
        const Rms r_peer = rmsBetween(pr->map(p), pt->map(p));
        const Rms n_peer = rmsBetween(pn->map(p), pt->map(p));
        std::printf("[ level %d ] vs true-pose map: registered %.4f m, navigation %.4f m (%lld bins)\n", pr->level(p),
                    r_peer.rms_m, n_peer.rms_m, static_cast<long long>(r_peer.bins));
        EXPECT_LE(r_peer.rms_m, peer_bound[p]);
        EXPECT_GE(n_peer.rms_m, 3.0 * r_peer.rms_m);
        EXPECT_EQ(r_peer.bins, pt->map(p).filledCells());
        if (p == 2) {
            continue;  // the surface at 0.125 m: 30,720 evaluations more under qemu for no new fact
        }
        const std::vector<float> surface = surfaceAtCentres(pt->map(p));
        const Rms t_surf = rmsAgainstSurface(pt->map(p), surface);
        const Rms r_surf = rmsAgainstSurface(pr->map(p), surface);
        const Rms n_surf = rmsAgainstSurface(pn->map(p), surface);
        std::printf("[ level %d ] vs the surface at bin centres: true poses %.4f, registered %.4f, navigation %.4f m\n",
                    pr->level(p), t_surf.rms_m, r_surf.rms_m, n_surf.rms_m);
        EXPECT_LE(r_surf.rms_m, t_surf.rms_m + 0.005);
        EXPECT_GT(n_surf.rms_m, r_surf.rms_m + 0.01);
    }
}

TEST(TerrainIntegrator, AModelOffTheMapIsRefusedAndChangesNothing) {
    Rig rig(testConfig());
    static const std::vector<Vec3> posts = demPosts();
    AddResult r;
    ASSERT_TRUE(rig.integrator->addModel(demInput(posts), r).isOk());
    const Stop far = makeStop({11.0, 15.0, -15.0, -11.0}, 0.0, motion(0.5, 0.5, 0.5, Vec3(0.1, 0.1, 0.0)), 21U);
    const std::uint32_t nodes = rig.integrator->map().nodeCount();
    const std::int64_t inserted = rig.integrator->map().stats().inserted;
    const Status st = rig.integrator->addModel(stopInput(far, 1U, far.guess, true), r);
    EXPECT_EQ(st.code(), StatusCode::kNoData);
    EXPECT_NE(std::strstr(st.reason(), "too little of the map"), nullptr) << st.reason();
    EXPECT_EQ(r.inserted, 0);
    EXPECT_FALSE(r.registered);
    EXPECT_EQ(rig.integrator->map().nodeCount(), nodes);
    EXPECT_EQ(rig.integrator->map().stats().inserted, inserted);
    EXPECT_EQ(rig.integrator->modelsInserted(), 1);
    ASSERT_NE(rig.integrator->stages().failed(), nullptr);
    EXPECT_EQ(rig.integrator->stages().failed()->stage, Stage::kMapModel);
    // The same stop half on the DEM's edge: ICP refuses the overlap by name; nothing changes.
    const Stop edge = makeStop({7.5, 15.5, -4.0, 4.0}, 0.0, motion(0.0, 0.0, 0.0, Vec3::Zero()), 22U);
    const Status st2 = rig.integrator->addModel(stopInput(edge, 1U, edge.guess, true), r);
    std::printf("[ edge ] %s (%lld), overlap %.2f\n", st2.reason(), static_cast<long long>(st2.detail()), r.icp.overlap);
    EXPECT_EQ(st2.code(), StatusCode::kDegenerate);
    EXPECT_EQ(rig.integrator->stages().failed()->stage, Stage::kRegister);
    EXPECT_EQ(rig.integrator->map().nodeCount(), nodes);
    EXPECT_EQ(rig.integrator->products(), nullptr);
}

TEST(TerrainIntegrator, BadInputsAreNamedAndChangeNothing) {
    Rig rig(testConfig());
    std::vector<Vec3> pts = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    std::vector<float> fp = {0.1F, 0.1F};
    AddResult r;
    TerrainIntegrator idle;
    ModelInput m;
    m.points_m = Span<const Vec3>(pts.data(), pts.size());
    m.footprint.footprint_m = 0.1;
    EXPECT_EQ(idle.addModel(m, r).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(idle.extractProducts().code(), StatusCode::kNotInitialized);
    struct Case {
        const char* what;
        ModelInput input;
        StatusCode code;
        std::int64_t detail;
    };
    std::vector<Case> cases;
    ModelInput c = m;
    c.points_m = Span<const Vec3>();
    cases.push_back({"points empty", c, StatusCode::kInvalidArgument, 0});
    std::vector<Vec3> many(8193, Vec3(0, 0, 0));
    c = m;
    c.points_m = Span<const Vec3>(many.data(), many.size());
    cases.push_back({"more than max_input_points", c, StatusCode::kInvalidArgument, 8193});
    std::vector<Vec3> nan = pts;
    nan[2].z() = std::nan("");
    c = m;
    c.points_m = Span<const Vec3>(nan.data(), nan.size());
    cases.push_back({"not finite", c, StatusCode::kCorruptData, 2});
    c = m;
    c.map_from_model_guess.R(0, 0) = 2.0;
    cases.push_back({"map_from_model_guess", c, StatusCode::kInvalidArgument, 0});
    c = m;
    c.source = 16U;
    cases.push_back({"source", c, StatusCode::kInvalidArgument, 16});
    c = m;
    c.footprint.footprint_m = 0.0;
    cases.push_back({"footprint_m", c, StatusCode::kInvalidArgument, 0});
    c = m;
    c.footprint.kind = FootprintKind::kPerPoint;
    c.footprint.per_point_m = Span<const float>(fp.data(), fp.size());
    cases.push_back({"per_point_m size", c, StatusCode::kSizeMismatch, 2});
    std::vector<float> fp3 = {0.1F, -1.0F, 0.1F};
    c.footprint.per_point_m = Span<const float>(fp3.data(), fp3.size());
    cases.push_back({"point's footprint", c, StatusCode::kInvalidArgument, 1});
    c = m;
    c.footprint.kind = FootprintKind::kRangeTimesAngle;
    c.footprint.pixel_angle_rad = 1e-3;
    c.footprint.sensor_m = pts[1];
    cases.push_back({"point's footprint", c, StatusCode::kInvalidArgument, 1});
    c.footprint.pixel_angle_rad = -1.0;
    cases.push_back({"pixel_angle_rad", c, StatusCode::kInvalidArgument, 0});
    for (const Case& k : cases) {
        const Status st = rig.integrator->addModel(k.input, r);
        EXPECT_EQ(st.code(), k.code) << k.what << ": " << st.reason();
        EXPECT_NE(std::strstr(st.reason(), k.what), nullptr) << k.what << ": " << st.reason();
        EXPECT_EQ(st.detail(), k.detail) << k.what;
        EXPECT_EQ(rig.integrator->map().stats().inserted, 0) << k.what;
    }
    EXPECT_EQ(rig.integrator->map().nodeCount(), 1U);
    EXPECT_EQ(rig.integrator->modelsInserted(), 0);
    // A point outside the cube is skipped and counted; the rest go in.
    std::vector<Vec3> out = pts;
    out[0].x() = 100.0;
    c = m;
    c.points_m = Span<const Vec3>(out.data(), out.size());
    EXPECT_TRUE(rig.integrator->addModel(c, r).isOk());
    EXPECT_EQ(r.inserted, 2);
    EXPECT_EQ(r.refused_outside, 1);
}

TEST(TerrainIntegrator, BadConfigsAreNamedAndTheWorkspaceFormulaIsExact) {
    struct Bad {
        const char* field;
        IntegratorConfig config;
    };
    std::vector<Bad> bad;
    IntegratorConfig c = testConfig();
    c.registration_level = 9;
    bad.push_back({"integrator.registration_level", c});
    c = testConfig();
    c.window_margin_m = std::nan("");
    bad.push_back({"integrator.window_margin_m", c});
    c = testConfig();
    c.max_input_points = 0;
    bad.push_back({"integrator.max_input_points", c});
    c = testConfig();
    c.octree.side_m = -1.0;
    bad.push_back({"octree.side_m", c});
    c = testConfig();
    c.products.levels[1] = 3;
    bad.push_back({"products.levels", c});
    c = testConfig();
    c.icp.min_gate_m = 0.0;
    bad.push_back({"icp.min_gate_m", c});
    hal::ManualClock clock;
    hal::EventLog events;
    for (const Bad& b : bad) {
        const Status st = b.config.validate();
        EXPECT_EQ(st.code(), StatusCode::kInvalidConfig) << b.field;
        EXPECT_NE(std::strstr(st.reason(), b.field), nullptr) << st.reason();
        EXPECT_EQ(TerrainIntegrator::workspaceBytes(b.config), 0U) << b.field;
        std::vector<std::byte> pool(1024);
        Arena arena(pool.data(), pool.size());
        TerrainIntegrator t;
        EXPECT_EQ(t.init(b.config, arena, clock, events).code(), StatusCode::kInvalidConfig) << b.field;
    }
    const IntegratorConfig defaults;
    EXPECT_TRUE(defaults.validate().isOk());
    std::printf("[ default ] workspace %zu bytes, object %zu bytes\n", TerrainIntegrator::workspaceBytes(defaults),
                sizeof(TerrainIntegrator));
    const IntegratorConfig good = testConfig();
    const std::size_t bytes = TerrainIntegrator::workspaceBytes(good);
    octree::ProductConfig grid;
    grid.levels = {{7, 0, 0, 0, 0, 0}};
    grid.count = 1;
    grid.reducer = terrain::Reducer::kMean;
    EXPECT_EQ(bytes, octree::Octree::workspaceBytes(good.octree) +
                         octree::HeightProducts::workspaceBytes(good.products, good.octree) +
                         octree::HeightProducts::workspaceBytes(grid, good.octree) +
                         icp::PointToPlaneIcp::workspaceBytes(good.icp) + Arena::arrayBytes<Vec3>(8192));
    std::vector<std::byte> pool(bytes + 16);
    auto t = std::make_unique<TerrainIntegrator>();
    for (std::size_t offset = 0; offset < 16; ++offset) {
        Arena arena(pool.data() + offset, bytes);
        EXPECT_TRUE(t->init(good, arena, clock, events).isOk()) << offset;
    }
    Arena half(pool.data(), bytes / 2);
    EXPECT_EQ(t->init(good, half, clock, events).code(), StatusCode::kOutOfMemory);
}

TEST(TerrainIntegrator, RequestsTouchNoHeapAndRepeatBitForBit) {
    static const std::vector<Vec3> posts = demPosts();
    const Stop& s = stops()[1];
    std::vector<float> first;
    for (int run = 0; run < 2; ++run) {
        Rig rig(testConfig());
        AddResult r0, r1;
        const ModelInput dem = demInput(posts);
        const ModelInput in = stopInput(s, 1U, s.guess, true);
        std::uint64_t calls = 0;
        {
            vtm::test::NoHeapScope guard;
            EXPECT_TRUE(rig.integrator->addModel(dem, r0).isOk());
            EXPECT_TRUE(rig.integrator->addModel(in, r1).isOk());
            EXPECT_TRUE(rig.integrator->extractProducts().isOk());
            calls = guard.heapCalls();
        }
        EXPECT_EQ(calls, 0U);
        ASSERT_EQ(rig.integrator->stages().size(), 1U);
        EXPECT_EQ(rig.integrator->stages().at(0).stage, Stage::kExtract);
        const terrain::HeightMap& m = rig.integrator->products()->map(2);
        std::vector<float> now;
        for (std::int32_t row = 0; row < m.grid().rows; ++row) {
            for (std::int32_t col = 0; col < m.grid().cols; ++col) now.push_back(m.highest(col, row));
        }
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) now.push_back(static_cast<float>(r1.map_from_model.R(i, j)));
            now.push_back(static_cast<float>(r1.map_from_model.t_m(i)));
        }
        if (run == 0) {
            first = now;
        } else {
            ASSERT_EQ(now.size(), first.size());
            EXPECT_EQ(std::memcmp(now.data(), first.data(), now.size() * sizeof(float)), 0);
        }
    }
}

}  // namespace
}  // namespace vtm::app
