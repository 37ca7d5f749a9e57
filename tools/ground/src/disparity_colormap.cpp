#include "vtm/ground/disparity_colormap.hpp"

#include <algorithm>
#include <cmath>

namespace vtm::ground {
namespace {

// Hue sweep from red (0 deg) to purple (270 deg).
constexpr double kPurpleHueDeg = 270.0;

std::uint8_t channel(double v) { return static_cast<std::uint8_t>(std::lround(255.0 * v)); }

// HSV -> RGB with S = V = 1, for hue in [0, 300] degrees: six 60-degree sectors.
Rgb hueToRgb(double hue_deg) {
    const double sector = hue_deg / 60.0;
    const int s = std::min(static_cast<int>(sector), 4);
    const double f = sector - s;  // position inside the sector, 0..1
    switch (s) {
        case 0: return {channel(1.0), channel(f), channel(0.0)};        // red -> yellow
        case 1: return {channel(1.0 - f), channel(1.0), channel(0.0)};  // yellow -> green
        case 2: return {channel(0.0), channel(1.0), channel(f)};        // green -> cyan
        case 3: return {channel(0.0), channel(1.0 - f), channel(1.0)};  // cyan -> blue
        default: return {channel(f), channel(0.0), channel(1.0)};       // blue -> purple
    }
}

}  // namespace

Rgb disparityColor(float d_px, float d_lo_px, float d_hi_px) {
    if (!std::isfinite(d_px)) {
        return {0, 0, 0};
    }
    const double span = static_cast<double>(d_hi_px) - static_cast<double>(d_lo_px);
    const double t = (span > 0.0) ? std::clamp((static_cast<double>(d_px) - d_lo_px) / span, 0.0, 1.0) : 1.0;
    return hueToRgb((1.0 - t) * kPurpleHueDeg);
}

GreyImage colorizeDisparity(const FloatImage& disparity_px, float d_lo_px, float d_hi_px) {
    GreyImage rgb(disparity_px.width, disparity_px.height, 3);
    for (std::int32_t y = 0; y < disparity_px.height; ++y) {
        for (std::int32_t x = 0; x < disparity_px.width; ++x) {
            const Rgb c = disparityColor(disparity_px.at(x, y), d_lo_px, d_hi_px);
            for (std::int32_t k = 0; k < 3; ++k) {
                rgb.at(x, y, k) = c[static_cast<std::size_t>(k)];
            }
        }
    }
    return rgb;
}

}  // namespace vtm::ground
