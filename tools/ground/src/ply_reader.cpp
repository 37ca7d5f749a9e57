#include "vtm/ground/ply_reader.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "file_bytes.hpp"
#include "little_endian.hpp"
#include "ply_ascii_body.hpp"
#include "ply_header.hpp"

namespace vtm::ground {
namespace {

using detail::PlyElement;
using detail::PlyFormat;
using detail::PlyHeader;
using detail::PlyProperty;
using detail::PlyType;
using Points = std::vector<Vec3>;

using VertexLayout = detail::PlyVertexLayout;
constexpr std::size_t kNone = VertexLayout::kNone;

std::string findAxes(const PlyElement& e, VertexLayout& layout) {
    static const char* const kAxes[3] = {"x", "y", "z"};
    for (std::size_t k = 0; k < 3U; ++k) {
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
            if (e.properties[p].name != kAxes[k]) continue;
            const PlyProperty& prop = e.properties[p];
            if (prop.is_list || (prop.type != PlyType::kFloat32 && prop.type != PlyType::kFloat64)) {
                return std::string("vertex property ") + kAxes[k] + " must be float or double";
            }
            if (layout.axis[k] != kNone) return std::string("vertex property ") + kAxes[k] + " appears twice";
            layout.axis[k] = p;
        }
        if (layout.axis[k] == kNone) return std::string("no vertex property ") + kAxes[k];
    }
    return "";
}

Result<VertexLayout> vertexLayout(const PlyHeader& h, const std::string& name) {
    VertexLayout layout;
    for (std::size_t i = 0; i < h.elements.size(); ++i) {
        if (h.elements[i].properties.empty()) {
            return Result<VertexLayout>::failure(name + ": PLY element '" + h.elements[i].name + "' has no properties");
        }
        if (h.elements[i].name != "vertex") continue;
        if (layout.element != kNone) return Result<VertexLayout>::failure(name + ": PLY has two 'vertex' elements");
        layout.element = i;
    }
    if (layout.element == kNone) return Result<VertexLayout>::failure(name + ": PLY has no 'vertex' element");
    const PlyElement& v = h.elements[layout.element];
    const std::string axes = findAxes(v, layout);
    if (!axes.empty()) return Result<VertexLayout>::failure(name + ": PLY " + axes);
    if (v.count > kMaxPlyVertices) {
        return Result<VertexLayout>::failure(name + ": PLY declares " + std::to_string(v.count) +
                                             " vertices, more than the " + std::to_string(kMaxPlyVertices) + " accepted");
    }
    return Result<VertexLayout>::success(layout);
}

// Smallest size of one instance of `e` in a binary file (lists empty).
std::uint64_t minimumBytes(const PlyElement& e) {
    std::uint64_t n = 0;
    for (const PlyProperty& p : e.properties) n += detail::plyTypeBytes(p.is_list ? p.count_type : p.type);
    return n;
}

// --- binary little endian -----------------------------------------------------------

class BinaryBody {
public:
    BinaryBody(const std::vector<unsigned char>& b, const std::string& name, std::size_t pos)
        : b_(b), name_(name), pos_(pos) {}
    std::string read(const PlyHeader& h, const VertexLayout& layout, Points& points);

private:
    std::string element(const PlyElement& e, std::size_t index, const VertexLayout& layout, Points& points);
    std::string take(std::uint64_t n, const PlyElement& e, std::uint64_t i);
    std::int64_t integerAt(PlyType type) const;
    const std::vector<unsigned char>& b_;
    const std::string& name_;
    std::size_t pos_;
};

// n in 64 bits: a list of 2^32 - 1 doubles must not wrap a 32-bit size_t (armhf, ppc750).
std::string BinaryBody::take(std::uint64_t n, const PlyElement& e, std::uint64_t i) {
    if (static_cast<std::uint64_t>(b_.size() - pos_) < n) {
        return name_ + ": truncated PLY: " + e.name + " " + std::to_string(i + 1U) + " of " + std::to_string(e.count) +
               " needs bytes " + std::to_string(pos_) + ".." + std::to_string(pos_ + n - 1U) + ", the file has " +
               std::to_string(b_.size());
    }
    return "";
}

std::int64_t BinaryBody::integerAt(PlyType type) const {
    const std::size_t n = detail::plyTypeBytes(type);
    const std::uint64_t u = detail::loadUnsignedLE(b_.data() + pos_, n);
    const bool is_signed = type == PlyType::kInt8 || type == PlyType::kInt16 || type == PlyType::kInt32;
    const std::uint64_t sign = std::uint64_t{1} << (8U * n - 1U);
    if (is_signed && (u & sign) != 0U) return -static_cast<std::int64_t>((~u + 1U) & ((sign << 1U) - 1U));
    return static_cast<std::int64_t>(u);
}

std::string BinaryBody::element(const PlyElement& e, std::size_t index, const VertexLayout& layout, Points& points) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
        Vec3 v = Vec3::Zero();
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            std::uint64_t n = detail::plyTypeBytes(prop.type);
            if (prop.is_list) {
                std::string error = take(detail::plyTypeBytes(prop.count_type), e, i);
                if (!error.empty()) return error;
                const std::int64_t items = integerAt(prop.count_type);
                if (items < 0) return name_ + ": PLY byte " + std::to_string(pos_) + ": negative list length";
                pos_ += detail::plyTypeBytes(prop.count_type);
                n *= static_cast<std::uint64_t>(items);  // items < 2^32, n < 2^35
            }
            std::string error = take(n, e, i);
            if (!error.empty()) return error;
            const int axis = layout.axisOf(index, p);
            if (axis >= 0) {
                v[axis] = prop.type == PlyType::kFloat32 ? static_cast<double>(detail::loadF32LE(b_.data() + pos_))
                                                         : detail::loadF64LE(b_.data() + pos_);
            }
            pos_ += static_cast<std::size_t>(n);  // n <= the bytes left (take)
        }
        if (index == layout.element) points.push_back(v);
    }
    return "";
}

