// ImageView<T>: a non-owning view of a 2-D image with an explicit row stride, the way
// frames move between the HAL and the modules without copies. ImageBuffer<T, W, H>
// owns fixed-capacity storage as a member. Coordinates: x = column (0 = left),
// y = row (0 = top), in pixels. Stride is in elements (pixels), not bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "vtm/core/arena.hpp"
#include "vtm/core/assert.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

template <typename T>
class ImageView {
public:
    constexpr ImageView() noexcept = default;
    constexpr ImageView(T* data, std::int32_t width, std::int32_t height, std::int32_t stride) noexcept
        : data_(data), width_(width), height_(height), stride_(stride) {}
    // Tightly packed rows.
    constexpr ImageView(T* data, std::int32_t width, std::int32_t height) noexcept
        : ImageView(data, width, height, width) {}
    // ImageView<T> converts to ImageView<const T>.
    template <typename U, typename = std::enable_if_t<std::is_same_v<const U, T>>>
    constexpr ImageView(const ImageView<U>& other) noexcept
        : data_(other.data()), width_(other.width()), height_(other.height()), stride_(other.stride()) {}

    [[nodiscard]] constexpr T* data() const noexcept { return data_; }
    [[nodiscard]] constexpr std::int32_t width() const noexcept { return width_; }
    [[nodiscard]] constexpr std::int32_t height() const noexcept { return height_; }
    [[nodiscard]] constexpr std::int32_t stride() const noexcept { return stride_; }
    [[nodiscard]] constexpr std::size_t pixelCount() const noexcept {
        return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    }
    // A view is usable when it has pixels and its stride covers a row.
    [[nodiscard]] constexpr bool valid() const noexcept {
        return data_ != nullptr && width_ > 0 && height_ > 0 && stride_ >= width_;
    }
    [[nodiscard]] constexpr bool contains(std::int32_t x, std::int32_t y) const noexcept {
        return x >= 0 && y >= 0 && x < width_ && y < height_;
    }
    [[nodiscard]] constexpr bool sameSize(std::int32_t w, std::int32_t h) const noexcept {
        return width_ == w && height_ == h;
    }

    // Pointer to the first pixel of row y (0 <= y < height()).
    [[nodiscard]] T* row(std::int32_t y) const noexcept {
        VTM_ASSERT(y >= 0 && y < height_, y, height_);
        const std::int32_t yy = (y >= 0 && y < height_) ? y : 0;
        return data_ + static_cast<std::ptrdiff_t>(yy) * stride_;
    }
    // Bounds-checked pixel access; hot loops use row() and index the row themselves.
    [[nodiscard]] T& at(std::int32_t x, std::int32_t y) const noexcept {
        VTM_ASSERT(contains(x, y), x, y);
        const bool inside = contains(x, y);
        return data_[static_cast<std::ptrdiff_t>(inside ? y : 0) * stride_ + (inside ? x : 0)];
    }

    // The rectangle [x, x+w) x [y, y+h), which must lie inside this view.
    [[nodiscard]] ImageView subView(std::int32_t x, std::int32_t y, std::int32_t w, std::int32_t h) const noexcept {
        const bool inside = x >= 0 && y >= 0 && w >= 0 && h >= 0 && x <= width_ - w && y <= height_ - h;
        VTM_ASSERT(inside, x, y);
        if (!inside) {
            return ImageView();
        }
        return ImageView(data_ + static_cast<std::ptrdiff_t>(y) * stride_ + x, w, h, stride_);
    }

    // Sets every pixel to value.
    void fill(const T& value) const noexcept {
        for (std::int32_t y = 0; y < height_; ++y) {
            T* r = row(y);
            for (std::int32_t x = 0; x < width_; ++x) {
                r[x] = value;
            }
        }
    }

private:
    T* data_ = nullptr;
    std::int32_t width_ = 0;
    std::int32_t height_ = 0;
    std::int32_t stride_ = 0;
};

// Copies src into dst pixel by pixel; both must have the same size.
template <typename T>
[[nodiscard]] Status copyImage(const ImageView<const T>& src, const ImageView<T>& dst) noexcept {
    if (!src.valid() || !dst.valid()) {
        return Status(StatusCode::kInvalidArgument, "copyImage: empty or malformed view");
    }
    if (!dst.sameSize(src.width(), src.height())) {
        return Status(StatusCode::kSizeMismatch, "copyImage: destination size differs from source",
                      dst.width());
    }
    for (std::int32_t y = 0; y < src.height(); ++y) {
        const T* s = src.row(y);
        T* d = dst.row(y);
        for (std::int32_t x = 0; x < src.width(); ++x) {
            d[x] = s[x];
        }
    }
    return Status::ok();
}

// Fixed-capacity image storage owned as a member (put it in static storage: a
// 1024x1024 8-bit buffer is 1 MiB). The active size can be set up to the capacity.
template <typename T, std::int32_t kMaxWidth, std::int32_t kMaxHeight>
class ImageBuffer {
    static_assert(kMaxWidth > 0 && kMaxHeight > 0, "ImageBuffer needs a positive capacity");

public:
    static constexpr std::size_t kCapacityPixels =
        static_cast<std::size_t>(kMaxWidth) * static_cast<std::size_t>(kMaxHeight);

    // Sets the active size; kSizeMismatch when it exceeds the capacity or is empty.
    [[nodiscard]] Status setSize(std::int32_t width, std::int32_t height) noexcept {
        if (width <= 0 || height <= 0) {
            return Status(StatusCode::kInvalidArgument, "ImageBuffer: width and height must be positive",
                          width <= 0 ? width : height);
        }
        if (width > kMaxWidth || height > kMaxHeight) {
            return Status(StatusCode::kSizeMismatch, "ImageBuffer: size exceeds the buffer capacity",
                          width > kMaxWidth ? width : height);
        }
        width_ = width;
        height_ = height;
        return Status::ok();
    }
    // Packed rows (stride = active width).
    [[nodiscard]] ImageView<T> view() noexcept { return ImageView<T>(pixels_, width_, height_); }
    [[nodiscard]] ImageView<const T> view() const noexcept { return ImageView<const T>(pixels_, width_, height_); }

private:
    T pixels_[kCapacityPixels]{};
    std::int32_t width_ = kMaxWidth;
    std::int32_t height_ = kMaxHeight;
};

// Carves a packed width x height image from an arena (at init). kOutOfMemory if the
// arena is too small.
template <typename T>
[[nodiscard]] Status allocateImage(Arena& arena, std::int32_t width, std::int32_t height,
                                   ImageView<T>& out) noexcept {
    if (width <= 0 || height <= 0) {
        return Status(StatusCode::kInvalidArgument, "allocateImage: width and height must be positive",
                      width <= 0 ? width : height);
    }
    const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const Span<T> block = arena.allocateArray<T>(count);
    if (block.empty()) {
        return Status(StatusCode::kOutOfMemory, "allocateImage: arena exhausted",
                      static_cast<std::int64_t>(count * sizeof(T)));
    }
    out = ImageView<T>(block.data(), width, height);
    return Status::ok();
}

}  // namespace vtm
