// Ground-side images and results: owning pixel buffers on the heap (tools only, never
// flight code) and a result type whose error message names the file and the reason.
//
// Coordinates as in vtm::ImageView: x = column (0 = left), y = row (0 = top), pixels.
// Pixels are stored row by row from the top, channels interleaved (RGB for colour).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "vtm/core/image.hpp"

namespace vtm::ground {

template <typename T>
struct Image {
    std::int32_t width = 0;
    std::int32_t height = 0;
    std::int32_t channels = 1;  // 1 = grey / scalar, 3 = RGB
    std::vector<T> pixels;      // width * height * channels values

    Image() = default;
    Image(std::int32_t w, std::int32_t h, std::int32_t c = 1, T fill = T{})
        : width(w), height(h), channels(c), pixels(count(w, h, c), fill) {}

    [[nodiscard]] bool empty() const { return pixels.empty(); }
    template <typename U>
    [[nodiscard]] bool sameSize(const Image<U>& other) const {
        return width == other.width && height == other.height;
    }
    [[nodiscard]] T& at(std::int32_t x, std::int32_t y, std::int32_t c = 0) { return pixels[index(x, y, c)]; }
    [[nodiscard]] const T& at(std::int32_t x, std::int32_t y, std::int32_t c = 0) const {
        return pixels[index(x, y, c)];
    }
    // Views for the flight API (one-channel images): packed rows, stride = width.
    [[nodiscard]] ImageView<T> view() { return ImageView<T>(pixels.data(), width, height); }
    [[nodiscard]] ImageView<const T> view() const { return ImageView<const T>(pixels.data(), width, height); }

private:
    static std::size_t count(std::int32_t w, std::int32_t h, std::int32_t c) {
        return (w > 0 && h > 0 && c > 0)
                   ? static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c)
                   : 0U;
    }
    [[nodiscard]] std::size_t index(std::int32_t x, std::int32_t y, std::int32_t c) const {
        return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                   static_cast<std::size_t>(channels) +
               static_cast<std::size_t>(c);
    }
};

using GreyImage = Image<std::uint8_t>;        // 8-bit grey (or RGB with channels = 3)
using Grey16Image = Image<std::uint16_t>;     // raw grey levels of an 8- or 16-bit file
using FloatImage = Image<float>;              // disparities, uncertainties (pixels)

// Bilinear sample of a one-channel 8-bit image at (x, y), inside [0, w-1] x [0, h-1].
inline double bilinearAt(const GreyImage& g, double x, double y) {
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const int x1 = std::min(x0 + 1, g.width - 1), y1 = std::min(y0 + 1, g.height - 1);
    const double fx = x - x0, fy = y - y0;
    const double top = (1.0 - fx) * g.at(x0, y0) + fx * g.at(x1, y0);
    const double bottom = (1.0 - fx) * g.at(x0, y1) + fx * g.at(x1, y1);
    return (1.0 - fy) * top + fy * bottom;
}

// The outcome of an operation on outside data. When !ok, `error` is one line that
// names the input (usually the file path) and what is wrong with it, e.g.
// "teddy/im2.png: cannot open: No such file or directory".
template <typename T>
struct [[nodiscard]] Result {
    bool ok = false;
    std::string error;
    T value{};

    static Result success(T v) { return Result{true, std::string(), std::move(v)}; }
    static Result failure(std::string message) { return Result{false, std::move(message), T{}}; }
};

// Result of an operation that produces nothing but a side effect (writing a file).
struct [[nodiscard]] Outcome {
    bool ok = false;
    std::string error;

    static Outcome success() { return Outcome{true, std::string()}; }
    static Outcome failure(std::string message) { return Outcome{false, std::move(message)}; }
};

}  // namespace vtm::ground
