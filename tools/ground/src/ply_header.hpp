// The header of a PLY file (Greg Turk's format, as the PLY readers of meshlab, Open3D and
// PCL read it): format, elements and their properties. The subset ply_reader.hpp accepts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vtm/ground/image.hpp"

namespace vtm::ground::detail {

enum class PlyFormat : std::uint8_t { kAscii, kBinaryLittleEndian };

// Scalar types; PLY's old names (char, uchar, ...) and new ones (int8, uint8, ...) both.
enum class PlyType : std::uint8_t { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::kFloat32;        // scalar type, or a list's item type
    bool is_list = false;
    PlyType count_type = PlyType::kUInt8;    // a list's count type (an integer type)
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::kAscii;
    std::vector<PlyElement> elements;
    std::size_t data_offset = 0;  // first byte after "end_header\n"
    std::size_t lines = 0;        // lines of the header, "end_header" included
};

// Where a point's coordinates are: the vertex element and the index of x, y, z in its
// properties (ply_reader.cpp finds them).
struct PlyVertexLayout {
    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    std::size_t element = kNone;
    std::size_t axis[3] = {kNone, kNone, kNone};
    // The coordinate (0 x, 1 y, 2 z) that property p of element e holds, or -1.
    [[nodiscard]] int axisOf(std::size_t e, std::size_t p) const {
        if (e != element) return -1;
        for (int k = 0; k < 3; ++k) {
            if (axis[k] == p) return k;
        }
        return -1;
    }
};

// Bounds of what a header may declare (a corrupt header cannot ask for gigabytes).
constexpr std::size_t kMaxPlyHeaderBytes = 65536;
constexpr std::size_t kMaxPlyElements = 16;
constexpr std::size_t kMaxPlyProperties = 64;

std::size_t plyTypeBytes(PlyType type);
bool plyTypeIsInteger(PlyType type);

// Parses the header of `bytes`; errors name `name`, the header line and what is wrong.
Result<PlyHeader> parsePlyHeader(const std::vector<unsigned char>& bytes, const std::string& name);

}  // namespace vtm::ground::detail
