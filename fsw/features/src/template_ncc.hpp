// Normalised correlation of a warped template with windows of an 8-bit image (private to
// fsw/features; the template matcher's score). Every sum is an exact integer: the window's
// in 32 bits where it fits, the variances and the covariance in doubles (each below 2^53),
// so the scores are the same bits on every target and the same as int64 arithmetic gave.
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/math.hpp"

namespace vtm::features::detail {

// Template samples are bilinear with weights quantised to 1/kWeightOne, and stored in
// 1/kWeightOne grey levels (uint16, at most 255 * 256): all NCC sums stay exact integers.
constexpr std::int32_t kWeightShift = 8;
constexpr std::int32_t kWeightOne = 1 << kWeightShift;

struct Pos {
    std::int32_t x;
    std::int32_t y;
};

// A warped template: (2 half + 1)^2 values, row-major, in 1/kWeightOne grey levels, and
// its sums (setTemplateSums).
struct Template {
    const std::uint16_t* values = nullptr;
    double sum = 0.0;  // sum of the values
    double var = 0.0;  // n sum(v^2) - sum^2, n = (2 half + 1)^2; 0 for a flat template
};

// The window of `to` around a position: its sum and n sum(b^2) - sum^2.
struct WindowStats {
    double sum = 0.0;
    double var = 0.0;
};

// Fills t.sum and t.var from t.values.
void setTemplateSums(Template& t, std::int32_t half) noexcept;

// The window around b (which must fit) and its sums of products with `count` (1 or 2)
// templates, in one pass over the window: cross[i] for templates[i].
[[nodiscard]] WindowStats windowAndCrossSums(const Template* const* templates, std::int32_t count,
                                             const ImageView<const std::uint8_t>& to, Pos b, std::int32_t half,
                                             double* cross) noexcept;

// Column sums of an image over the rows y - half .. y + half, for the columns x0 .. x1 (which
// must lie in the image, as must the rows): sum[i] and sum_sq[i] for column x0 + i. Each
// fits 32 bits (31 rows of 255^2). A search that visits consecutive rows slides them
// (slideColumnSums) instead of summing the window anew at every position.
struct ColumnSums {
    std::uint32_t* sum = nullptr;
    std::uint32_t* sum_sq = nullptr;
    std::int32_t x0 = 0;
    std::int32_t x1 = -1;
    std::int32_t y = 0;  // the centre row they hold
    // The last window windowFromColumns() summed on this row (none after set or slide):
    // the next column's window is that one plus a column and minus another.
    std::int32_t window_x = 0;
    bool window_held = false;
    std::uint32_t window_sum = 0U;
    std::uint32_t window_sum_sq = 0U;
};

// Fills c for centre row y (c.x0, c.x1 and the arrays set by the caller).
void setColumnSums(ColumnSums& c, const ImageView<const std::uint8_t>& image, std::int32_t y,
                   std::int32_t half) noexcept;

// Moves c from centre row c.y to c.y + 1 (the row y + 1 + half must lie in the image).
void slideColumnSums(ColumnSums& c, const ImageView<const std::uint8_t>& image, std::int32_t half) noexcept;

// windowFromColumns() and nccIfAbove() are inline: the coarse search calls them for every
// position. The number of pixels of a window of half width `half`:
[[nodiscard]] inline double windowCount(std::int32_t half) noexcept {
    const std::int32_t side = 2 * half + 1;
    return static_cast<double>(side * side);
}

// A window's WindowStats from its exact sums of b and b^2.
[[nodiscard]] inline WindowStats statsOf(std::uint32_t sb, std::uint32_t sbb, std::int32_t half) noexcept {
    const double s = static_cast<double>(sb);
    return WindowStats{s, windowCount(half) * static_cast<double>(sbb) - s * s};
}

// The window around (x, c.y) from the column sums: the same WindowStats as
// windowAndCrossSums gives there (slid from the last window when that was at x - 1).
[[nodiscard]] inline WindowStats windowFromColumns(ColumnSums& c, std::int32_t x, std::int32_t half) noexcept {
    const std::int32_t side = 2 * half + 1;
    const std::int32_t left = x - half - c.x0;  // index of the window's first column
    std::uint32_t sb = 0U, sbb = 0U;            // at most 961 * 255^2 = 6.2e7
    if (c.window_held && x == c.window_x + 1) {
        // Modulo 2^32 like slideColumnSums: the result fits.
        sb = c.window_sum + c.sum[left + side - 1] - c.sum[left - 1];
        sbb = c.window_sum_sq + c.sum_sq[left + side - 1] - c.sum_sq[left - 1];
    } else {
        for (std::int32_t i = 0; i < side; ++i) {
            sb += c.sum[left + i];
            sbb += c.sum_sq[left + i];
        }
    }
    c.window_x = x;
    c.window_held = true;
    c.window_sum = sb;
    c.window_sum_sq = sbb;
    return statsOf(sb, sbb, half);
}

// The window's sums of products with `count` (1 or 2) templates only (its own sums come
// from windowFromColumns): cross[i] as windowAndCrossSums gives it.
void crossSums(const Template* const* templates, std::int32_t count, const ImageView<const std::uint8_t>& to, Pos b,
               std::int32_t half, double* cross) noexcept;

// Whether the matcher's coarse search uses crossSumsFloatRun: on the scalar targets with a
// hardware fused multiply-add (ppc750, riscv64), where it takes the rover's refine stage
// from 5.18e9 to 3.92e9 and 4.00e9 instructions. Not on aarch64, whose integer pass GCC
// vectorises (3.28e9 -> 3.50e9 with the float runs), nor without a fused multiply-add (x86-64:
// the host's rover refine 271 -> 315 ms with a first version of the float runs; armhf's
// VFPv3, leon3): those keep crossSums and plan no float copies. docs/features.md "The
// coarse search's products in floats".
#if defined(__FP_FAST_FMA) && !defined(__aarch64__)
constexpr bool kFloatProducts = true;
#else
constexpr bool kFloatProducts = false;
#endif

// The products of crossSums for a run of `run` (1..kMaxRun) positions b, b + (1, 0), ...
// that share their templates, from float copies of the templates and the image (toFloats;
// every value an integer below 2^24, exact in float), accumulated in doubles: each product
// is an integer below 2^24 and each sum one below 2^53, so no operation rounds and
// cross[k * count + i] (position k, template i) is the number crossSums gives there. Fused
// multiply-adds where the target has them (__FP_FAST_FMA), a product and a sum elsewhere:
// the same bits (the kernel is built and tested on every target, used where
// kFloatProducts). Why: on the 750 the integer pass costs eight instructions a pixel for
// one position; this one about 17 for four (a template value loaded once for the run).
// templates[i]: template i's values as floats (toFloats).
constexpr std::int32_t kMaxRun = 4;
void crossSumsFloatRun(const float* const* templates, std::int32_t count, const ImageView<const float>& to, Pos b,
                       std::int32_t run, std::int32_t half, double* cross) noexcept;

// dst[i] = values[i] for i < n (uint16 grey levels of a template, exact in float).
void toFloats(const std::uint16_t* values, std::int32_t n, float* dst) noexcept;

// dst = image, pixel by pixel, as floats (sizes equal; rows of dst contiguous).
void toFloats(const ImageView<const std::uint8_t>& image, float* dst) noexcept;

// The NCC from the sums; 0 when the template or the window is flat (undefined).
[[nodiscard]] double nccFromSums(const Template& t, const WindowStats& w, double cross, std::int32_t half) noexcept;

// Returned by nccIfAbove() for a score certainly not above the best: below every NCC.
constexpr double kNotAbove = -2.0;

// nccFromSums(), or kNotAbove when the NCC is certainly not above `best` (never for a
// negative best): decided without the square root, with a margin far above the rounding
// of either side, so a search keeping the first score above its best keeps the same best.
[[nodiscard]] inline double nccIfAbove(const Template& t, const WindowStats& w, double cross, std::int32_t half,
                                       double best) noexcept {
    if (!(t.var > 0.0) || !(w.var > 0.0)) {
        return 0.0;
    }
    // n cross <= 961 * 1.6e10 and t.sum * w.sum <= 6.3e7 * 2.5e5: both below 2^53, exact.
    const double cov = windowCount(half) * cross - t.sum * w.sum;
    // ncc > best >= 0 needs cov > 0 and cov^2 > best^2 var_t var_w, up to a few roundings
    // (1e-16 each): below that (with a margin of 1e-9) the root is not taken.
    if (best >= 0.0 && !(cov > 0.0)) {
        return kNotAbove;
    }
    const double p = t.var * w.var;
    if (best >= 0.0 && !(cov * cov >= (best * best) * p * (1.0 - 1e-9))) {
        return kNotAbove;
    }
    return cov / math::sqrt(p);
}

// NCC of the template with the window around b (which must fit).
[[nodiscard]] double ncc(const Template& t, const ImageView<const std::uint8_t>& to, Pos b, std::int32_t half) noexcept;

}  // namespace vtm::features::detail
