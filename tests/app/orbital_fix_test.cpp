// DescentMapper's locate stage (orbital fix, issue 24 item 4; docs/app.md "Orbital fix")
// on a descent_orbital.scn-like world: the located frames and the map's placement against
// the simulator's true camera positions, in orbital pixels; the depth error with the fix
// against the same mapper without it on the same frames and navigation (SimOdometry's
// scale error, random walk and drift), in the same run; a useless orbital map refused by
// name while the request still maps; bad maps and configurations named.
// 256 x 256 frames; under qemu one request on a coarser terrain grid.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "orbital_world.hpp"

namespace vtm::app {
namespace {

using orbital_test::Outcome;
using orbital_test::World;
using orbital_test::WorldSpec;

// The flying tests run on the host only: under qemu the five descent requests they fly
// (refinement in software floating point) cost minutes per target. The locate step's bits
// on every target are the determinism suite's section orbital_fix, and the config and map
// checks below run everywhere.
#if !defined(VTM_TEST_UNDER_EMULATOR)
// The shipped descent_orbital.scn world on a 2^9 terrain grid, three requests.
constexpr std::int32_t kSamplesLog2 = 9;
constexpr int kRequests = 3;
constexpr bool kNoiseMap = true;

const World& world() {
    static const std::unique_ptr<World> w = [] {
        WorldSpec s;
        s.samples_log2 = kSamplesLog2;
        return orbital_test::buildWorld(s);
    }();
    return *w;
}

class OrbitalFixTest : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(world().ok) << "descent_orbital.scn did not parse or build"; }
};

// Each frame located within 1 orbital pixel of its true camera position (measured: see
// docs/app.md); the map placed there; the depth scale better than the navigation's.
TEST_F(OrbitalFixTest, LocatesBothFramesAndFixesThePlacementAndTheDepthScale) {
    const std::vector<Outcome> fixed = orbital_test::fly(world(), orbital_test::orbitalConfig(world(), true), kRequests);
    const std::vector<Outcome> nav = orbital_test::fly(world(), orbital_test::orbitalConfig(world(), false), kRequests);
    ASSERT_EQ(fixed.size(), nav.size());
    std::printf("| request | located frame 1 / 2, orbital px | map placement px (navigation's) | median depth error %% with / without |\n");
    for (std::size_t r = 0; r < fixed.size(); ++r) {
        const Outcome& f = fixed[r];
        std::printf("| %zu | %.2f / %.2f | %.2f (%.2f) | %.3f / %.3f |%s%s\n", r, f.frame_error_px[0], f.frame_error_px[1],
                    f.placement_error_px, f.navigation_error_px, 100.0 * f.depth_error, 100.0 * nav[r].depth_error,
                    f.applied ? "" : " not applied: ", f.applied ? "" : f.reason);
        std::printf("    scale %s %.4f (frames %.4f %.4f), true %.4f\n", f.scale_applied ? "applied" : "not applied", f.scale,
                    f.frame_scale[0], f.frame_scale[1], f.true_scale);
        ASSERT_TRUE(f.mapped && nav[r].mapped) << "request " << r;
        EXPECT_TRUE(f.applied) << "request " << r << ": " << f.reason;
        EXPECT_EQ(f.locate_quality, 2) << "request " << r;
        for (int i = 0; i < 2; ++i) {
            EXPECT_GE(f.frame_error_px[i], 0.0) << "request " << r << " frame " << i << " not located";
            EXPECT_LE(f.frame_error_px[i], 1.0) << "request " << r << " frame " << i;
        }
        EXPECT_LE(f.placement_error_px, 1.0) << "request " << r;
        // The scale: where both frames agree on it, the depth error within 0.5 % (the
        // issue's target; it is not always below the navigation's: docs/app.md); elsewhere the navigation's baseline, so its depth error to 0.1
        // point (the map moved by the position fix only). docs/app.md: where it is missed.
        if (f.scale_applied) {
            EXPECT_LE(f.depth_error, 0.005) << "request " << r;
        } else {
            EXPECT_NEAR(f.depth_error, nav[r].depth_error, 0.001) << "request " << r;
        }
        EXPECT_EQ(nav[r].locate_quality, -1) << "no locate stage without orbital.enabled";
    }
}

