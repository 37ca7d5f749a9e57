// A smooth random texture for the stereo tests: uniform noise from `rng`, w x h, blurred
// by the 3-tap cross (the pixel's row and column neighbours, edges clamped) and scaled to
// lo + span * mean. Row-major. The noise is drawn before anything else, so a caller that
// keeps drawing from `rng` afterwards gets the same sequence as before.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vtm/core/random.hpp"

namespace vtm::stereo {

inline std::vector<double> smoothTexture(Random& rng, std::int32_t w, std::int32_t h, double lo, double span) {
    std::vector<double> noise(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (double& v : noise) {
        v = rng.uniform01();
    }
    std::vector<double> tex(noise.size());
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            double s = 0.0;
            for (std::int32_t k = -1; k <= 1; ++k) {
                const std::int32_t xx = x + k < 0 ? 0 : (x + k >= w ? w - 1 : x + k);
                const std::int32_t yy = y + k < 0 ? 0 : (y + k >= h ? h - 1 : y + k);
                s += noise[static_cast<std::size_t>(y * w + xx)] + noise[static_cast<std::size_t>(yy * w + x)];
            }
            tex[static_cast<std::size_t>(y * w + x)] = lo + span * s / 6.0;
        }
    }
    return tex;
}

}  // namespace vtm::stereo
