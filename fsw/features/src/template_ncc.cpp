// Normalised correlation of a warped template with image windows (template_ncc.hpp).
#include "template_ncc.hpp"

#include "vtm/core/math.hpp"

namespace vtm::features::detail {
namespace {

// The largest window side whose whole sum of products fits 32 bits: 15 (225 products of at
// most 255 * 256 by 255: 3.75e9 < 2^32). Wider windows add their rows' sums in 64 bits
// (a row of 31 fits 32 bits: 5.2e8).
constexpr std::int32_t kMaxWindow32 = 15;
static_assert(std::uint64_t{kMaxWindow32} * kMaxWindow32 * (std::uint64_t{255U} * kWeightOne) * 255U < 0xFFFFFFFFULL,
              "the window's sum of products must fit 32 bits");
static_assert(31U * (255U * kWeightOne) * 255U < 0xFFFFFFFFU, "a row's sum of products must fit 32 bits");

// One pass over the window whose top-left pixel is rb: its sums of products with kCount
// templates and, when kOwnSums, its own sums. Sum: the products' accumulator, uint32 where
// the whole window's products fit (kMaxWindow32), else uint64 over rows summed in uint32
// (a row of 31 fits).
template <std::size_t kCount, typename Sum, bool kOwnSums>
WindowStats passOver(const Template* const* templates, const std::uint8_t* rb, std::int32_t stride,
                     std::int32_t half, double* cross) noexcept {
    const std::int32_t side = 2 * half + 1;
    const std::uint16_t* t[kCount];
    Sum sab[kCount];
    for (std::size_t i = 0; i < kCount; ++i) {
        t[i] = templates[i]->values;
        sab[i] = 0U;
    }
    std::uint32_t sb = 0U, sbb = 0U;  // at most 961 * 255^2 = 6.2e7
    for (std::int32_t dy = 0; dy < side; ++dy, rb += stride) {
        std::uint32_t row[kCount] = {};
        for (std::int32_t dx = 0; dx < side; ++dx) {
            const std::uint32_t vb = rb[dx];
            if constexpr (kOwnSums) {
                sb += vb;
                sbb += vb * vb;
            }
            for (std::size_t i = 0; i < kCount; ++i) {
                row[i] += static_cast<std::uint32_t>(t[i][dx]) * vb;
            }
        }
        for (std::size_t i = 0; i < kCount; ++i) {
            sab[i] += row[i];
            t[i] += side;
        }
    }
    for (std::size_t i = 0; i < kCount; ++i) {
        cross[i] = static_cast<double>(sab[i]);  // below 2^34: exact
    }
    if constexpr (kOwnSums) {
        return statsOf(sb, sbb, half);
    } else {
        return WindowStats{};  // not summed
    }
}

}  // namespace

void setTemplateSums(Template& t, std::int32_t half) noexcept {
    const std::int32_t n = (2 * half + 1) * (2 * half + 1);
    std::int64_t sum = 0, sum_sq = 0;
    for (std::int32_t i = 0; i < n; ++i) {
        const std::int64_t v = t.values[i];
        sum += v;
        sum_sq += v * v;
    }
    // Below 2^53 for a window of 31: exact in double.
    t.sum = static_cast<double>(sum);
    t.var = static_cast<double>(static_cast<std::int64_t>(n) * sum_sq - sum * sum);
}

WindowStats windowAndCrossSums(const Template* const* templates, std::int32_t count,
                               const ImageView<const std::uint8_t>& to, Pos b, std::int32_t half,
                               double* cross) noexcept {
    const std::int32_t side = 2 * half + 1;
    const std::uint8_t* rb = to.row(b.y - half) + (b.x - half);
    if (count > 1) {
        return side <= kMaxWindow32 ? passOver<2, std::uint32_t, true>(templates, rb, to.stride(), half, cross)
                                    : passOver<2, std::uint64_t, true>(templates, rb, to.stride(), half, cross);
    }
    return side <= kMaxWindow32 ? passOver<1, std::uint32_t, true>(templates, rb, to.stride(), half, cross)
                                : passOver<1, std::uint64_t, true>(templates, rb, to.stride(), half, cross);
}

// windowAndCrossSums' dispatch with the window's own sums left out. Not folded into one
// template with it: GCC 12 then keeps the one-template passes out of line on the 750
// (+17,000 instructions per searched feature on the matcher probe, measured).
void crossSums(const Template* const* templates, std::int32_t count, const ImageView<const std::uint8_t>& to, Pos b,
               std::int32_t half, double* cross) noexcept {
    const std::int32_t side = 2 * half + 1;
    const std::uint8_t* rb = to.row(b.y - half) + (b.x - half);
    if (count > 1 && side <= kMaxWindow32) {
        static_cast<void>(passOver<2, std::uint32_t, false>(templates, rb, to.stride(), half, cross));
    } else if (count > 1) {
        static_cast<void>(passOver<2, std::uint64_t, false>(templates, rb, to.stride(), half, cross));
    } else if (side <= kMaxWindow32) {
        static_cast<void>(passOver<1, std::uint32_t, false>(templates, rb, to.stride(), half, cross));
    } else {
        static_cast<void>(passOver<1, std::uint64_t, false>(templates, rb, to.stride(), half, cross));
    }
}

void setColumnSums(ColumnSums& c, const ImageView<const std::uint8_t>& image, std::int32_t y,
                   std::int32_t half) noexcept {
    const std::int32_t n = c.x1 - c.x0 + 1;
    for (std::int32_t i = 0; i < n; ++i) {
        c.sum[i] = 0U;
        c.sum_sq[i] = 0U;
    }
    c.window_held = false;
    for (std::int32_t dy = -half; dy <= half; ++dy) {
        const std::uint8_t* r = image.row(y + dy) + c.x0;
        for (std::int32_t i = 0; i < n; ++i) {
            const std::uint32_t v = r[i];
            c.sum[i] += v;
            c.sum_sq[i] += v * v;
        }
    }
    c.y = y;
}

void slideColumnSums(ColumnSums& c, const ImageView<const std::uint8_t>& image, std::int32_t half) noexcept {
    const std::int32_t n = c.x1 - c.x0 + 1;
    const std::uint8_t* in = image.row(c.y + 1 + half) + c.x0;
    const std::uint8_t* out = image.row(c.y - half) + c.x0;
    // Modulo 2^32 the intermediate may wrap; every final value fits (setColumnSums).
    for (std::int32_t i = 0; i < n; ++i) {
        const std::uint32_t a = in[i];
        const std::uint32_t r = out[i];
        c.sum[i] += a - r;
        c.sum_sq[i] += a * a - r * r;
    }
    ++c.y;
    c.window_held = false;
}

double nccFromSums(const Template& t, const WindowStats& w, double cross, std::int32_t half) noexcept {
    return nccIfAbove(t, w, cross, half, -1.0);
}

double ncc(const Template& t, const ImageView<const std::uint8_t>& to, Pos b, std::int32_t half) noexcept {
    const Template* one[1] = {&t};
    double cross = 0.0;
    const WindowStats w = windowAndCrossSums(one, 1, to, b, half, &cross);
    return nccFromSums(t, w, cross, half);
}

}  // namespace vtm::features::detail
