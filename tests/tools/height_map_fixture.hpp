// A height map for the ground-product tests, filled cell by cell with known elevations:
// one site point at a cell's centre (x north, y east, z down = -elevation).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::ground::test {

class TestHeightMap {
public:
    explicit TestHeightMap(const terrain::GridConfig& grid)
        : config_{grid, terrain::Reducer::kHighest}, pool_(terrain::HeightMap::workspaceBytes(config_)),
          arena_(pool_.data(), pool_.size()) {
        EXPECT_TRUE(map_.init(config_, arena_).isOk());
    }
    // Adds a point of elevation `up_m` at the centre of cell (col, row), computed from the
    // grid's definition (docs/terrain.md), not from the map.
    void put(std::int32_t col, std::int32_t row, float up_m) {
        const terrain::GridConfig& g = config_.grid;
        const Vec3 site(g.north_edge_m - (row + 0.5) * g.cell_m, g.west_edge_m + (col + 0.5) * g.cell_m,
                        -static_cast<double>(up_m));
        EXPECT_TRUE(map_.add(site).isOk());
    }
    [[nodiscard]] const terrain::HeightMap& map() const { return map_; }

private:
    terrain::HeightMapConfig config_;
    std::vector<std::byte> pool_;
    Arena arena_;
    terrain::HeightMap map_;
};

}  // namespace vtm::ground::test
