// Span<T>: a non-owning view of a contiguous array (C++17 has no std::span).
#pragma once

#include <cstddef>
#include <type_traits>

#include "vtm/core/assert.hpp"

namespace vtm {

template <typename T>
class Span {
public:
    constexpr Span() noexcept = default;
    constexpr Span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}
    // Span<T> converts to Span<const T>.
    template <typename U, typename = std::enable_if_t<std::is_same_v<const U, T>>>
    constexpr Span(const Span<U>& other) noexcept : data_(other.data()), size_(other.size()) {}

    [[nodiscard]] constexpr T* data() const noexcept { return data_; }
    [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
    [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0U; }
    [[nodiscard]] constexpr T* begin() const noexcept { return data_; }
    [[nodiscard]] constexpr T* end() const noexcept { return data_ + size_; }

    // Bounds-checked: an index past the end is a programmer error. If the assert hook
    // returns, the first element (or a static dummy for an empty span) is returned.
    [[nodiscard]] T& operator[](std::size_t i) const noexcept {
        VTM_ASSERT(i < size_, static_cast<std::int64_t>(i), static_cast<std::int64_t>(size_));
        return (i < size_) ? data_[i] : fallback();
    }

    [[nodiscard]] Span subspan(std::size_t offset, std::size_t count) const noexcept {
        const bool inside = offset <= size_ && count <= size_ - offset;
        VTM_ASSERT(inside, static_cast<std::int64_t>(offset), static_cast<std::int64_t>(count));
        return inside ? Span(data_ + offset, count) : Span();
    }

private:
    [[nodiscard]] T& fallback() const noexcept {
        if (size_ != 0U) {
            return data_[0];
        }
        static std::remove_const_t<T> dummy{};
        return dummy;
    }

    T* data_ = nullptr;
    std::size_t size_ = 0U;
};

}  // namespace vtm
