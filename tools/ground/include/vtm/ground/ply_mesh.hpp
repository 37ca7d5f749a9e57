// A triangle mesh of a height map as binary little-endian PLY (docs/geotiff.md "Mesh").
//
// Vertices: one per cell with data, at the cell's centre in the site frame as writePly
// states it (x north, y east, z down, metres; float): x = centreNorthM(row), y =
// centreEastM(col), z = -elevation. Numbered row by row from the north-west cell, the
// cells without data skipped.
// Faces: two triangles per 2x2 block of cells whose four cells all have data (none across
// NO_DATA) and whose elevations differ by at most MeshOptions::max_step_m (none across a
// cliff). Block (col, row) .. (col + 1, row + 1) gives (NW, SW, NE) and (NE, SW, SE):
// counter-clockwise seen from above, so the normals point up (-z).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "vtm/ground/image.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::ground {

struct MeshOptions {
    // A block whose highest and lowest of its four elevations differ by more than this
    // (metres) gets no faces. Default: no limit.
    double max_step_m = std::numeric_limits<double>::infinity();
};

// The mesh's size, for callers' summaries and the tests.
struct MeshCounts {
    std::int64_t vertices = 0;
    std::int64_t faces = 0;
};

// Counts of the mesh writeMeshPly would write for this map.
MeshCounts meshCounts(const terrain::HeightMap& map, const MeshOptions& options = {});

// The PLY file's bytes: header, float x y z per vertex, then per face a uchar 3 and three
// int32 vertex indices.
std::vector<unsigned char> encodeMeshPly(const terrain::HeightMap& map, const MeshOptions& options = {});

// Writes the mesh. Refused (one line naming the file): a map without a cell with data, a
// negative or NaN max_step_m, a file that cannot be written.
Outcome writeMeshPly(const std::string& path, const terrain::HeightMap& map, const MeshOptions& options = {});

}  // namespace vtm::ground
