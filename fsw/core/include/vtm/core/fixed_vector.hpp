// FixedVector<T, N>: a vector whose capacity is a compile-time constant and whose
// storage is a member array. It never allocates. A push onto a full vector returns
// false (the caller decides: drop, count, report) rather than growing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "vtm/core/assert.hpp"
#include "vtm/core/span.hpp"

namespace vtm {

template <typename T, std::size_t N>
class FixedVector {
    static_assert(N > 0U, "FixedVector needs a positive capacity");
    static_assert(std::is_default_constructible_v<T> && std::is_copy_assignable_v<T>,
                  "FixedVector stores default-constructible, copy-assignable values");

public:
    static constexpr std::size_t kCapacity = N;

    [[nodiscard]] static constexpr std::size_t capacity() noexcept { return N; }
    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    [[nodiscard]] bool empty() const noexcept { return size_ == 0U; }
    [[nodiscard]] bool full() const noexcept { return size_ == N; }

    // Appends a copy; false (and no change) when full.
    [[nodiscard]] bool push_back(const T& value) noexcept {
        if (size_ == N) {
            return false;
        }
        items_[size_] = value;
        ++size_;
        return true;
    }
    void pop_back() noexcept {
        VTM_ASSERT(size_ > 0U);
        if (size_ > 0U) {
            --size_;
            items_[size_] = T{};
        }
    }
    // Removes every element; storage is reset to T{} so no stale data is ever read.
    void clear() noexcept {
        for (std::size_t i = 0U; i < size_; ++i) {
            items_[i] = T{};
        }
        size_ = 0U;
    }
    // Shrinks to n elements (n <= size()).
    void truncate(std::size_t n) noexcept {
        VTM_ASSERT(n <= size_, static_cast<std::int64_t>(n), static_cast<std::int64_t>(size_));
        for (std::size_t i = n; i < size_; ++i) {
            items_[i] = T{};
        }
        size_ = (n < size_) ? n : size_;
    }

    [[nodiscard]] T& operator[](std::size_t i) noexcept {
        VTM_ASSERT(i < size_, static_cast<std::int64_t>(i), static_cast<std::int64_t>(size_));
        return items_[(i < size_) ? i : 0U];
    }
    [[nodiscard]] const T& operator[](std::size_t i) const noexcept {
        VTM_ASSERT(i < size_, static_cast<std::int64_t>(i), static_cast<std::int64_t>(size_));
        return items_[(i < size_) ? i : 0U];
    }

    [[nodiscard]] T* begin() noexcept { return items_; }
    [[nodiscard]] T* end() noexcept { return items_ + size_; }
    [[nodiscard]] const T* begin() const noexcept { return items_; }
    [[nodiscard]] const T* end() const noexcept { return items_ + size_; }
    [[nodiscard]] Span<T> span() noexcept { return Span<T>(items_, size_); }
    [[nodiscard]] Span<const T> span() const noexcept { return Span<const T>(items_, size_); }

private:
    T items_[N]{};
    std::size_t size_ = 0U;
};

}  // namespace vtm
