// One warped row of image 2 (warp_row.hpp).
#include "warp_row.hpp"

#include <algorithm>
#include <cmath>

namespace vtm::descent::detail {
namespace {

// One warped row: 32 u = (h0 x + bx) / W and 32 v = (h3 x + by) / W with W = h6 x + bw, in
// image 2 when |32 u - cu| <= cu and |32 v - cv| <= cv (and W > 0).
struct RowWarp {
    double h0, bx, h3, by, h6, bw;
    double cu, cv;
};

// [lo, hi] narrowed to the x where a x + b >= 0 (a line, so a half-line or all or none).
void keepWhereNonNegative(double a, double b, double& lo, double& hi) noexcept {
    if (a > 0.0) {
        lo = std::max(lo, -b / a);
    } else if (a < 0.0) {
        hi = std::min(hi, b / -a);
    } else if (!(b >= 0.0)) {
        hi = lo - 1.0;  // none
    }
}

// Margin of the spans' inequalities in 32 u units (1/32 px): the per-pixel expression's
// rounding is below 1e-10 of them.
constexpr double kSpanMargin = 1.0;
constexpr double kSpanMinW = 1e-9;

// Whether every term of the row is finite (else nothing is certain about it).
bool finiteRow(const RowWarp& r) noexcept {
    const double terms[8] = {r.h0, r.bx, r.h3, r.by, r.h6, r.bw, r.cu, r.cv};
    for (const double t : terms) {
        if (!std::isfinite(t)) {
            return false;
        }
    }
    return true;
}

// The x (as doubles, within [0, width - 1]) where W >= min_w and margin <= 32 u <= 2 cu -
// margin, the same for v: an interval, the intersection of half-lines; lo > hi when
// empty. margin > 0: inside image 2 with that to spare; margin < 0 (and min_w 0): a set
// holding every x whose position is inside. A finite row (finiteRow) only.
void spanWhere(const RowWarp& r, std::int32_t width, double margin, double min_w, double& lo, double& hi) noexcept {
    lo = 0.0;
    hi = static_cast<double>(width - 1);
    const double m = margin;
    keepWhereNonNegative(r.h6, r.bw - min_w, lo, hi);
    keepWhereNonNegative(r.h0 - m * r.h6, r.bx - m * r.bw, lo, hi);
    keepWhereNonNegative((2.0 * r.cu - m) * r.h6 - r.h0, (2.0 * r.cu - m) * r.bw - r.bx, lo, hi);
    keepWhereNonNegative(r.h3 - m * r.h6, r.by - m * r.bw, lo, hi);
    keepWhereNonNegative((2.0 * r.cv - m) * r.h6 - r.h3, (2.0 * r.cv - m) * r.bw - r.by, lo, hi);
}

// A warped row's columns in three kinds: [first, last] certainly inside image 2 (no
// per-pixel test), outside [maybe_first, maybe_last] certainly outside (0), the rest (a
// column or two at each end of the inside part) tested pixel by pixel. One column of
// slack on each side for the rounding of the bounds; first > last: none certainly inside.
struct RowSpans {
    std::int32_t maybe_first, maybe_last, first, last;
};
RowSpans rowSpans(const RowWarp& r, std::int32_t width) noexcept {
    RowSpans s{0, width - 1, 0, -1};
    if (!finiteRow(r)) {
        return s;  // every column tested
    }
    double lo = 0.0, hi = 0.0;
    spanWhere(r, width, -kSpanMargin, 0.0, lo, hi);
    if (!(lo <= hi)) {
        s.maybe_last = -1;  // no column can be inside
        return s;
    }
    // lo, hi in [0, width - 1]: truncation is floor.
    s.maybe_first = std::max(0, static_cast<std::int32_t>(lo) - 1);
    s.maybe_last = std::min(width - 1, static_cast<std::int32_t>(hi) + 2);
    spanWhere(r, width, kSpanMargin, kSpanMinW, lo, hi);
    if (lo + 2.0 <= hi) {
        s.first = static_cast<std::int32_t>(lo) + 1;
        s.last = static_cast<std::int32_t>(hi) - 1;
    }
    return s;
}

// Image 2 at row position x (a double: no conversion per pixel): the bilinear sample in
// levels x 16, or 0 outside image 2 or behind camera 2 when kTest; without kTest the caller
// knows the position is inside (rowSpans). The same value either way where it is inside.
template <bool kTest>
float warpPixel(const RowWarp& r, double xd, const std::uint16_t* src, std::int32_t w) noexcept {
    const double W = r.h6 * xd + r.bw;
    if (kTest && !(W > 0.0)) {
        return 0.0F;
    }
    const double inv = 1.0 / W;
    const double pu = (r.h0 * xd + r.bx) * inv;  // 32 u
    const double pv = (r.h3 * xd + r.by) * inv;  // 32 v
    if (kTest && !(std::fabs(pu - r.cu) <= r.cu && std::fabs(pv - r.cv) <= r.cv)) {
        return 0.0F;
    }
    // floor(32 u + 0.5): 32 u > -0.5 here (rounding at the lower edge can let through a
    // value a hair below 0), so truncation is the floor, the same integers as std::floor
    // without its libm call on the 750 (no rounding instruction). Not lround: halves go up.
    const auto ui = static_cast<std::int32_t>(pu + 0.5);  // NOLINT(bugprone-incorrect-roundings)
    const auto vi = static_cast<std::int32_t>(pv + 0.5);  // NOLINT(bugprone-incorrect-roundings)
    const std::int32_t ix = ui >> kSubpixelBits;
    const std::int32_t fx = ui & (kSubpixel - 1);
    const std::int32_t iy = vi >> kSubpixelBits;
    const std::int32_t fy = vi & (kSubpixel - 1);
    // At the last column (row) fx (fy) is 0: the pixel after it, the next row's first or
    // the padding row (prefilter()), enters with weight 0.
    const std::uint16_t* p = src + static_cast<std::ptrdiff_t>(iy) * w + ix;
    const auto top = static_cast<std::uint32_t>(p[0] * (kSubpixel - fx) + p[1] * fx);
    const auto bottom = static_cast<std::uint32_t>(p[w] * (kSubpixel - fx) + p[w + 1] * fx);
    const std::uint32_t sum =
        top * static_cast<std::uint32_t>(kSubpixel - fy) + bottom * static_cast<std::uint32_t>(fy);
    return static_cast<float>(static_cast<std::int32_t>((sum + 512U) >> 10U));
}

// Columns [x0, x1) of a warped row.
template <bool kTest>
void warpColumns(const RowWarp& r, std::int32_t x0, std::int32_t x1, const std::uint16_t* src, std::int32_t w,
                 float* out) noexcept {
    double xd = static_cast<double>(x0);  // x as a double without a conversion per pixel (exact)
    for (std::int32_t x = x0; x < x1; ++x) {
        out[x] = warpPixel<kTest>(r, xd, src, w);
        xd += 1.0;
    }
}

}  // namespace

void warpRow(const double* h, std::int32_t y, std::int32_t x0, std::int32_t x1, const std::uint16_t* image2,
             std::int32_t width, std::int32_t height, float* out) noexcept {
    // The first two rows times 32: u * 32 = (32 X) / W exactly (a power of two), so the
    // 1/32 px positions are the same integers as from u itself, one multiply fewer.
    // Image 2's extent in 1/32 px, as centre and half-width: |32 u - cu| <= cu is
    // 0 <= 32 u <= 32 (width - 1), i.e. u inside (a rounded difference cannot leave the
    // interval [-cu, cu] from inside it), and it is false for NaN.
    const double s = static_cast<double>(kSubpixel);
    const double yd = static_cast<double>(y);
    const RowWarp r{s * h[0], s * (h[1] * yd + h[2]), s * h[3], s * (h[4] * yd + h[5]), h[6], h[7] * yd + h[8],
                    0.5 * s * static_cast<double>(width - 1), 0.5 * s * static_cast<double>(height - 1)};
    const RowSpans spans = rowSpans(r, width);
    // Clipped to [x0, x1): certainly outside before `from` and from `to` on.
    const std::int32_t from = std::min(std::max(spans.maybe_first, x0), x1);
    const std::int32_t to = std::max(std::min(spans.maybe_last + 1, x1), from);
    std::fill(out + x0, out + from, 0.0F);
    const std::int32_t first = std::max(spans.first, from);
    const std::int32_t last = std::min(spans.last, to - 1);
    if (first > last) {
        warpColumns<true>(r, from, to, image2, width, out);
    } else {
        warpColumns<true>(r, from, first, image2, width, out);
        warpColumns<false>(r, first, last + 1, image2, width, out);
        warpColumns<true>(r, last + 1, to, image2, width, out);
    }
    std::fill(out + to, out + x1, 0.0F);
}

void spanMappedInside(const double* h, double dx, double y, std::int32_t width, std::int32_t height, double& lo,
                      double& hi) noexcept {
    // In image-2 pixels (no 1/32 scale), the column offset dx folded into the row terms.
    const RowWarp r{h[0], h[0] * dx + (h[1] * y + h[2]), h[3], h[3] * dx + (h[4] * y + h[5]), h[6],
                    h[6] * dx + (h[7] * y + h[8]), 0.5 * static_cast<double>(width - 1),
                    0.5 * static_cast<double>(height - 1)};
    if (!finiteRow(r)) {
        lo = 0.0;
        hi = static_cast<double>(width - 1);
        return;
    }
    spanWhere(r, width, -kSpanMargin / static_cast<double>(kSubpixel), 0.0, lo, hi);
    if (lo <= hi) {
        lo = std::max(0.0, lo - 2.0);  // the bounds' own rounding
        hi = std::min(static_cast<double>(width - 1), hi + 2.0);
    }
}

}  // namespace vtm::descent::detail
