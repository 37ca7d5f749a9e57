// Terrains built into static 24 MiB pools, one per slot, each on its first request only:
// terrain builds dominate the sim tests under qemu, so a suite gives each of its worlds a
// slot of its own and every test of it asks for that slot with the same parameters.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>

#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::sim {

constexpr int kTerrainPoolSlots = 3;

// The terrain of `slot`, built from `params` on the slot's first call (later calls return
// it as built: a slot holds one world for the whole process).
inline const Terrain& terrainInPool(const TerrainParams& params, int slot = 0) {
    constexpr std::size_t kPoolBytes = 24U << 20U;
    static std::byte pools[kTerrainPoolSlots][kPoolBytes];
    static Terrain terrains[kTerrainPoolSlots];
    static bool built[kTerrainPoolSlots] = {};
    EXPECT_TRUE(slot >= 0 && slot < kTerrainPoolSlots) << slot;
    const int s = slot >= 0 && slot < kTerrainPoolSlots ? slot : 0;
    if (!built[s]) {
        built[s] = true;
        Arena arena(pools[s], kPoolBytes);
        EXPECT_LE(Terrain::storageBytes(params), kPoolBytes);
        const Status status = terrains[s].build(params, arena);
        EXPECT_TRUE(status.isOk()) << status.reason();
    }
    return terrains[s];
}

}  // namespace vtm::sim
