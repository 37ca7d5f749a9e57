// The orthophoto's occlusion test against the simulator's terrain: a low mast view over
// rocks, where relief hides part of the ground.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/render.hpp"
#include "sim_scene.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/kriging/orthophoto.hpp"

namespace vtm::kriging {
namespace {

// How far the line from the node to the eye dips below the simulator's terrain at most
// (metres; sampled every 1/300 of its length, the node's own 10 cm left out).
double deepestDip(const sim::Terrain& terrain, const Vec3& node, const Vec3& eye) {
    double deepest = -1e9;
    const double skip = 0.1 / (eye - node).norm();
    for (int i = 1; i < 300; ++i) {
        const double t = i / 300.0;
        if (t < skip) {
            continue;
        }
        const Vec3 q = node + t * (eye - node);
        deepest = std::max(deepest, terrain.elevationAt(q.x(), q.y()) + q.z());
    }
    return deepest;
}

// A mast camera 1.5 m up looking 4.6 m ahead over the rocky terrain: relief hides parts of
// the ground. The truth from the simulator's terrain: a node is hidden when the line to the
// eye dips more than twice the margin (4 cm) under the terrain, seen when it never dips
// under it; grazing lines in between are left out. The occlusion test, which knows the
// terrain only through the 8 cm grid, must reject most hidden nodes and few seen ones. The
// grid reaches back to the mast's foot, so every occluder lies in it.
TEST(Orthophoto, TheOcclusionTestRejectsTheViewsReliefHides) {
    const sim::Terrain& terrain = test::smallMarsTerrain();
    terrain::GridConfig g;
    g.north_edge_m = 7.2;
    g.west_edge_m = -2.56;
    g.cell_m = 0.08;
    g.cols = 64;
    g.rows = 88;
    std::vector<float> z;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            z.push_back(static_cast<float>(
                terrain.elevationAt(g.north_edge_m - (row + 0.5) * g.cell_m, g.west_edge_m + (col + 0.5) * g.cell_m)));
        }
    }
    constexpr std::int32_t kW = 160;
    constexpr std::int32_t kH = 120;
    const CameraModel model = makePinhole(kW, kH, 70.0);
    NetworkStation st;
    st.rig.model_a = model;
    st.rig.model_b = model;
    st.rig.b_from_a.t_m = Vec3(-0.3, 0.0, 0.0);
    const Vec3 eye(0.0, 0.0, -(terrain.elevationAt(0.0, 0.0) + 1.5));
    st.site_from_a = sim::poseLookingAt(eye, Vec3(4.6, 0.0, -terrain.elevationAt(4.6, 0.0)));
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(kW * kH), 0U);
    sim::FrameRequest r;
    r.terrain = &terrain;
    r.model = model;
    r.pose = st.site_from_a;
    r.lighting = test::plainLighting();
    r.sensor = test::plainSensor();
    sim::FrameOutput out;
    out.image8 = ImageView<std::uint8_t>(pixels.data(), kW, kH);
    ASSERT_TRUE(sim::renderFrame(r, out, nullptr).isOk());
    StationImages im;
    im.left = ImageView<const std::uint8_t>(pixels.data(), kW, kH);
    const auto run = [&](bool occlusion, std::vector<std::uint16_t>& source, OrthophotoStats& stats) {
        std::vector<std::uint8_t> grey(z.size(), 0U);
        source.assign(z.size(), 0U);
        OrthophotoConfig c;
        c.occlusion_test = occlusion;
        vtm::test::NoHeapScope guard;
        const Status s = buildOrthophoto(c, g, Span<const float>(z.data(), z.size()), Span<const NetworkStation>(&st, 1),
                                         Span<const StationImages>(&im, 1), ImageView<std::uint8_t>(grey.data(), g.cols, g.rows),
                                         ImageView<std::uint16_t>(source.data(), g.cols, g.rows), &stats);
        EXPECT_EQ(guard.heapCalls(), 0U);
        EXPECT_TRUE(s.isOk()) << s.reason();
    };
    std::vector<std::uint16_t> with, without;
    OrthophotoStats sw, so;
    run(true, with, sw);
    run(false, without, so);
    int hidden = 0, hidden_kept = 0, seen = 0, seen_rejected = 0;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            const auto k = static_cast<std::size_t>(row * g.cols + col);
            if (without[k] == kNoSource) {
                continue;
            }
            const Vec3 node(g.north_edge_m - (row + 0.5) * g.cell_m, g.west_edge_m + (col + 0.5) * g.cell_m,
                            -static_cast<double>(z[k]));
            const double dip = deepestDip(terrain, node, st.site_from_a.t_m);
            if (dip > 0.0 && dip <= 0.04) {
                continue;  // grazing
            }
            const bool is_hidden = dip > 0.04;
            const bool kept = with[k] != kNoSource;
            hidden += is_hidden ? 1 : 0;
            hidden_kept += (is_hidden && kept) ? 1 : 0;
            seen += is_hidden ? 0 : 1;
            seen_rejected += (!is_hidden && !kept) ? 1 : 0;
        }
    }
    std::printf("mast view over rocks: %d nodes in the image (grazing ones left out), %d hidden by relief (truth); "
                "occlusion test keeps "
                "%d hidden (%.1f %%) and rejects %d seen (%.1f %%); %d views rejected\n",
                hidden + seen, hidden, hidden_kept, 100.0 * hidden_kept / std::max(1, hidden), seen_rejected,
                100.0 * seen_rejected / std::max(1, seen), sw.occluded_views);
    EXPECT_GT(hidden, 50);  // the scene has something to hide
    EXPECT_LT(hidden_kept, 0.1 * hidden);
    EXPECT_LT(seen_rejected, 0.02 * seen);
    EXPECT_EQ(so.occluded_views, 0);
}

}  // namespace
}  // namespace vtm::kriging
