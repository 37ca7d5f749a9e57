#include "ply_header.hpp"

#include <cstdlib>
#include <sstream>

namespace vtm::ground::detail {
namespace {

// Splits a header line into white-space separated words.
std::vector<std::string> words(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    std::string w;
    while (in >> w) out.push_back(w);
    return out;
}

bool typeFromName(const std::string& s, PlyType& type) {
    static const struct {
        const char* old_name;
        const char* new_name;
        PlyType type;
    } kTypes[] = {{"char", "int8", PlyType::kInt8},       {"uchar", "uint8", PlyType::kUInt8},
                  {"short", "int16", PlyType::kInt16},    {"ushort", "uint16", PlyType::kUInt16},
                  {"int", "int32", PlyType::kInt32},      {"uint", "uint32", PlyType::kUInt32},
                  {"float", "float32", PlyType::kFloat32}, {"double", "float64", PlyType::kFloat64}};
    for (const auto& t : kTypes) {
        if (s == t.old_name || s == t.new_name) {
            type = t.type;
            return true;
        }
    }
    return false;
}

bool parseCount(const std::string& s, std::uint64_t& v) {
    if (s.empty() || s.size() > 19U || s.find_first_not_of("0123456789") != std::string::npos) return false;
    v = std::strtoull(s.c_str(), nullptr, 10);
    return true;
}

// The header line by line: the parser's state and its error messages.
class HeaderParser {
public:
    HeaderParser(const std::vector<unsigned char>& bytes, const std::string& name) : b_(bytes), name_(name) {}
    Result<PlyHeader> run();

private:
    bool nextLine(std::string& line);
    std::string fail(const std::string& what) const {
        return name_ + ": PLY header line " + std::to_string(h_.lines) + ": " + what;
    }
    std::string format(const std::vector<std::string>& w);
    std::string element(const std::vector<std::string>& w);
    std::string property(const std::vector<std::string>& w);
    std::string keyword(const std::vector<std::string>& w, bool& done);

    const std::vector<unsigned char>& b_;
    const std::string& name_;
    PlyHeader h_;
    std::size_t pos_ = 0;
    bool have_format_ = false;
};

bool HeaderParser::nextLine(std::string& line) {
    line.clear();
    while (pos_ < b_.size() && pos_ < kMaxPlyHeaderBytes && b_[pos_] != '\n') {
        line.push_back(static_cast<char>(b_[pos_++]));
    }
    if (pos_ >= b_.size() || b_[pos_] != '\n') return false;
    ++pos_;
    ++h_.lines;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
}

std::string HeaderParser::format(const std::vector<std::string>& w) {
    if (have_format_ || !h_.elements.empty()) return fail("'format' must come once, before the elements");
    if (w.size() != 3U || w[2] != "1.0") return fail("expected 'format <ascii|binary_little_endian> 1.0'");
    if (w[1] == "binary_big_endian") return fail("binary_big_endian is not supported (ascii or binary_little_endian)");
    if (w[1] == "ascii") {
        h_.format = PlyFormat::kAscii;
    } else if (w[1] == "binary_little_endian") {
        h_.format = PlyFormat::kBinaryLittleEndian;
    } else {
        return fail("unknown format '" + w[1] + "'");
    }
    have_format_ = true;
    return "";
}

std::string HeaderParser::element(const std::vector<std::string>& w) {
    if (!have_format_) return fail("'element' before 'format'");
    if (h_.elements.size() >= kMaxPlyElements) return fail("more than " + std::to_string(kMaxPlyElements) + " elements");
    PlyElement e;
    if (w.size() != 3U || !parseCount(w[2], e.count)) return fail("expected 'element <name> <count>'");
    e.name = w[1];
    h_.elements.push_back(e);
    return "";
}

std::string HeaderParser::property(const std::vector<std::string>& w) {
    if (h_.elements.empty()) return fail("'property' before any 'element'");
    PlyElement& e = h_.elements.back();
    if (e.properties.size() >= kMaxPlyProperties) return fail("more than " + std::to_string(kMaxPlyProperties) + " properties");
    PlyProperty p;
    if (w.size() == 3U && typeFromName(w[1], p.type)) {
        p.name = w[2];
    } else if (w.size() == 5U && w[1] == "list" && typeFromName(w[2], p.count_type) && typeFromName(w[3], p.type)) {
        if (!plyTypeIsInteger(p.count_type)) return fail("a list's count type must be an integer type");
        p.is_list = true;
        p.name = w[4];
    } else {
        return fail("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
    }
    e.properties.push_back(p);
    return "";
}

// One header line's keyword; sets done at end_header.
std::string HeaderParser::keyword(const std::vector<std::string>& w, bool& done) {
    if (w.empty()) return fail("empty line");
    if (w[0] == "comment" || w[0] == "obj_info") return "";
    if (w[0] == "format") return format(w);
    if (w[0] == "element") return element(w);
    if (w[0] == "property") return property(w);
    if (w[0] == "end_header" && w.size() == 1U) {
        if (!have_format_) return fail("'end_header' before 'format'");
        done = true;
        return "";
    }
    return fail("unknown keyword '" + w[0].substr(0, 32) + "'");
}

Result<PlyHeader> HeaderParser::run() {
    std::string line;
    if (!nextLine(line) || line != "ply") {
        return Result<PlyHeader>::failure(name_ + ": not a PLY file (first line is not 'ply')");
    }
    bool done = false;
    while (!done) {
        if (!nextLine(line)) {
            ++h_.lines;
            return Result<PlyHeader>::failure(fail("no 'end_header' in the first " +
                                                   std::to_string(kMaxPlyHeaderBytes) + " bytes (or the file ends)"));
        }
        const std::string error = keyword(words(line), done);
        if (!error.empty()) return Result<PlyHeader>::failure(error);
    }
    h_.data_offset = pos_;
    return Result<PlyHeader>::success(h_);
}

}  // namespace

std::size_t plyTypeBytes(PlyType type) {
    switch (type) {
        case PlyType::kInt8:
        case PlyType::kUInt8: return 1U;
        case PlyType::kInt16:
        case PlyType::kUInt16: return 2U;
        case PlyType::kInt32:
        case PlyType::kUInt32:
        case PlyType::kFloat32: return 4U;
        case PlyType::kFloat64: return 8U;
    }
    return 8U;
}

bool plyTypeIsInteger(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

Result<PlyHeader> parsePlyHeader(const std::vector<unsigned char>& bytes, const std::string& name) {
    return HeaderParser(bytes, name).run();
}

}  // namespace vtm::ground::detail
