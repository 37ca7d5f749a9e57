// Synthetic multi-modal scenes for the entropy tests: a procedural 8-bit "world" of flat
// and textured patches (integer arithmetic only, the same bytes on every target), an
// image of it, and a second "sensor's" image: the world warped by a known similarity and
// seen through a non-monotonic intensity response.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vtm/core/random.hpp"

namespace vtm::entropy::test {

constexpr std::int32_t kWorld = 256;

// splitmix64 of a key: per-pixel noise without state.
inline std::uint32_t hashNoise(std::uint64_t key) { return static_cast<std::uint32_t>(mixBits64(key) >> 40U); }

// kWorld x kWorld grey levels: a gentle gradient with 48 discs and boxes, each flat,
// noisy (one of three amplitudes) or striped.
inline std::vector<std::uint8_t> makeWorld(std::uint64_t seed) {
    std::vector<std::uint8_t> w(static_cast<std::size_t>(kWorld) * kWorld);
    for (std::int32_t y = 0; y < kWorld; ++y) {
        for (std::int32_t x = 0; x < kWorld; ++x) {
            w[static_cast<std::size_t>(y * kWorld + x)] = static_cast<std::uint8_t>(90 + (x + 2 * y) / 12);
        }
    }
    for (std::uint64_t k = 0; k < 48U; ++k) {
        const std::uint32_t h = hashNoise(seed * 1000U + k);
        const std::int32_t cx = static_cast<std::int32_t>(h % kWorld);
        const std::int32_t cy = static_cast<std::int32_t>((h / kWorld) % kWorld);
        const std::uint32_t g = hashNoise(seed * 1000U + k + 500U);
        const std::int32_t r = 6 + static_cast<std::int32_t>(g % 16U);
        const std::int32_t kind = static_cast<std::int32_t>((g >> 4U) % 5U);
        const std::int32_t level = 30 + static_cast<std::int32_t>((g >> 8U) % 190U);
        const bool disc = ((g >> 16U) & 1U) != 0U;
        for (std::int32_t y = cy - r; y <= cy + r; ++y) {
            for (std::int32_t x = cx - r; x <= cx + r; ++x) {
                if (x < 0 || y < 0 || x >= kWorld || y >= kWorld ||
                    (disc && (x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r)) {
                    continue;
                }
                std::int32_t v = level;
                const std::int32_t n = static_cast<std::int32_t>(
                    hashNoise(seed * 7919U + static_cast<std::uint64_t>(y * kWorld + x) * 31U + k) % 256U);
                if (kind == 1) v += (n - 128) / 8;
                if (kind == 2) v += (n - 128) / 3;
                if (kind == 3) v += (n - 128) * 2 / 3;
                if (kind == 4) v += ((x + y) / 3) % 2 == 0 ? 40 : -40;
                w[static_cast<std::size_t>(y * kWorld + x)] =
                    static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
            }
        }
    }
    return w;
}

// A second sensor's response: non-monotonic (folds the grey scale three times), so that no
// monotonic (let alone linear) relation maps one sensor's intensities to the other's.
inline std::uint8_t otherSensor(std::uint8_t v) {
    const std::int32_t t = (static_cast<std::int32_t>(v) * 3) % 510;
    return static_cast<std::uint8_t>(t < 255 ? t : 509 - t);
}

// The similarity p2 = s R (p1 - c1) + c2 + t of registration.hpp.
struct Similarity {
    double angle_rad = 0.0;
    double scale = 1.0;
    double tx = 0.0;
    double ty = 0.0;
};

// Image 1: the world's window at (offset, offset), size x size.
// With +-noise grey levels of pixel noise (a sensor's own).
inline std::vector<std::uint8_t> cameraImage(const std::vector<std::uint8_t>& world, std::int32_t size,
                                             std::int32_t offset, std::int32_t noise = 0) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(size) * size);
    for (std::int32_t y = 0; y < size; ++y) {
        for (std::int32_t x = 0; x < size; ++x) {
            std::int32_t v = world[static_cast<std::size_t>((y + offset) * kWorld + x + offset)];
            if (noise > 0) {
                v += static_cast<std::int32_t>(hashNoise(0x5EEDU + static_cast<std::uint64_t>(y * size + x)) %
                                               static_cast<std::uint32_t>(2 * noise + 1)) -
                     noise;
            }
            img[static_cast<std::size_t>(y * size + x)] = static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
        }
    }
    return img;
}

// Image 2 (size2 x size2): pixel q shows the world at image 1's point G^-1(q) (bilinear,
// test-side double), through otherSensor(), plus +-noise grey levels of pixel noise.
inline std::vector<std::uint8_t> secondSensorImage(const std::vector<std::uint8_t>& world, std::int32_t size1,
                                                   std::int32_t offset, std::int32_t size2, const Similarity& g,
                                                   std::int32_t noise, bool remap = true) {
    std::vector<std::uint8_t> img(static_cast<std::size_t>(size2) * size2);
    const double c1 = 0.5 * (size1 - 1);
    const double c2 = 0.5 * (size2 - 1);
    const double c = std::cos(g.angle_rad) / g.scale;
    const double s = std::sin(g.angle_rad) / g.scale;
    for (std::int32_t y = 0; y < size2; ++y) {
        for (std::int32_t x = 0; x < size2; ++x) {
            const double dx = x - c2 - g.tx;
            const double dy = y - c2 - g.ty;
            const double px = c * dx + s * dy + c1 + offset;  // R^T (q - c2 - t) / s + c1, in the world
            const double py = -s * dx + c * dy + c1 + offset;
            const auto x0 = static_cast<std::int32_t>(std::floor(px));
            const auto y0 = static_cast<std::int32_t>(std::floor(py));
            double v = 128.0;
            if (x0 >= 0 && y0 >= 0 && x0 + 1 < kWorld && y0 + 1 < kWorld) {
                const double ax = px - x0;
                const double ay = py - y0;
                auto at = [&](std::int32_t xx, std::int32_t yy) {
                    return static_cast<double>(world[static_cast<std::size_t>(yy * kWorld + xx)]);
                };
                v = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                    ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
            }
            const auto grey = static_cast<std::uint8_t>(std::lround(v));
            std::int32_t out = remap ? otherSensor(grey) : grey;
            if (noise > 0) {
                out += static_cast<std::int32_t>(hashNoise(0xABCDU + static_cast<std::uint64_t>(y * size2 + x)) %
                                                 static_cast<std::uint32_t>(2 * noise + 1)) -
                       noise;
            }
            img[static_cast<std::size_t>(y * size2 + x)] =
                static_cast<std::uint8_t>(out < 0 ? 0 : (out > 255 ? 255 : out));
        }
    }
    return img;
}

// Largest distance (px of image 2) between where two 2x3 transforms put image 1's four corners.
template <typename M>
double cornerError(const M& estimate, const M& truth, std::int32_t width1, std::int32_t height1) {
    double worst = 0.0;
    for (const double x : {0.0, static_cast<double>(width1 - 1)}) {
        for (const double y : {0.0, static_cast<double>(height1 - 1)}) {
            const double ex = estimate(0, 0) * x + estimate(0, 1) * y + estimate(0, 2);
            const double ey = estimate(1, 0) * x + estimate(1, 1) * y + estimate(1, 2);
            const double tx = truth(0, 0) * x + truth(0, 1) * y + truth(0, 2);
            const double ty = truth(1, 0) * x + truth(1, 1) * y + truth(1, 2);
            worst = std::max(worst, std::hypot(ex - tx, ey - ty));
        }
    }
    return worst;
}

}  // namespace vtm::entropy::test
