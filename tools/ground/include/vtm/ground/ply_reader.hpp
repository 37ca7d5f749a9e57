// Points of a user's PLY file, for `vtm integrate` (docs/geotiff.md "PLY reader").
//
// Accepted: "format ascii 1.0" and "format binary_little_endian 1.0"; any elements, each
// with scalar properties (char/int8 ... double/float64) and list properties (integer
// count type), in any order; comment and obj_info lines. Exactly one element "vertex" with
// properties x, y and z, each float or double (not a list); every other property and
// element is read past and dropped. ASCII: one element per line, blank lines ignored.
// The points are returned as stored (a float widened to double, NaN and inf included);
// VTM takes them as site-frame metres (x north, y east, z down), as writePly writes them.
//
// Refused, with one line naming the file and the reason (header line, data line or byte):
// not "ply", binary_big_endian or another format, an unknown keyword or type, a header over
// 64 KiB, more than 16 elements or 64 properties per element, no vertex x/y/z of float or
// double, more than kMaxPlyVertices vertices, counts the data cannot hold, truncated data,
// values that are not numbers, bytes or lines after the last element, a file over
// kMaxPlyFileBytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vtm/core/eigen.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::ground {

// 4096 x 4096: a point per cell of the largest height map (terrain::kMaxGridSide).
constexpr std::uint64_t kMaxPlyVertices = std::uint64_t{1} << 24;
constexpr std::uint64_t kMaxPlyFileBytes = std::uint64_t{1} << 30;  // 1 GiB

// Points from PLY bytes; `name` (usually the path) goes into the error messages.
Result<std::vector<Vec3>> decodePlyPoints(const std::vector<unsigned char>& bytes, const std::string& name);
Result<std::vector<Vec3>> readPlyPoints(const std::string& path);

}  // namespace vtm::ground
