#include "plan.hpp"

#include "sum_lanes.hpp"

#include "vtm/core/math.hpp"

namespace vtm::stereo::detail {
namespace {

// -ln f(D) + ln f(0) for D^2 = d2 / F px^2.
double negLogLikelihood(const Config& c, const Plan& p, std::int32_t d2) noexcept {
    const double sigma = static_cast<double>(c.inlier_sigma_px16) / 16.0;
    const double alpha = static_cast<double>(c.inlier_percent) / 100.0;
    const double fOut = static_cast<double>(c.outlier_level_percent) / 100.0;
    const double dd = static_cast<double>(d2) / static_cast<double>(p.d2Scale);
    const double g = math::exp(-dd / (2.0 * sigma * sigma));
    const double f = c.outlier_enabled ? alpha * g + (1.0 - alpha) * fOut : g;
    const double f0 = c.outlier_enabled ? alpha + (1.0 - alpha) * fOut : 1.0;
    return math::log(f0) - math::log(f);
}

// Nearest integer of a non-negative value, halves up. (Truncating v + 0.5 is exact for
// the table values here, all far from the rare doubles where v + 0.5 itself rounds up.)
std::int32_t roundNonNegative(double v) noexcept {
    return static_cast<std::int32_t>(v + 0.5);  // NOLINT(bugprone-incorrect-roundings): v >= 0, see above
}

std::int32_t log2Exact(std::int32_t v) noexcept {
    std::int32_t n = 0;
    for (std::int32_t i = 0; i < 31 && (1 << n) < v; ++i) {
        ++n;
    }
    return n;
}

}  // namespace

Plan makePlan(const Config& c) noexcept {
    Plan p;
    p.width = c.max_width;
    p.height = c.max_height;
    p.disparities = c.d_max - c.d_min + 1;
    p.half = c.window / 2;
    p.bins = c.intensity_bins;
    p.binShift = 8 - log2Exact(c.intensity_bins);
    const std::int32_t radius16 = c.truncation_sigmas * c.inlier_sigma_px16;  // r in 1/16 px
    p.radius = c.distance_transform_enabled ? (radius16 + 15) / 16 : 0;
    // F as large as the 8-bit store allows: r^2 F <= 255 (at least 1).
    const std::int32_t r2 = p.radius * p.radius;
    p.d2Scale = (r2 > 0) ? (255 / r2 > 0 ? 255 / r2 : 1) : 16;
    // Intensity axis: s = beta * (256 / Q) px per bin, weight F s^2 per bin^2 (rounded).
    const double s = (static_cast<double>(c.beta_q10) / 1024.0) * (256.0 / static_cast<double>(c.intensity_bins));
    const double w = static_cast<double>(p.d2Scale) * s * s;
    p.binWeight = roundNonNegative(w) > 0 ? roundNonNegative(w) : 1;
    // Without a DT the cap is the truncation radius along the intensity axis alone.
    const std::int32_t capFromRadius16 = (radius16 * radius16 * p.d2Scale + 128) / 256;
    p.d2Cap = (p.radius > 0) ? r2 * p.d2Scale : (capFromRadius16 < 255 ? capFromRadius16 : 255);
    p.d2Cap = p.d2Cap > 0 ? p.d2Cap : 1;
    std::int32_t reach = 0;
    for (std::int32_t k = 1; k < 256 && p.binWeight * k * k <= p.d2Cap; ++k) {
        reach = k;
    }
    p.binReach = reach;
    const std::int32_t area = c.window * c.window;
    p.maxCost = (65535 / area < 255) ? 65535 / area : 255;  // window sums fit 16 bits
    // A prior's search centre may lie up to `disparities` columns outside the right image
    // (compute() clamps it there): that many more columns of padding on each side.
    p.padLeft = (c.d_max > 0 ? c.d_max : 0) + p.disparities;
    // kSlotGroup more on the right: a pixel's last cost word may read up to kSlotGroup - 1
    // slots past its D costs (window_sums.cpp), i.e. columns right of centre - d_min.
    p.dtStride = p.width + p.padLeft + (c.d_min < 0 ? -c.d_min : 0) + p.disparities + kSlotGroup;
    p.costStride = p.width + 2 * p.half;
    p.slotStride = (p.disparities + kSlotGroup - 1) / kSlotGroup * kSlotGroup;
    const double top = negLogLikelihood(c, p, p.d2Cap);
    p.costPerNat = static_cast<double>(p.maxCost) / (top > 0.0 ? top : 1.0);
    return p;
}

void buildCostTable(const Config& c, const Plan& p, std::uint8_t* table) noexcept {
    for (std::int32_t d2 = 0; d2 < 256; ++d2) {
        const double v = (d2 <= p.d2Cap) ? negLogLikelihood(c, p, d2) * p.costPerNat
                                         : static_cast<double>(p.maxCost);
        const std::int32_t q = roundNonNegative(v);
        table[d2] = static_cast<std::uint8_t>(q < p.maxCost ? q : p.maxCost);
    }
}

}  // namespace vtm::stereo::detail
