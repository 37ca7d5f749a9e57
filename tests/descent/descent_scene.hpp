// Test scenes for the descent plane sweep: a terrain built into a static pool and a pair
// of nadir frames rendered by the simulator with per-pixel truth. Test code (heap allowed
// outside NoHeapScope).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent::test {

// One terrain at a time (tests run one after another), in a pool of exactly its size.
inline const sim::Terrain& buildTerrain(const sim::TerrainParams& params) {
    static std::vector<std::byte> pool;
    static std::unique_ptr<Arena> arena;
    static sim::Terrain terrain;
    terrain = sim::Terrain();
    pool.assign(sim::Terrain::storageBytes(params), std::byte{0});
    arena = std::make_unique<Arena>(pool.data(), pool.size());
    const Status s = terrain.build(params, *arena);
    EXPECT_TRUE(s.isOk()) << s.reason();
    return terrain;
}

struct RenderedFrame {
    std::vector<std::uint16_t> image;
    std::vector<float> depth_m;
    std::vector<float> point_site_m;  // 3 per pixel
    RigidPose pose;
};

inline RenderedFrame render(const sim::Terrain& terrain, const CameraModel& model, const RigidPose& pose,
                            std::uint32_t frameIndex, const sim::SensorParams& sensor = sim::SensorParams{}) {
    const std::int32_t w = model.width_px;
    const std::int32_t h = model.height_px;
    RenderedFrame f;
    f.pose = pose;
    f.image.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0U);
    f.depth_m.assign(f.image.size(), 0.0F);
    f.point_site_m.assign(3U * f.image.size(), 0.0F);
    sim::FrameRequest r;
    r.terrain = &terrain;
    r.model = model;
    r.pose = pose;
    r.sensor = sensor;
    r.sensor.bit_depth = 12;
    r.frame_index = frameIndex;
    sim::FrameOutput out;
    out.image16 = ImageView<std::uint16_t>(f.image.data(), w, h);
    out.truth.depth_m = ImageView<float>(f.depth_m.data(), w, h);
    out.truth.point_site_m = ImageView<float>(f.point_site_m.data(), 3 * w, h);
    const Status s = sim::renderFrame(r, out, nullptr);
    EXPECT_TRUE(s.isOk()) << s.reason();
    return f;
}

// Nadir camera (optical axis straight down, image +x = east) at `eye_site_m`.
inline RigidPose nadirPose(const Vec3& eye_site_m) {
    return sim::poseLookingAt(eye_site_m, eye_site_m + Vec3(0.0, 0.0, 100.0));
}

}  // namespace vtm::descent::test
