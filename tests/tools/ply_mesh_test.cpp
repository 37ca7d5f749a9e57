// PLY mesh of a height map: counts against a map with known holes and a known step, the
// vertices at the cell centres (read back with the PLY reader), the faces' indices and
// their upward normals from the bytes.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "ground_test_files.hpp"
#include "height_map_fixture.hpp"
#include "vtm/ground/ply_mesh.hpp"
#include "vtm/ground/ply_reader.hpp"

namespace vtm::ground {
namespace {

// 4 x 3 cells of 1 m, north-west corner at north 10, east 20. Holes at (2, 1) and, when
// asked, none else:   row 0  X X X X
//                     row 1  X X . X
//                     row 2  X X X X
// Elevation of cell (col, row): 0.25 col - 0.5 row (exact in float).
constexpr terrain::GridConfig kGrid{10.0, 20.0, 1.0, 4, 3};

float elevationOf(std::int32_t col, std::int32_t row) { return 0.25F * static_cast<float>(col) - 0.5F * static_cast<float>(row); }

void fill(test::TestHeightMap& m) {
    for (std::int32_t row = 0; row < kGrid.rows; ++row) {
        for (std::int32_t col = 0; col < kGrid.cols; ++col) {
            if (!(col == 2 && row == 1)) m.put(col, row, elevationOf(col, row));
        }
    }
}

std::uint32_t u32At(const std::vector<unsigned char>& b, std::size_t at) {
    return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8U |
           static_cast<std::uint32_t>(b[at + 2]) << 16U | static_cast<std::uint32_t>(b[at + 3]) << 24U;
}

TEST(PlyMesh, CountsVerticesAndFacesAroundHoles) {
    test::TestHeightMap m(kGrid);
    fill(m);
    // 11 cells with data; of the 6 blocks of 2x2 cells, the two in column 0 have four cells
    // with data; the others touch the hole at (2, 1).
    const MeshCounts c = meshCounts(m.map());
    EXPECT_EQ(c.vertices, 11);
    EXPECT_EQ(c.faces, 4);
}

TEST(PlyMesh, SkipsBlocksAcrossAStepLargerThanTheLimit) {
    test::TestHeightMap m(kGrid);
    fill(m);
    m.put(0, 0, 3.0F);  // highest reducer: cell (0, 0) is now 3 m, a 3.5 m step to (0, 1)
    EXPECT_EQ(meshCounts(m.map(), MeshOptions{1.0}).faces, 2);   // block (0, 0) dropped
    EXPECT_EQ(meshCounts(m.map(), MeshOptions{3.5}).faces, 4);   // the step is 3.5 m exactly: kept
    EXPECT_EQ(meshCounts(m.map()).faces, 4);                     // no limit
}

TEST(PlyMesh, VerticesAreCellCentresInTheSiteFrame) {
    test::TempDir dir;
    test::TestHeightMap m(kGrid);
    fill(m);
    const std::string path = dir.file("mesh.ply");
    ASSERT_TRUE(writeMeshPly(path, m.map()).ok);
    const Result<std::vector<Vec3>> r = readPlyPoints(path);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.size(), 11U);
    std::size_t i = 0;
    for (std::int32_t row = 0; row < 3; ++row) {
        for (std::int32_t col = 0; col < 4; ++col) {
            if (col == 2 && row == 1) continue;
            EXPECT_EQ(r.value[i], Vec3(9.5 - row, 20.5 + col, -static_cast<double>(elevationOf(col, row)))) << i;
            ++i;
        }
    }
}

TEST(PlyMesh, FacesIndexTheBlockCornersCounterClockwiseFromAbove) {
    test::TestHeightMap m(kGrid);
    fill(m);
    const std::vector<unsigned char> b = encodeMeshPly(m.map());
    const std::string text(b.begin(), b.end());
    const std::size_t body = text.find("end_header\n") + 11U;
    ASSERT_NE(text.find("element face 4\nproperty list uchar int vertex_indices\n"), std::string::npos);
    ASSERT_EQ(b.size(), body + 11U * 12U + 4U * 13U);
    // Vertices: row 0 -> 0..3, row 1 -> (0,1)=4 (1,1)=5 (3,1)=6, row 2 -> 7..10.
    const std::uint32_t expected[4][3] = {{0, 4, 1}, {1, 4, 5}, {4, 7, 5}, {5, 7, 8}};
    for (std::size_t f = 0; f < 4U; ++f) {
        const std::size_t at = body + 11U * 12U + f * 13U;
        EXPECT_EQ(b[at], 3U);
        for (std::size_t k = 0; k < 3U; ++k) EXPECT_EQ(u32At(b, at + 1U + 4U * k), expected[f][k]) << f << " " << k;
    }
    // NW (north 9.5, east 20.5), SW (8.5, 20.5), NE (9.5, 21.5): (SW - NW) x (NE - NW) has
    // z = (-1)(1) - 0 < 0, up in a z-down frame.
    const Vec3 nw(9.5, 20.5, 0.0), sw(8.5, 20.5, 0.0), ne(9.5, 21.5, 0.0);
    EXPECT_LT((sw - nw).cross(ne - nw).z(), 0.0);
}

TEST(PlyMesh, RefusesAnEmptyMapABadLimitAndAnUnwritablePath) {
    test::TempDir dir;
    test::TestHeightMap empty(kGrid);
    const std::string path = dir.file("mesh.ply");
    const Outcome e = writeMeshPly(path, empty.map());
    EXPECT_EQ(e.error, path + ": the height map has no cell with data; no mesh written");
    test::TestHeightMap m(kGrid);
    fill(m);
    const Outcome s = writeMeshPly(path, m.map(), MeshOptions{-1.0});
    EXPECT_NE(s.error.find(path + ": mesh max_step_m must be >= 0"), std::string::npos) << s.error;
    const std::string missing = dir.file("no/such/dir/mesh.ply");
    const Outcome w = writeMeshPly(missing, m.map());
    EXPECT_EQ(w.error, missing + ": cannot create: No such file or directory");
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace vtm::ground
