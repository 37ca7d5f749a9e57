#include "vtm/ground/pfm.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "file_bytes.hpp"

namespace vtm::ground {
namespace {

// Largest side we accept: far beyond any camera, small enough that width * height * 4
// cannot overflow and a corrupt header cannot ask for gigabytes.
constexpr long kMaxSidePx = 1L << 16;

bool isSpace(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Reads one white-space separated token starting at `pos`; pos ends just after it.
std::string nextToken(const std::vector<unsigned char>& b, std::size_t& pos) {
    while (pos < b.size() && isSpace(b[pos])) {
        ++pos;
    }
    std::string token;
    while (pos < b.size() && !isSpace(b[pos]) && token.size() < 32U) {
        token.push_back(static_cast<char>(b[pos++]));
    }
    return token;
}

bool parseLong(const std::string& s, long& v) {
    char* end = nullptr;
    v = std::strtol(s.c_str(), &end, 10);
    return !s.empty() && *end == '\0';
}

bool parseDouble(const std::string& s, double& v) {
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0' && std::isfinite(v);
}

// Bytes <-> float through the integer bit pattern, so the file's byte order is explicit
// and independent of the host's.
float floatFromBytes(const unsigned char* p, bool little_endian) {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) {
        const unsigned shift = little_endian ? 8U * static_cast<unsigned>(i) : 8U * static_cast<unsigned>(3 - i);
        bits |= static_cast<std::uint32_t>(p[i]) << shift;
    }
    float f = 0.0F;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

void appendLittleEndian(std::vector<unsigned char>& out, float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    for (unsigned i = 0; i < 4U; ++i) {
        out.push_back(static_cast<unsigned char>((bits >> (8U * i)) & 0xFFU));
    }
}

struct PfmHeader {
    long width = 0;
    long height = 0;
    bool little_endian = true;
    std::size_t data_offset = 0;
};

// Parses "Pf <w> <h> <scale>" plus the single white-space byte that ends the header.
Result<PfmHeader> parseHeader(const std::vector<unsigned char>& b, const std::string& name) {
    std::size_t pos = 0;
    const std::string magic = nextToken(b, pos);
    if (magic == "PF") {
        return Result<PfmHeader>::failure(name + ": colour PFM (PF) not supported; need a one-channel PFM (Pf)");
    }
    if (magic != "Pf") {
        return Result<PfmHeader>::failure(name + ": not a PFM file (no 'Pf' signature)");
    }
    PfmHeader h;
    double scale = 0.0;
    const std::string w = nextToken(b, pos);
    const std::string ht = nextToken(b, pos);
    const std::string s = nextToken(b, pos);
    if (!parseLong(w, h.width) || !parseLong(ht, h.height) || h.width <= 0 || h.height <= 0 ||
        h.width > kMaxSidePx || h.height > kMaxSidePx) {
        return Result<PfmHeader>::failure(name + ": PFM header: bad size '" + w + " " + ht + "'");
    }
    if (!parseDouble(s, scale) || scale == 0.0 || pos >= b.size() || !isSpace(b[pos])) {
        return Result<PfmHeader>::failure(name + ": PFM header: bad scale '" + s + "' (nonzero number)");
    }
    h.little_endian = scale < 0.0;
    h.data_offset = pos + 1U;
    return Result<PfmHeader>::success(h);
}

}  // namespace

std::vector<unsigned char> encodePfm(const FloatImage& image) {
    const std::string header = "Pf\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1\n";
    std::vector<unsigned char> out(header.begin(), header.end());
    out.reserve(out.size() + image.pixels.size() * 4U);
    for (std::int32_t y = image.height - 1; y >= 0; --y) {  // bottom row first
        for (std::int32_t x = 0; x < image.width; ++x) {
            appendLittleEndian(out, image.at(x, y));
        }
    }
    return out;
}

Result<FloatImage> decodePfm(const std::vector<unsigned char>& bytes, const std::string& name) {
    Result<PfmHeader> h = parseHeader(bytes, name);
    if (!h.ok) {
        return Result<FloatImage>::failure(h.error);
    }
    const auto w = static_cast<std::int32_t>(h.value.width);
    const auto ht = static_cast<std::int32_t>(h.value.height);
    const std::size_t need = static_cast<std::size_t>(w) * static_cast<std::size_t>(ht) * 4U;
    const std::size_t have = bytes.size() - h.value.data_offset;
    if (have < need) {
        return Result<FloatImage>::failure(name + ": truncated PFM: " + std::to_string(need) +
                                           " bytes of pixels expected, " + std::to_string(have) + " found");
    }
    FloatImage img(w, ht);
    const unsigned char* p = bytes.data() + h.value.data_offset;
    for (std::int32_t y = ht - 1; y >= 0; --y) {  // bottom row first
        for (std::int32_t x = 0; x < w; ++x, p += 4) {
            img.at(x, y) = floatFromBytes(p, h.value.little_endian);
        }
    }
    return Result<FloatImage>::success(std::move(img));
}

Result<FloatImage> readPfm(const std::string& path) {
    Result<detail::Bytes> bytes = detail::readFileBytes(path);
    if (!bytes.ok) {
        return Result<FloatImage>::failure(bytes.error);
    }
    return decodePfm(bytes.value, path);
}

Outcome writePfm(const std::string& path, const FloatImage& image) {
    if (image.empty() || image.channels != 1) {
        return Outcome::failure(path + ": cannot write an empty or multi-channel image as PFM");
    }
    return detail::writeFileBytes(path, encodePfm(image));
}

bool looksLikePfm(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
        return false;
    }
    unsigned char head[3] = {0, 0, 0};
    const std::size_t n = std::fread(head, 1, sizeof head, f);
    (void)std::fclose(f);
    return n == 3U && head[0] == 'P' && (head[1] == 'f' || head[1] == 'F') && isSpace(head[2]);
}

}  // namespace vtm::ground