// A useless orbital map (noise; a flat image): the fix is refused with a named reason,
// the stage records quality 0, and the request maps from the navigation exactly as the
// mapper without the fix does. With orbital.required the request ends at locate instead.
TEST_F(OrbitalFixTest, AUselessOrbitalMapIsRefusedByNameAndTheRequestMapsFromTheNavigation) {
    std::vector<std::uint8_t> noise(world().orbital.size());
    std::mt19937 rng(7U);
    for (std::uint8_t& v : noise) v = static_cast<std::uint8_t>(rng() & 0xFFU);
    std::vector<std::uint8_t> flat(world().orbital.size(), 90U);
    DescentMapperConfig plain = orbital_test::orbitalConfig(world(), false);
    const std::vector<Outcome> nav = orbital_test::fly(world(), plain, 1);
    ASSERT_EQ(nav.size(), 1U);
    for (const std::vector<std::uint8_t>* image : {&flat, &noise}) {
        if (image == &noise && !kNoiseMap) continue;
        World& w = const_cast<World&>(world());
        const std::vector<std::uint8_t> saved = w.orbital;
        w.orbital = *image;
        const std::vector<Outcome> o = orbital_test::fly(w, orbital_test::orbitalConfig(w, true), 1);
        DescentMapperConfig required = orbital_test::orbitalConfig(w, true);
        required.orbital.required = true;
        // The required fix: the request ends at locate, nothing published.
        {
            hal::FaultPlan plan;
            hal::SimCamera camera;
            hal::SimOdometry odometry;
            hal::ManualClock clock;
            hal::EventLog events;
            hal::SimCamera::Config cc{&w.scenario, &w.terrain, &w.frames, sim::kMainCameraId, &plan};
            ASSERT_TRUE(camera.init(cc).isOk());
            ASSERT_TRUE(odometry.init({&w.frames, &plan}).isOk());
            std::vector<std::byte> pool(DescentMapper::workspaceBytes(required));
            Arena arena(pool.data(), pool.size());
            auto mapper = std::make_unique<DescentMapper>();
            ASSERT_TRUE(mapper->init(required, arena, camera, odometry, clock, events).isOk());
            ASSERT_TRUE(mapper->setOrbitalMap(orbital_test::orbitalMapOf(w)).isOk());
            const Status st = mapper->map();
            EXPECT_FALSE(st.isOk());
            ASSERT_NE(mapper->stages().failed(), nullptr);
            EXPECT_EQ(mapper->stages().failed()->stage, Stage::kLocate);
            EXPECT_EQ(mapper->products(), nullptr);
            EXPECT_EQ(std::strncmp(st.reason(), "locate:", 7) == 0 || std::strncmp(st.reason(), "registration", 12) == 0 ||
                          std::strstr(st.reason(), "NCC") != nullptr || std::strstr(st.reason(), "contrast") != nullptr ||
                          std::strstr(st.reason(), "ambiguous") != nullptr,
                      true)
                << st.reason();
        }
        w.orbital = saved;
        ASSERT_EQ(o.size(), 1U);
        std::printf("[ %s orbital map ] fix refused: %s\n", image == &noise ? "noise" : "flat", o[0].reason);
        EXPECT_TRUE(o[0].mapped);
        EXPECT_FALSE(o[0].applied);
        EXPECT_EQ(o[0].locate_quality, 0);
        EXPECT_GT(std::strlen(o[0].reason), 0U);
        // The navigation's answer, as without the fix, to the bit.
        EXPECT_EQ(o[0].depth_error, nav[0].depth_error);
        EXPECT_EQ(o[0].placement_error_px, nav[0].placement_error_px);
    }
}
#endif  // !VTM_TEST_UNDER_EMULATOR

TEST(OrbitalFixConfigTest, BadMapsAndConfigsAreNamed) {
    static std::uint8_t pixels[64 * 64];
    static std::uint16_t deep[64 * 64];
    OrbitalMap good;
    good.image8 = ImageView<const std::uint8_t>(pixels, 64, 64);
    EXPECT_TRUE(validateOrbitalMap(good).isOk());
    const auto reasonOf = [](const OrbitalMap& m) { return std::string(validateOrbitalMap(m).reason()); };
    OrbitalMap bad;
    EXPECT_NE(reasonOf(bad).find("image8 or image16"), std::string::npos);
    bad = good;
    bad.image16 = ImageView<const std::uint16_t>(deep, 64, 64);
    EXPECT_NE(reasonOf(bad).find("image8 or image16"), std::string::npos);
    bad = good;
    bad.image8 = ImageView<const std::uint8_t>(pixels, 8, 64);
    EXPECT_NE(reasonOf(bad).find("16 x 16"), std::string::npos);
    bad = good;
    bad.bit_depth = 12;
    EXPECT_NE(reasonOf(bad).find("bit_depth"), std::string::npos);
    bad.image8 = ImageView<const std::uint8_t>();
    bad.image16 = ImageView<const std::uint16_t>(deep, 64, 64);
    EXPECT_TRUE(validateOrbitalMap(bad).isOk());
    bad.bit_depth = 17;
    EXPECT_NE(reasonOf(bad).find("bit_depth"), std::string::npos);
    bad = good;
    bad.geo.cell_m = 0.0;
    EXPECT_NE(reasonOf(bad).find("geo.cell_m"), std::string::npos);
    bad = good;
    bad.geo.north0_m = std::nan("");
    EXPECT_NE(reasonOf(bad).find("north0_m"), std::string::npos);
    EXPECT_EQ(validateOrbitalMap(bad).code(), StatusCode::kInvalidArgument);

    OrbitalFixConfig c;
    c.enabled = true;
    EXPECT_TRUE(c.validate().isOk());
    const auto cfgReason = [](const OrbitalFixConfig& x) { return std::string(x.validate().reason()); };
    OrbitalFixConfig b = c;
    b.min_ncc = 1.5;
    EXPECT_NE(cfgReason(b).find("orbital.min_ncc"), std::string::npos);
    b = c;
    b.scale_range = 0.0;
    EXPECT_NE(cfgReason(b).find("orbital.scale_range"), std::string::npos);
    b = c;
    b.max_peak_ratio = 0.0;
    EXPECT_NE(cfgReason(b).find("orbital.max_peak_ratio"), std::string::npos);
    b = c;
    b.max_residual_px = -1.0;
    EXPECT_NE(cfgReason(b).find("orbital.max_residual_px"), std::string::npos);
    b = c;
    b.angle_range_rad = 4.0;
    EXPECT_NE(cfgReason(b).find("orbital.angle_range_rad"), std::string::npos);
    b = c;
    b.max_position_disagreement_px = 0.0;
    EXPECT_NE(cfgReason(b).find("orbital.max_position_disagreement_px"), std::string::npos);
    b = c;
    b.max_scale_change = 0.0;
    EXPECT_NE(cfgReason(b).find("orbital.max_scale_change"), std::string::npos);
    b = c;
    b.min_pixel_cells = 0.0;
    EXPECT_NE(cfgReason(b).find("orbital.min_pixel_cells"), std::string::npos);
    b = c;
    b.registration.levels = 0;
    EXPECT_NE(cfgReason(b).find("levels"), std::string::npos);
}

