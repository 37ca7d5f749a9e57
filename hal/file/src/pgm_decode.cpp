#include "pgm_decode.hpp"

namespace vtm::hal::detail {
namespace {

// Netpbm whitespace: blank, tab, CR, LF, vertical tab, form feed.
bool isPnmSpace(std::uint8_t c) noexcept {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}
bool isDigit(std::uint8_t c) noexcept { return c >= '0' && c <= '9'; }

struct Cursor {
    const std::uint8_t* bytes;
    std::size_t size;
    std::size_t pos;
};

// Skips whitespace and '#' comments (to the end of the line) before a header number.
// Every pass advances by one byte, so `size` passes bound the loop.
void skipSpaceAndComments(Cursor& c) noexcept {
    bool in_comment = false;
    for (std::size_t pass = 0U; pass < c.size && c.pos < c.size; ++pass) {
        const std::uint8_t b = c.bytes[c.pos];
        if (in_comment) {
            in_comment = (b != '\n' && b != '\r');
        } else if (b == '#') {
            in_comment = true;
        } else if (!isPnmSpace(b)) {
            return;
        }
        ++c.pos;
    }
}

// Reads one header number: at least one whitespace (or comment) before it, decimal
// digits, and whitespace or a comment after it. Values above 99 999 999 are refused
// (larger than any frame side or maxval), so the arithmetic cannot overflow.
Status readHeaderNumber(Cursor& c, std::uint32_t& value) noexcept {
    const std::size_t before = c.pos;
    skipSpaceAndComments(c);
    if (c.pos == c.size) {
        return Status(StatusCode::kCorruptData, "PGM: header truncated", static_cast<std::int64_t>(c.size));
    }
    if (c.pos == before || !isDigit(c.bytes[c.pos])) {
        return Status(StatusCode::kCorruptData, "PGM: header field is not a separated decimal number",
                      static_cast<std::int64_t>(c.pos));
    }
    std::uint32_t v = 0U;
    std::size_t digits = 0U;
    for (; c.pos < c.size && isDigit(c.bytes[c.pos]); ++c.pos) {
        ++digits;
        if (digits > 8U) {
            return Status(StatusCode::kCorruptData, "PGM: header number too large", static_cast<std::int64_t>(c.pos));
        }
        v = v * 10U + static_cast<std::uint32_t>(c.bytes[c.pos] - '0');
    }
    if (c.pos == c.size) {
        return Status(StatusCode::kCorruptData, "PGM: header truncated", static_cast<std::int64_t>(c.size));
    }
    if (!isPnmSpace(c.bytes[c.pos]) && c.bytes[c.pos] != '#') {
        return Status(StatusCode::kCorruptData, "PGM: header field is not a separated decimal number",
                      static_cast<std::int64_t>(c.pos));
    }
    value = v;
    return Status::ok();
}

struct PgmHeader {
    std::uint32_t width = 0U;
    std::uint32_t height = 0U;
    std::uint32_t maxval = 0U;
    std::size_t raster_offset = 0U;
};

Status readHeader(Cursor& c, PgmHeader& h) noexcept {
    if (c.size < 2U || c.bytes[0] != 'P' || c.bytes[1] != '5') {
        return Status(StatusCode::kCorruptData, "PGM: magic number is not P5");
    }
    c.pos = 2U;
    VTM_RETURN_IF_ERROR(readHeaderNumber(c, h.width));
    VTM_RETURN_IF_ERROR(readHeaderNumber(c, h.height));
    VTM_RETURN_IF_ERROR(readHeaderNumber(c, h.maxval));
    // Exactly one whitespace byte separates maxval from the raster (a comment may not).
    if (!isPnmSpace(c.bytes[c.pos])) {
        return Status(StatusCode::kCorruptData, "PGM: maxval not followed by one whitespace byte",
                      static_cast<std::int64_t>(c.pos));
    }
    h.raster_offset = c.pos + 1U;
    return Status::ok();
}

Status checkHeader(const PgmHeader& h, const FrameTarget& target) noexcept {
    if (h.width == 0U || h.height == 0U) {
        return Status(StatusCode::kCorruptData, "PGM: width or height is zero");
    }
    if (h.width != static_cast<std::uint32_t>(target.width())) {
        return Status(StatusCode::kSizeMismatch, kWidthMismatch, h.width);
    }
    if (h.height != static_cast<std::uint32_t>(target.height())) {
        return Status(StatusCode::kSizeMismatch, kHeightMismatch, h.height);
    }
    if (h.maxval == 0U || h.maxval > 65535U) {
        return Status(StatusCode::kCorruptData, "PGM: maxval outside 1..65535", h.maxval);
    }
    if (h.maxval > 255U && !target.wide()) {
        return Status(StatusCode::kSizeMismatch, kWideSamplesFor8Bit, h.maxval);
    }
    return Status::ok();
}

}  // namespace

Status decodePgm(const std::uint8_t* bytes, std::size_t size, const FrameTarget& target) noexcept {
    Cursor c{bytes, size, 0U};
    PgmHeader h;
    VTM_RETURN_IF_ERROR(readHeader(c, h));
    VTM_RETURN_IF_ERROR(checkHeader(h, target));
    const std::size_t sample_bytes = (h.maxval > 255U) ? 2U : 1U;
    const std::size_t row_bytes = static_cast<std::size_t>(h.width) * sample_bytes;
    const std::size_t raster_bytes = row_bytes * h.height;
    const std::size_t present = size - h.raster_offset;
    if (present < raster_bytes) {
        return Status(StatusCode::kCorruptData, "PGM: raster truncated",
                      static_cast<std::int64_t>(raster_bytes - present));
    }
    const FrameTarget checked = target.limitedTo(h.maxval, "PGM: sample exceeds maxval");
    for (std::int32_t y = 0; y < target.height(); ++y) {
        const std::uint8_t* row = bytes + h.raster_offset + static_cast<std::size_t>(y) * row_bytes;
        if (sample_bytes == 1U) {
            VTM_RETURN_IF_ERROR(checked.fillRow(y, [row](std::int32_t x) { return std::uint32_t{row[x]}; }));
        } else {
            // Netpbm: the most significant byte first, whatever the host's byte order.
            VTM_RETURN_IF_ERROR(checked.fillRow(y, [row](std::int32_t x) {
                const std::uint8_t* s = row + static_cast<std::ptrdiff_t>(x) * 2;
                return (std::uint32_t{s[0]} << 8U) | std::uint32_t{s[1]};
            }));
        }
    }
    return Status::ok();
}

}  // namespace vtm::hal::detail
