#include "pnm_decode.hpp"

namespace vtm::ground::detail {
namespace {

constexpr long kMaxSidePx = 1L << 16;

bool isSpace(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

// Skips white space and '#' comments (to end of line), as Netpbm allows in headers.
void skipSpaceAndComments(const unsigned char* d, std::size_t n, std::size_t& pos) {
    while (pos < n && (isSpace(d[pos]) || d[pos] == '#')) {
        if (d[pos] == '#') {
            while (pos < n && d[pos] != '\n') {
                ++pos;
            }
        } else {
            ++pos;
        }
    }
}

// A decimal header field; -1 when there is none or it is absurdly long.
long headerNumber(const unsigned char* d, std::size_t n, std::size_t& pos) {
    skipSpaceAndComments(d, n, pos);
    long v = 0;
    int digits = 0;
    while (pos < n && d[pos] >= '0' && d[pos] <= '9' && digits < 9) {
        v = v * 10 + (d[pos++] - '0');
        ++digits;
    }
    return (digits > 0 && (pos >= n || isSpace(d[pos]))) ? v : -1;
}

void copySamples(const unsigned char* p, std::size_t count, DecodedImage& out) {
    if (out.sixteen_bit) {
        out.words.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            out.words[i] = static_cast<std::uint16_t>((p[2 * i] << 8) | p[2 * i + 1]);  // big endian
        }
    } else {
        out.bytes.assign(p, p + count);
    }
}

}  // namespace

bool isBinaryPnm(const unsigned char* data, std::size_t size) {
    return size >= 2U && data[0] == 'P' && (data[1] == '5' || data[1] == '6');
}

bool decodePnm(const unsigned char* data, std::size_t size, DecodedImage& out, std::string& reason) {
    if (!isBinaryPnm(data, size)) {
        reason = "not a binary PGM/PPM (P5/P6)";
        return false;
    }
    std::size_t pos = 2;
    const long w = headerNumber(data, size, pos);
    const long h = headerNumber(data, size, pos);
    const long maxval = headerNumber(data, size, pos);
    if (w <= 0 || h <= 0 || w > kMaxSidePx || h > kMaxSidePx || maxval <= 0 || maxval > 65535 || pos >= size) {
        reason = "bad PGM/PPM header (width, height, maxval 1..65535)";
        return false;
    }
    ++pos;  // the single white-space byte that ends the header
    out.width = static_cast<int>(w);
    out.height = static_cast<int>(h);
    out.channels = (data[1] == '5') ? 1 : 3;
    out.sixteen_bit = maxval > 255;
    const std::size_t count = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) *
                              static_cast<std::size_t>(out.channels);
    const std::size_t need = count * (out.sixteen_bit ? 2U : 1U);
    if (size - pos < need) {
        reason = "truncated: " + std::to_string(need) + " bytes of pixels expected, " + std::to_string(size - pos) +
                 " found";
        return false;
    }
    copySamples(data + pos, count, out);
    return true;
}

}  // namespace vtm::ground::detail