#if !defined(VTM_TEST_UNDER_EMULATOR)
// In the mapper (host only: it needs the world): the fix needs refine_pose; its memory is
// planned only when enabled; setOrbitalMap before init and without the fix is refused.
TEST_F(OrbitalFixTest, TheMapperPlansTheFixAndRefusesAMapBeforeInitOrWhenDisabled) {
    static std::uint8_t pixels[64 * 64];
    OrbitalMap good;
    good.image8 = ImageView<const std::uint8_t>(pixels, 64, 64);
    ASSERT_TRUE(world().ok);
    DescentMapperConfig m = orbital_test::orbitalConfig(world(), true);
    DescentMapperConfig off = orbital_test::orbitalConfig(world(), false);
    EXPECT_GT(DescentMapper::workspaceBytes(m),
              DescentMapper::workspaceBytes(off) + entropy::EntropyRegistration::workspaceBytes(m.orbital.registration));
    DescentMapperConfig nr = m;
    nr.refine_pose = false;
    EXPECT_NE(std::string(nr.validate().reason()).find("orbital.enabled"), std::string::npos);
    nr = m;
    nr.orbital.min_ncc = -1.0;
    EXPECT_NE(std::string(nr.validate().reason()).find("orbital.min_ncc"), std::string::npos);
    DescentMapper fresh;
    EXPECT_EQ(fresh.setOrbitalMap(good).code(), StatusCode::kNotInitialized);
    hal::FaultPlan plan;
    hal::SimCamera camera;
    hal::SimOdometry odometry;
    hal::ManualClock clock;
    hal::EventLog events;
    World& w = const_cast<World&>(world());
    hal::SimCamera::Config cc{&w.scenario, &w.terrain, &w.frames, sim::kMainCameraId, &plan};
    ASSERT_TRUE(camera.init(cc).isOk());
    ASSERT_TRUE(odometry.init({&w.frames, &plan}).isOk());
    std::vector<std::byte> pool(DescentMapper::workspaceBytes(m));
    {
        Arena half(pool.data(), pool.size() - entropy::EntropyRegistration::workspaceBytes(m.orbital.registration) / 2U);
        auto mapper = std::make_unique<DescentMapper>();
        EXPECT_EQ(mapper->init(m, half, camera, odometry, clock, events).code(), StatusCode::kOutOfMemory);
    }
    {
        Arena arena(pool.data(), pool.size());
        auto mapper = std::make_unique<DescentMapper>();
        ASSERT_TRUE(mapper->init(off, arena, camera, odometry, clock, events).isOk());
        EXPECT_NE(std::string(mapper->setOrbitalMap(good).reason()).find("orbital.enabled"), std::string::npos);
    }
    {
        Arena arena(pool.data(), pool.size());
        auto mapper = std::make_unique<DescentMapper>();
        ASSERT_TRUE(mapper->init(m, arena, camera, odometry, clock, events).isOk());
        EXPECT_LE(mapper->memoryBytes(), DescentMapper::workspaceBytes(m));
        OrbitalMap bad = good;
        bad.geo.cell_m = -1.0;
        EXPECT_NE(std::string(mapper->setOrbitalMap(bad).reason()).find("geo.cell_m"), std::string::npos);
        EXPECT_TRUE(mapper->setOrbitalMap(good).isOk());
    }
}
#endif  // !VTM_TEST_UNDER_EMULATOR

}  // namespace
}  // namespace vtm::app
