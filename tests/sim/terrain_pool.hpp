// One terrain at a time, built into a static 24 MiB pool: the sim tests of an executable
// run one after another, and a test keeps the terrain it asked for until its next call.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>

#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::sim {

inline const Terrain& buildTerrainInPool(const TerrainParams& params) {
    static std::byte pool[24U << 20U];
    static Arena arena(pool, sizeof pool);
    static Terrain terrain;
    arena.reset();
    terrain = Terrain();
    EXPECT_LE(Terrain::storageBytes(params), sizeof pool);
    const Status s = terrain.build(params, arena);
    EXPECT_TRUE(s.isOk()) << s.reason();
    return terrain;
}

}  // namespace vtm::sim
