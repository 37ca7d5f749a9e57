#include "vtm/ground/ply_mesh.hpp"

#include <algorithm>
#include <cstddef>

#include "file_bytes.hpp"
#include "little_endian.hpp"

namespace vtm::ground {
namespace {

constexpr std::int32_t kNoVertex = -1;

// Vertex index of every cell (kNoVertex where there is no data), row by row from the north.
std::vector<std::int32_t> vertexIndices(const terrain::HeightMap& map, std::int64_t& vertices) {
    const terrain::GridConfig& g = map.grid();
    std::vector<std::int32_t> index(static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows), kNoVertex);
    std::int32_t next = 0;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            if (!terrain::isNoData(map.elevation(col, row))) {
                index[static_cast<std::size_t>(row) * static_cast<std::size_t>(g.cols) + static_cast<std::size_t>(col)] =
                    next++;
            }
        }
    }
    vertices = next;
    return index;
}

// True when the block with north-west cell (col, row) gets its two triangles.
bool blockMeshed(const terrain::HeightMap& map, std::int32_t col, std::int32_t row, double max_step_m) {
    const float z[4] = {map.elevation(col, row), map.elevation(col + 1, row), map.elevation(col, row + 1),
                        map.elevation(col + 1, row + 1)};
    for (const float v : z) {
        if (terrain::isNoData(v)) return false;
    }
    const auto [lo, hi] = std::minmax_element(z, z + 4);
    return static_cast<double>(*hi) - static_cast<double>(*lo) <= max_step_m;
}

// Calls face(nw, sw, ne) then face(ne, sw, se) (vertex indices) for every meshed block.
template <typename Face>
void forEachFace(const terrain::HeightMap& map, const std::vector<std::int32_t>& index, double max_step_m, Face face) {
    const terrain::GridConfig& g = map.grid();
    const auto at = [&](std::int32_t col, std::int32_t row) {
        return index[static_cast<std::size_t>(row) * static_cast<std::size_t>(g.cols) + static_cast<std::size_t>(col)];
    };
    for (std::int32_t row = 0; row + 1 < g.rows; ++row) {
        for (std::int32_t col = 0; col + 1 < g.cols; ++col) {
            if (!blockMeshed(map, col, row, max_step_m)) continue;
            face(at(col, row), at(col, row + 1), at(col + 1, row));
            face(at(col + 1, row), at(col, row + 1), at(col + 1, row + 1));
        }
    }
}

std::string meshHeader(const MeshCounts& counts) {
    return "ply\nformat binary_little_endian 1.0\n"
           "comment VTM height-map mesh, site frame (x north, y east, z down), metres; vertices at cell centres\n"
           "element vertex " + std::to_string(counts.vertices) +
           "\nproperty float x\nproperty float y\nproperty float z\n"
           "element face " + std::to_string(counts.faces) +
           "\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

MeshCounts meshCounts(const terrain::HeightMap& map, const MeshOptions& options) {
    MeshCounts counts;
    const std::vector<std::int32_t> index = vertexIndices(map, counts.vertices);
    forEachFace(map, index, options.max_step_m, [&](std::int32_t, std::int32_t, std::int32_t) { ++counts.faces; });
    return counts;
}

std::vector<unsigned char> encodeMeshPly(const terrain::HeightMap& map, const MeshOptions& options) {
    const MeshCounts counts = meshCounts(map, options);
    const std::string header = meshHeader(counts);
    std::vector<unsigned char> out(header.begin(), header.end());
    out.reserve(out.size() + static_cast<std::size_t>(counts.vertices) * 12U + static_cast<std::size_t>(counts.faces) * 13U);
    const terrain::GridConfig& g = map.grid();
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            const float up_m = map.elevation(col, row);
            if (terrain::isNoData(up_m)) continue;
            detail::appendF32LE(out, static_cast<float>(map.centreNorthM(row)));
            detail::appendF32LE(out, static_cast<float>(map.centreEastM(col)));
            detail::appendF32LE(out, -up_m);
        }
    }
    std::int64_t unused = 0;
    const std::vector<std::int32_t> index = vertexIndices(map, unused);
    forEachFace(map, index, options.max_step_m, [&](std::int32_t a, std::int32_t b, std::int32_t c) {
        out.push_back(3U);
        for (const std::int32_t v : {a, b, c}) detail::appendU32LE(out, static_cast<std::uint32_t>(v));
    });
    return out;
}

Outcome writeMeshPly(const std::string& path, const terrain::HeightMap& map, const MeshOptions& options) {
    if (!(options.max_step_m >= 0.0)) {
        return Outcome::failure(path + ": mesh max_step_m must be >= 0 metres, got " + std::to_string(options.max_step_m));
    }
    if (map.filledCells() == 0) {
        return Outcome::failure(path + ": the height map has no cell with data; no mesh written");
    }
    return detail::writeFileBytes(path, encodeMeshPly(map, options));
}

}  // namespace vtm::ground
