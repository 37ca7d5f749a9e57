// Terrains built into static 24 MiB pools, one per slot: the sim tests of an executable run
// one after another, and a test keeps the terrain of a slot until the slot's next build.
// Terrain builds dominate these tests under qemu, so a suite that alternates between a few
// worlds gives each its own slot and builds each once.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>

#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::sim {

constexpr int kTerrainPoolSlots = 3;

inline const Terrain& buildTerrainInPool(const TerrainParams& params, int slot = 0) {
    constexpr std::size_t kPoolBytes = 24U << 20U;
    static std::byte pools[kTerrainPoolSlots][kPoolBytes];
    static Terrain terrains[kTerrainPoolSlots];
    EXPECT_TRUE(slot >= 0 && slot < kTerrainPoolSlots) << slot;
    const int s = slot >= 0 && slot < kTerrainPoolSlots ? slot : 0;
    Arena arena(pools[s], kPoolBytes);
    terrains[s] = Terrain();
    EXPECT_LE(Terrain::storageBytes(params), kPoolBytes);
    const Status status = terrains[s].build(params, arena);
    EXPECT_TRUE(status.isOk()) << status.reason();
    return terrains[s];
}

}  // namespace vtm::sim
