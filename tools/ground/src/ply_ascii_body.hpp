// The data of an ASCII PLY file after its header: one element per line (ply_reader.hpp).
#pragma once

#include <string>
#include <vector>

#include "ply_header.hpp"
#include "vtm/core/eigen.hpp"

namespace vtm::ground::detail {

// Appends the vertices' x, y, z to `points`; returns "" or one line naming `name`, the
// line and what is wrong.
std::string readAsciiPlyBody(const std::vector<unsigned char>& bytes, const std::string& name, const PlyHeader& h,
                             const PlyVertexLayout& layout, std::vector<Vec3>& points);

}  // namespace vtm::ground::detail
