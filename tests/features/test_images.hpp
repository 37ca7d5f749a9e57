// Synthetic images with known geometry for the fsw/features tests: an anti-aliased
// rotated checkerboard (corner positions known exactly) and a smooth random texture that
// is a continuous function of position (so a shifted copy is exact, not resampled).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "vtm/core/image.hpp"
#include "vtm/core/random.hpp"

namespace vtm::features::test {

struct Image {
    std::int32_t width = 0;
    std::int32_t height = 0;
    std::vector<std::uint8_t> pixels;
    Image(std::int32_t w, std::int32_t h) : width(w), height(h), pixels(static_cast<std::size_t>(w * h)) {}
    std::uint8_t& at(std::int32_t x, std::int32_t y) { return pixels[static_cast<std::size_t>(y * width + x)]; }
    ImageView<const std::uint8_t> view() const { return ImageView<const std::uint8_t>(pixels.data(), width, height); }
};

// Checkerboard of square side `square_px`, rotated by `angle_rad`, one corner at `origin`;
// corners at origin + square_px * R(angle) (i, j). Each pixel is the area average over
// 8x8 sub-samples (anti-aliased), dark 40, bright 200.
struct Checkerboard {
    double origin_x, origin_y, square_px, angle_rad;
    bool bright(double x, double y) const {
        const double c = std::cos(angle_rad), s = std::sin(angle_rad);
        const double dx = x - origin_x, dy = y - origin_y;
        const double u = (c * dx + s * dy) / square_px;
        const double v = (-s * dx + c * dy) / square_px;
        return ((static_cast<long>(std::floor(u)) + static_cast<long>(std::floor(v))) & 1L) == 0L;
    }
    void cornerAt(int i, int j, double& x, double& y) const {
        const double c = std::cos(angle_rad), s = std::sin(angle_rad);
        x = origin_x + square_px * (c * i - s * j);
        y = origin_y + square_px * (s * i + c * j);
    }
    Image render(std::int32_t w, std::int32_t h) const {
        Image img(w, h);
        constexpr int kSub = 8;
        for (std::int32_t y = 0; y < h; ++y) {
            for (std::int32_t x = 0; x < w; ++x) {
                int n = 0;
                for (int sy = 0; sy < kSub; ++sy) {
                    for (int sx = 0; sx < kSub; ++sx) {
                        n += bright(x - 0.5 + (sx + 0.5) / kSub, y - 0.5 + (sy + 0.5) / kSub) ? 1 : 0;
                    }
                }
                img.at(x, y) = static_cast<std::uint8_t>(std::lround(40.0 + 160.0 * n / (kSub * kSub)));
            }
        }
        return img;
    }
};

// Smooth random texture T(u, v): bilinear interpolation of a 3x3-box-blurred noise grid
// with one node every 2 px, defined for u, v in [0, 2 * (nodes - 2)).
class Texture {
public:
    Texture(std::uint64_t seed, std::int32_t nodes, std::int32_t blur = 1) : n_(nodes), grid_(static_cast<std::size_t>(nodes * nodes)) {
        Random rng(seed);
        std::vector<double> noise(grid_.size());
        for (double& v : noise) {
            v = rng.uniform01();
        }
        for (std::int32_t y = 0; y < n_; ++y) {
            for (std::int32_t x = 0; x < n_; ++x) {
                double s = 0.0;
                for (std::int32_t dy = -blur; dy <= blur; ++dy) {
                    for (std::int32_t dx = -blur; dx <= blur; ++dx) {
                        s += noise[idx(clampi(x + dx), clampi(y + dy))];
                    }
                }
                const double n = (2 * blur + 1) * (2 * blur + 1);
                // Mean 0.5, standard deviation 0.29 / sqrt(n): scaled to about 20..235.
                grid_[idx(x, y)] = 128.0 + 200.0 * std::sqrt(n) * (s / n - 0.5);
            }
        }
    }
    double at(double u, double v) const {
        const double gu = u / 2.0, gv = v / 2.0;
        const auto x0 = clampi(static_cast<std::int32_t>(std::floor(gu)));
        const auto y0 = clampi(static_cast<std::int32_t>(std::floor(gv)));
        const double fx = gu - x0, fy = gv - y0;
        const auto x1 = clampi(x0 + 1), y1 = clampi(y0 + 1);
        return (grid_[idx(x0, y0)] * (1 - fx) + grid_[idx(x1, y0)] * fx) * (1 - fy) +
               (grid_[idx(x0, y1)] * (1 - fx) + grid_[idx(x1, y1)] * fx) * fy;
    }

private:
    std::int32_t clampi(std::int32_t i) const { return i < 0 ? 0 : (i >= n_ ? n_ - 1 : i); }
    std::size_t idx(std::int32_t x, std::int32_t y) const { return static_cast<std::size_t>(y * n_ + x); }
    std::int32_t n_;
    std::vector<double> grid_;
};

inline std::uint8_t toGrey(double v) {
    return static_cast<std::uint8_t>(v < 0.0 ? 0 : (v > 255.0 ? 255 : std::lround(v)));
}

// Image whose pixel (x, y) is T(x - shift_x + pad, y - shift_y + pad).
inline Image renderTexture(const Texture& t, std::int32_t w, std::int32_t h, double shift_x, double shift_y,
                           double pad) {
    Image img(w, h);
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            img.at(x, y) = toGrey(t.at(x - shift_x + pad, y - shift_y + pad));
        }
    }
    return img;
}

}  // namespace vtm::features::test
