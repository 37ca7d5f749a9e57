// A small Mars terrain of the simulator for the kriging and orthophoto tests (test code:
// heap allowed outside NoHeapScope). One terrain, built once per process.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::kriging::test {

// About 6.4 m of level-0 terrain (5 cm cells) around the site origin, rocks included.
inline sim::TerrainParams smallMarsParams() {
    sim::TerrainParams p = sim::defaultMarsTerrainParams();
    p.seed = 5U;
    p.finest_cell_m = 0.05;
    p.samples_log2 = 7;
    p.levels = 5;
    p.rock_region_radius_m = 10.0;
    p.rock_k = 0.12;
    p.relief_amplitude_m = 1.0;
    p.relief_longest_wavelength_m = 8.0;
    p.texture_longest_wavelength_m = 0.5;
    p.texture_finest_wavelength_m = 0.02;
    return p;
}

inline const sim::Terrain& smallMarsTerrain() {
    static std::vector<std::byte> pool;
    static std::unique_ptr<Arena> arena;
    static sim::Terrain terrain;
    if (!terrain.built()) {
        const sim::TerrainParams params = smallMarsParams();
        pool.assign(sim::Terrain::storageBytes(params) + Arena::kDefaultAlignment, std::byte{0});
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        const Status s = terrain.build(params, *arena);
        EXPECT_TRUE(s.isOk()) << s.reason();
    }
    return terrain;
}

// Lighting and sensor whose grey values follow the Lambertian model alone: no cast
// shadows, no noise, no vignetting.
inline sim::Lighting plainLighting() {
    sim::Lighting l;
    l.shadows = false;
    return l;
}

inline sim::SensorParams plainSensor() {
    sim::SensorParams s;
    s.read_noise_e = 0.0;
    s.shot_noise = false;
    s.vignetting = 0.0;
    return s;
}

}  // namespace vtm::kriging::test
