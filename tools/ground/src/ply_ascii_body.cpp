#include "ply_ascii_body.hpp"

#include <cmath>
#include <cstdlib>
#include <string_view>

namespace vtm::ground::detail {
namespace {

constexpr std::size_t kMaxTokenChars = 64;

bool isBlank(unsigned char c) { return c == ' ' || c == '\t' || c == '\r'; }

// The data lines: white-space separated values, line numbers counted from the file's start.
class AsciiBody {
public:
    AsciiBody(const std::vector<unsigned char>& b, const std::string& name, const PlyHeader& h)
        : b_(b), name_(name), pos_(h.data_offset), line_(h.lines) {}
    std::string read(const PlyHeader& h, const PlyVertexLayout& layout, std::vector<Vec3>& points);

private:
    bool nextLine();
    std::string instance(const PlyElement& e, std::size_t index, const PlyVertexLayout& layout, Vec3& v);
    std::string number(std::size_t token, double& value) const;
    std::string fail(const std::string& what) const {
        return name_ + ": PLY line " + std::to_string(line_) + ": " + what;
    }
    const std::vector<unsigned char>& b_;
    const std::string& name_;
    std::size_t pos_;
    std::size_t line_;
    std::vector<std::string_view> tokens_;
};

// Reads the next line that holds anything into tokens_; false at the end of the file.
bool AsciiBody::nextLine() {
    tokens_.clear();
    while (tokens_.empty() && pos_ < b_.size()) {
        ++line_;
        while (pos_ < b_.size() && b_[pos_] != '\n') {
            while (pos_ < b_.size() && isBlank(b_[pos_])) ++pos_;
            const std::size_t start = pos_;
            while (pos_ < b_.size() && b_[pos_] != '\n' && !isBlank(b_[pos_])) ++pos_;
            if (pos_ > start) {
                tokens_.emplace_back(reinterpret_cast<const char*>(b_.data()) + start, pos_ - start);
            }
        }
        if (pos_ < b_.size()) ++pos_;  // the '\n'
    }
    return !tokens_.empty();
}

std::string AsciiBody::number(std::size_t token, double& value) const {
    if (token >= tokens_.size()) return fail("fewer values than the element declares");
    const std::string_view t = tokens_[token];
    if (t.size() > kMaxTokenChars) return fail("value " + std::to_string(token + 1U) + " is too long");
    const std::string s(t);
    char* end = nullptr;
    value = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size()) return fail("value " + std::to_string(token + 1U) + " '" + s + "' is not a number");
    return "";
}

std::string AsciiBody::instance(const PlyElement& e, std::size_t index, const PlyVertexLayout& layout, Vec3& v) {
    std::size_t token = 0;
    for (std::size_t p = 0; p < e.properties.size(); ++p) {
        double value = 0.0;
        std::string error = number(token++, value);
        if (!error.empty()) return error;
        if (e.properties[p].is_list) {
            if (!(value >= 0.0 && value <= static_cast<double>(tokens_.size())) || value != std::floor(value)) {
                return fail("list length '" + std::string(tokens_[token - 1U]) + "' does not fit the line");
            }
            for (auto items = static_cast<std::size_t>(value); items > 0U; --items) {
                error = number(token++, value);
                if (!error.empty()) return error;
            }
            continue;
        }
        const int axis = layout.axisOf(index, p);
        if (axis >= 0) {
            v[axis] = e.properties[p].type == PlyType::kFloat32 ? static_cast<double>(static_cast<float>(value)) : value;
        }
    }
    if (token != tokens_.size()) {
        return fail(std::to_string(tokens_.size()) + " values, " + e.name + " declares " + std::to_string(token));
    }
    return "";
}

std::string AsciiBody::read(const PlyHeader& h, const PlyVertexLayout& layout, std::vector<Vec3>& points) {
    for (std::size_t k = 0; k < h.elements.size(); ++k) {
        const PlyElement& e = h.elements[k];
        // Each element needs a line of at least two bytes (a value and '\n', the last one's optional).
        if (e.count > (b_.size() - pos_ + 1U) / 2U) {
            return name_ + ": PLY declares " + std::to_string(e.count) + " " + e.name + " elements, but only " +
                   std::to_string(b_.size() - pos_) + " bytes follow line " + std::to_string(line_);
        }
        if (k == layout.element) points.reserve(static_cast<std::size_t>(e.count));
        for (std::uint64_t i = 0; i < e.count; ++i) {
            if (!nextLine()) {
                return name_ + ": PLY: the file ends after line " + std::to_string(line_) + ", at " + e.name + " " +
                       std::to_string(i + 1U) + " of " + std::to_string(e.count);
            }
            Vec3 v = Vec3::Zero();
            const std::string error = instance(e, k, layout, v);
            if (!error.empty()) return error;
            if (k == layout.element) points.push_back(v);
        }
    }
    if (nextLine()) return fail("data after the last element (wrong counts in the header?)");
    return "";
}

}  // namespace

std::string readAsciiPlyBody(const std::vector<unsigned char>& bytes, const std::string& name, const PlyHeader& h,
                             const PlyVertexLayout& layout, std::vector<Vec3>& points) {
    return AsciiBody(bytes, name, h).read(h, layout, points);
}

}  // namespace vtm::ground::detail