std::string BinaryBody::read(const PlyHeader& h, const VertexLayout& layout, Points& points) {
    for (std::size_t k = 0; k < h.elements.size(); ++k) {
        const PlyElement& e = h.elements[k];
        const std::uint64_t left = b_.size() - pos_;
        if (e.count > left / minimumBytes(e)) {
            return name_ + ": PLY declares " + std::to_string(e.count) + " " + e.name + " elements of at least " +
                   std::to_string(minimumBytes(e)) + " bytes, but " + std::to_string(left) +
                   " bytes remain at byte " + std::to_string(pos_);
        }
        if (k == layout.element) points.reserve(static_cast<std::size_t>(e.count));
        const std::string error = element(e, k, layout, points);
        if (!error.empty()) return error;
    }
    if (pos_ != b_.size()) {
        return name_ + ": PLY has " + std::to_string(b_.size() - pos_) + " bytes after the last element (byte " +
               std::to_string(pos_) + "; wrong counts in the header?)";
    }
    return "";
}

}  // namespace

Result<Points> decodePlyPoints(const std::vector<unsigned char>& bytes, const std::string& name) {
    const Result<PlyHeader> h = detail::parsePlyHeader(bytes, name);
    if (!h.ok) return Result<Points>::failure(h.error);
    const Result<VertexLayout> layout = vertexLayout(h.value, name);
    if (!layout.ok) return Result<Points>::failure(layout.error);
    Points points;
    const std::string error =
        h.value.format == PlyFormat::kBinaryLittleEndian
            ? BinaryBody(bytes, name, h.value.data_offset).read(h.value, layout.value, points)
            : detail::readAsciiPlyBody(bytes, name, h.value, layout.value, points);
    if (!error.empty()) return Result<Points>::failure(error);
    return Result<Points>::success(std::move(points));
}

Result<Points> readPlyPoints(const std::string& path) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > kMaxPlyFileBytes) {
        return Result<Points>::failure(path + ": PLY file of " + std::to_string(size) + " bytes, over the " +
                                       std::to_string(kMaxPlyFileBytes) + " accepted");
    }
    Result<detail::Bytes> bytes = detail::readFileBytes(path);
    if (!bytes.ok) return Result<Points>::failure(bytes.error);
    return decodePlyPoints(bytes.value, path);
}

}  // namespace vtm::ground
