// The 3D distance transform of the search image over (x, y, intensity), truncated at
// radius r: D2(u, v, i) = min over right pixels (u', v') within r of
//   F (u - u')^2 + F (v - v')^2 + binWeight (i - bin(u', v'))^2,   capped at d2Cap.
// Truncation makes the exact transform local: a pixel farther than r contributes at
// least the cap. The x pass scatters every pixel into the bins and columns it can reach
// (bins within binReach, columns within r); the y pass takes the least over rows v +- r.
// Every stored D2 is at most d2Cap (the x pass starts from it and only lowers), so a
// candidate of at least d2Cap never wins a min: both passes skip those (the rows v +- r
// of the y pass, whose offset r^2 F is d2Cap itself; the far columns of the x pass).
#include <cstring>

#include "plan.hpp"

namespace vtm::stereo::detail {

void distanceTransformRowX(const Plan& p, const std::uint8_t* rightRow, std::int32_t width,
                           std::uint8_t* out) noexcept {
    const std::size_t rowBytes = static_cast<std::size_t>(p.bins) * static_cast<std::size_t>(p.width);
    std::memset(out, p.d2Cap, rowBytes);
    // reach[n]: the largest |k| with n^2 binWeight + k^2 F < d2Cap (-1: none), n = |i - b|
    // <= binReach <= 15 (binWeight >= 1 and d2Cap <= 255: plan.cpp); so |k| <= 15 too.
    // stamp[n][15 + k]: that D2 itself (below d2Cap, a byte), read instead of recomputed.
    std::int32_t reach[16];
    std::uint8_t stamp[16][31];
    for (std::int32_t n = 0; n < 16; ++n) {
        reach[n] = -1;
        for (std::int32_t k = 0; n <= p.binReach && k <= p.radius && n * n * p.binWeight + k * k * p.d2Scale < p.d2Cap;
             ++k) {
            reach[n] = k;
            const auto d2 = static_cast<std::uint8_t>(n * n * p.binWeight + k * k * p.d2Scale);
            stamp[n][15 + k] = d2;
            stamp[n][15 - k] = d2;
        }
    }
    for (std::int32_t u = 0; u < width; ++u) {
        const std::int32_t b = rightRow[u] >> p.binShift;
        const std::int32_t iLo = b - p.binReach < 0 ? 0 : b - p.binReach;
        const std::int32_t iHi = b + p.binReach >= p.bins ? p.bins - 1 : b + p.binReach;
        for (std::int32_t i = iLo; i <= iHi; ++i) {
            const std::int32_t n = i > b ? i - b : b - i;
            const std::int32_t r = reach[n];
            const std::int32_t kLo = u - r < 0 ? -u : -r;
            const std::int32_t kHi = u + r >= width ? width - 1 - u : r;
            const std::uint8_t* d2 = stamp[n] + 15;
            std::uint8_t* binRow = out + static_cast<std::ptrdiff_t>(i) * p.width + u;
            for (std::int32_t k = kLo; k <= kHi; ++k) {
                if (d2[k] < binRow[k]) {
                    binRow[k] = d2[k];
                }
            }
        }
    }
}

namespace {

// dst[u] = map(min(cur[u], add + min(a[u], b[u]))), map: the cost table (kMap) or none.
// dst may be cur (in place).
template <bool kMap>
void minOfRows(const std::uint8_t* cur, const std::uint8_t* a, const std::uint8_t* b, std::uint32_t add,
               std::int32_t width, const std::uint8_t* table, std::uint8_t* dst) noexcept {
#pragma GCC unroll 4
    for (std::int32_t u = 0; u < width; ++u) {
        const std::uint32_t va = a[u];
        const std::uint32_t vb = b[u];
        const std::uint32_t v = (va < vb ? va : vb) + add;
        const std::uint32_t c = cur[u];
        const std::uint32_t m = v < c ? v : c;
        dst[u] = kMap ? table[m] : static_cast<std::uint8_t>(m);
    }
}

// Ring rows v - k and v + k (k >= 1, k^2 F < d2Cap): both lower the y pass's minimum by
// the same k^2 F. Near the top and bottom of the image one of them may be missing; the
// other then stands in for it (the min is unchanged).
struct RowPair {
    std::size_t above;   // byte offsets of the x-pass rows in the ring
    std::size_t below;
    std::uint32_t add;   // k^2 F
};

}  // namespace

void distanceTransformRowY(const Plan& p, const RowGeometry& g, const std::uint8_t* ring,
                           const std::uint8_t* costTable, std::uint8_t* dtRow) noexcept {
    const std::int32_t slots = 2 * p.radius + 1;
    const std::size_t ringRow = static_cast<std::size_t>(p.bins) * static_cast<std::size_t>(p.width);
    const auto slotOf = [&](std::int32_t k) { return static_cast<std::size_t>((g.y + k) % slots) * ringRow; };
    // At most r <= 15 pairs (Config::validate: r <= 15 px).
    RowPair pairs[16];
    std::int32_t n = 0;
    for (std::int32_t k = 1; k <= p.radius && k * k * p.d2Scale < p.d2Cap && n < 16; ++k) {
        const bool above = g.y - k >= 0;
        const bool below = g.y + k < g.height;
        if (above || below) {
            pairs[n++] = {slotOf(above ? -k : k), slotOf(below ? k : -k), static_cast<std::uint32_t>(k * k * p.d2Scale)};
        }
    }
    const std::int32_t width = g.width;
    for (std::int32_t i = 0; i < p.bins; ++i) {
        if (g.binUsed[i] == 0U) {
            continue;
        }
        const std::size_t bin = static_cast<std::size_t>(i) * static_cast<std::size_t>(p.width);
        const std::uint8_t* row0 = ring + slotOf(0) + bin;
        std::uint8_t* dst = dtRow + static_cast<std::ptrdiff_t>(i) * p.dtStride + p.padLeft;
        if (n == 0) {
            minOfRows<true>(row0, row0, row0, 0U, width, costTable, dst);
            continue;
        }
        for (std::int32_t r = 0; r < n; ++r) {
            const std::uint8_t* cur = r == 0 ? row0 : dst;
            const std::uint8_t* a = ring + pairs[r].above + bin;
            const std::uint8_t* b = ring + pairs[r].below + bin;
            if (r + 1 == n) {
                minOfRows<true>(cur, a, b, pairs[r].add, width, costTable, dst);
            } else {
                minOfRows<false>(cur, a, b, pairs[r].add, width, costTable, dst);
            }
        }
    }
}

void removeLocalMean(const ImageView<const std::uint8_t>& in, std::int32_t window, std::int32_t* columns,
                     const ImageView<std::uint8_t>& out) noexcept {
    const std::int32_t w = in.width();
    const std::int32_t h = in.height();
    const std::int32_t r = window / 2;
    const std::int32_t area = window * window;
    const auto clampRow = [h](std::int32_t y) { return y < 0 ? 0 : (y >= h ? h - 1 : y); };
    const auto clampCol = [w](std::int32_t x) { return x < 0 ? 0 : (x >= w ? w - 1 : x); };
    // Column sums over rows y-r..y+r with replicated borders, kept running down the image.
    for (std::int32_t x = 0; x < w; ++x) {
        columns[x] = 0;
    }
    for (std::int32_t k = -r; k <= r; ++k) {
        const std::uint8_t* row = in.row(clampRow(k));
        for (std::int32_t x = 0; x < w; ++x) {
            columns[x] += row[x];
        }
    }
    for (std::int32_t y = 0; y < h; ++y) {
        if (y > 0) {
            const std::uint8_t* enter = in.row(clampRow(y + r));
            const std::uint8_t* leave = in.row(clampRow(y - r - 1));
            for (std::int32_t x = 0; x < w; ++x) {
                columns[x] += enter[x] - leave[x];
            }
        }
        // Window sum along the row, kept running across x.
        std::int32_t sum = 0;
        for (std::int32_t k = -r; k <= r; ++k) {
            sum += columns[clampCol(k)];
        }
        const std::uint8_t* src = in.row(y);
        std::uint8_t* dst = out.row(y);
        const auto emit = [&](std::int32_t x) {
            const std::int32_t mean = (sum + area / 2) / area;
            const std::int32_t v = 128 + 2 * (static_cast<std::int32_t>(src[x]) - mean);
            dst[x] = static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
        };
        // The columns x - r - 1 and x + r lie inside the image for x in [r + 1, w - r - 1):
        // there the window slides without the border's clamps (the same sums).
        const std::int32_t inner_lo = r + 1 < w ? r + 1 : w;
        const std::int32_t inner_hi = w - r - 1 > inner_lo ? w - r - 1 : inner_lo;
        emit(0);
        for (std::int32_t x = 1; x < inner_lo; ++x) {
            sum += columns[clampCol(x + r)] - columns[clampCol(x - r - 1)];
            emit(x);
        }
        for (std::int32_t x = inner_lo; x < inner_hi; ++x) {
            sum += columns[x + r] - columns[x - r - 1];
            emit(x);
        }
        for (std::int32_t x = inner_hi; x < w; ++x) {
            sum += columns[clampCol(x + r)] - columns[clampCol(x - r - 1)];
            emit(x);
        }
    }
}

}  // namespace vtm::stereo::detail
