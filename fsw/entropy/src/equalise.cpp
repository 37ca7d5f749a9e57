// Grey-level equalisation before the entropy image, global and local (equalise.hpp).
#include "equalise.hpp"

namespace vtm::entropy::detail {

void equalise(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst,
              std::int32_t fillMax) noexcept {
    std::uint32_t counts[256] = {};
    for (std::int32_t y = 0; y < src.height(); ++y) {
        const std::uint8_t* r = src.row(y);
        for (std::int32_t x = 0; x < src.width(); ++x) {
            ++counts[r[x]];
        }
    }
    std::uint8_t table[256] = {};
    std::uint64_t n = 0U;
    for (std::int32_t v = fillMax + 1; v < 256; ++v) {
        n += counts[v];
    }
    std::uint64_t below = 0U;
    std::uint64_t first = 0U;
    for (std::int32_t v = fillMax + 1; v < 256; ++v) {
        below += counts[v];
        if (first == 0U) {
            first = below;
        }
        const std::uint64_t span = n > first ? n - first : 1U;
        const std::uint64_t above = below > first ? below - first : 0U;
        table[v] = static_cast<std::uint8_t>((above * 255U + span / 2U) / span);
    }
    for (std::int32_t y = 0; y < src.height(); ++y) {
        const std::uint8_t* r = src.row(y);
        std::uint8_t* d = dst.row(y);
        for (std::int32_t x = 0; x < src.width(); ++x) {
            d[x] = table[r[x]];
        }
    }
}

namespace {

// The level counts (256) and group counts (16 of 16 levels) of the samples in a window.
struct RankCounts {
    std::uint16_t* level;
    std::uint16_t* group;
    std::int32_t n;
};

// Adds (sign +1) or removes (-1) column x, rows y0..y1, skipping fill.
void moveColumn(RankCounts& c, const ImageView<const std::uint8_t>& src, std::int32_t x, std::int32_t y0,
                std::int32_t y1, std::int32_t fillMax, std::int32_t sign) noexcept {
    for (std::int32_t y = y0; y <= y1; ++y) {
        const std::uint8_t v = src.row(y)[x];
        if (static_cast<std::int32_t>(v) > fillMax) {
            c.level[v] = static_cast<std::uint16_t>(c.level[v] + sign);
            c.group[v >> 4U] = static_cast<std::uint16_t>(c.group[v >> 4U] + sign);
            c.n += sign;
        }
    }
}

// 256 (2 below + equal) / (2 n), at most 255, for grey level v.
std::uint8_t rankOf(const RankCounts& c, std::uint8_t v) noexcept {
    std::uint32_t below = 0U;
    const std::uint32_t g = static_cast<std::uint32_t>(v) >> 4U;
    for (std::uint32_t i = 0U; i < g; ++i) {
        below += c.group[i];
    }
    for (std::uint32_t i = g << 4U; i < v; ++i) {
        below += c.level[i];
    }
    const std::uint32_t twice = 2U * below + c.level[v];
    const std::uint32_t r = (256U * twice) / (2U * static_cast<std::uint32_t>(c.n));
    return static_cast<std::uint8_t>(r < 255U ? r : 255U);
}

}  // namespace

void localRank(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst, std::int32_t radius,
               std::int32_t fillMax, Span<std::uint16_t> counts) noexcept {
    const std::int32_t w = src.width();
    const std::int32_t h = src.height();
    RankCounts c{counts.data(), counts.data() + 256, 0};
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::size_t i = 0U; i < kRankCounts; ++i) {
            counts[i] = 0U;
        }
        c.n = 0;
        const std::int32_t y0 = y - radius > 0 ? y - radius : 0;
        const std::int32_t y1 = y + radius < h - 1 ? y + radius : h - 1;
        for (std::int32_t x = 0; x <= radius && x < w; ++x) {
            moveColumn(c, src, x, y0, y1, fillMax, 1);
        }
        const std::uint8_t* in = src.row(y);
        std::uint8_t* out = dst.row(y);
        for (std::int32_t x = 0; x < w; ++x) {
            out[x] = static_cast<std::int32_t>(in[x]) > fillMax ? rankOf(c, in[x]) : 0U;
            if (x - radius >= 0) {
                moveColumn(c, src, x - radius, y0, y1, fillMax, -1);
            }
            if (x + radius + 1 < w) {
                moveColumn(c, src, x + radius + 1, y0, y1, fillMax, 1);
            }
        }
    }
}

}  // namespace vtm::entropy::detail
