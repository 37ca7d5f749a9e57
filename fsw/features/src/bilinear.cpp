// The bilinear samplers of fsw/features (bilinear.hpp).
#include "bilinear.hpp"

#include <algorithm>
#include <cstddef>

#include "floor_int.hpp"
#include "template_ncc.hpp"

namespace vtm::features::detail {
namespace {

// The cell whose two rows start at r0 and r1 (its left column) blended with the quantised
// weights wx, wy in 0..kWeightOne, in 1/kWeightOne grey levels, rounded.
std::uint16_t blendQuantised(const std::uint8_t* r0, const std::uint8_t* r1, std::int32_t wx,
                             std::int32_t wy) noexcept {
    const std::int32_t top = r0[0] * (kWeightOne - wx) + r0[1] * wx;
    const std::int32_t bottom = r1[0] * (kWeightOne - wx) + r1[1] * wx;
    return static_cast<std::uint16_t>((top * (kWeightOne - wy) + bottom * wy + kWeightOne / 2) >> kWeightShift);
}

// The grid's point at offset (dx, dy), with the roundings sampleQuantisedGrid states.
void gridPoint(double cx, double cy, const Affine2& m, double dx, double dy, double& x, double& y) noexcept {
    x = cx + (m.a * dx + m.b * dy);
    y = cy + (m.c * dx + m.d * dy);
}

// Whether every point of the grid lies in [0, width - 1) x [0, height - 1), where
// sampleQuantised's clamps change nothing and its corner is the truncation. Each
// coordinate, as computed, is monotone in dx and in dy separately (a rounded sum of
// rounded products: every rounding is monotone), so its extremes are at the corners.
bool gridInside(const ImageView<const std::uint8_t>& img, double cx, double cy, const Affine2& m,
                std::int32_t half) noexcept {
    const double h = static_cast<double>(half);
    const double xmax = static_cast<double>(img.width() - 1), ymax = static_cast<double>(img.height() - 1);
    for (std::int32_t k = 0; k < 4; ++k) {
        double x = 0.0, y = 0.0;
        gridPoint(cx, cy, m, (k & 1) != 0 ? h : -h, (k & 2) != 0 ? h : -h, x, y);
        if (!(x >= 0.0 && x < xmax && y >= 0.0 && y < ymax)) {
            return false;
        }
    }
    return true;
}

// sampleQuantisedGrid where gridInside holds.
void fillInside(const ImageView<const std::uint8_t>& img, double cx, double cy, const Affine2& m, std::int32_t half,
                std::uint16_t* dst) noexcept {
    const double ma = m.a, mb = m.b, mc = m.c, md = m.d;
    const double one = static_cast<double>(kWeightOne);
    const std::uint8_t* base = img.data();
    const std::ptrdiff_t stride = img.stride();
    for (std::int32_t dy = -half; dy <= half; ++dy) {
        const double vy = static_cast<double>(dy);
        const double bx = mb * vy, by = md * vy;
        double vx = static_cast<double>(-half);  // exact: a small integer
        for (std::int32_t k = -half; k <= half; ++k) {
            const double x = cx + (ma * vx + bx);
            const double y = cy + (mc * vx + by);
            vx += 1.0;
            const auto x0 = static_cast<std::int32_t>(x);  // x >= 0: the floor
            const auto y0 = static_cast<std::int32_t>(y);
            // roundToInt(v) = floor(v + 0.5) of a weight v in [0, kWeightOne]: v + 0.5 > 0,
            // so the truncation is that floor (the same value, no std::lround).
            const double ux = (x - static_cast<double>(x0)) * one + 0.5;
            const double uy = (y - static_cast<double>(y0)) * one + 0.5;
            const auto wx = static_cast<std::int32_t>(ux);
            const auto wy = static_cast<std::int32_t>(uy);
            const std::uint8_t* r0 = base + static_cast<std::ptrdiff_t>(y0) * stride + x0;
            *dst++ = blendQuantised(r0, r0 + stride, wx, wy);
        }
    }
}

// sampleLinear's cell along one axis: the corner (the floor of x, at most last) and the
// fraction x - corner, the same values.
struct Cell {
    std::int32_t i;
    double f;
};
Cell cellOf(double x, std::int32_t last) noexcept {
    std::int32_t i = static_cast<std::int32_t>(x);
    double id = static_cast<double>(i);
    if (id > x) {  // floorToInt
        --i;
        id -= 1.0;
    }
    if (i > last) {
        i = last;
        id = static_cast<double>(last);
    }
    return {i, x - id};
}

// sampleLinear's interpolation along a row at cell c.
double lerpRow(const std::uint8_t* row, Cell c) noexcept {
    const double g0 = static_cast<double>(row[c.i]);
    return g0 + c.f * (static_cast<double>(row[c.i + 1]) - g0);
}

double between(double top, double bottom, double f) noexcept { return top + f * (bottom - top); }

}  // namespace

std::uint16_t sampleQuantised(const ImageView<const std::uint8_t>& img, double x, double y) noexcept {
    const double xc = std::clamp(x, 0.0, static_cast<double>(img.width() - 1));
    const double yc = std::clamp(y, 0.0, static_cast<double>(img.height() - 1));
    const std::int32_t x0 = std::min(floorToInt(xc), img.width() - 2);
    const std::int32_t y0 = std::min(floorToInt(yc), img.height() - 2);
    const std::int32_t wx = roundToInt((xc - static_cast<double>(x0)) * static_cast<double>(kWeightOne));
    const std::int32_t wy = roundToInt((yc - static_cast<double>(y0)) * static_cast<double>(kWeightOne));
    return blendQuantised(img.row(y0) + x0, img.row(y0 + 1) + x0, wx, wy);
}

void sampleQuantisedGrid(const ImageView<const std::uint8_t>& img, double cx, double cy, const Affine2& m,
                         std::int32_t half, std::uint16_t* dst) noexcept {
    if (gridInside(img, cx, cy, m, half)) {
        fillInside(img, cx, cy, m, half, dst);
        return;
    }
    for (std::int32_t dy = -half; dy <= half; ++dy) {
        for (std::int32_t dx = -half; dx <= half; ++dx) {
            double x = 0.0, y = 0.0;
            gridPoint(cx, cy, m, static_cast<double>(dx), static_cast<double>(dy), x, y);
            *dst++ = sampleQuantised(img, x, y);
        }
    }
}

double sampleLinear(const ImageView<const std::uint8_t>& img, double x, double y) noexcept {
    const Cell cx = cellOf(x, img.width() - 2), cy = cellOf(y, img.height() - 2);
    return between(lerpRow(img.row(cy.i), cx), lerpRow(img.row(cy.i + 1), cx), cy.f);
}

// x +- step use the centre's rows; y +- step the centre's columns, and the centre's row
// interpolations where their rows are the centre's.
CrossSample sampleCross(const ImageView<const std::uint8_t>& img, double x, double y, double step) noexcept {
    const std::int32_t last_x = img.width() - 2, last_y = img.height() - 2;
    const Cell cx = cellOf(x, last_x), px = cellOf(x + step, last_x), mx = cellOf(x - step, last_x);
    const Cell cy = cellOf(y, last_y), py = cellOf(y + step, last_y), my = cellOf(y - step, last_y);
    const std::uint8_t* base = img.data();
    const std::ptrdiff_t stride = img.stride();
    const std::uint8_t* r0 = base + static_cast<std::ptrdiff_t>(cy.i) * stride;
    const std::uint8_t* r1 = r0 + stride;
    const double c0 = lerpRow(r0, cx), c1 = lerpRow(r1, cx);
    const auto centreColumns = [&](std::int32_t r) {
        return r == cy.i ? c0 : (r == cy.i + 1 ? c1 : lerpRow(base + static_cast<std::ptrdiff_t>(r) * stride, cx));
    };
    CrossSample s{};
    s.value = between(c0, c1, cy.f);
    s.gx = between(lerpRow(r0, px), lerpRow(r1, px), cy.f) - between(lerpRow(r0, mx), lerpRow(r1, mx), cy.f);
    s.gy = between(centreColumns(py.i), centreColumns(py.i + 1), py.f) -
           between(centreColumns(my.i), centreColumns(my.i + 1), my.f);
    return s;
}

}  // namespace vtm::features::detail
