// RingBuffer<T, N>: fixed-capacity FIFO. When full, push() overwrites the oldest entry
// and counts it as dropped, so a producer (the flight code) is never blocked by a slow
// consumer (telemetry) and the loss is visible.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/assert.hpp"

namespace vtm {

template <typename T, std::size_t N>
class RingBuffer {
    static_assert(N > 0U, "RingBuffer needs a positive capacity");

public:
    static constexpr std::size_t kCapacity = N;

    void push(const T& value) noexcept {
        items_[(head_ + size_) % N] = value;
        if (size_ < N) {
            ++size_;
        } else {
            head_ = (head_ + 1U) % N;
            ++dropped_;
        }
    }
    // Removes the oldest entry into out; false when empty.
    [[nodiscard]] bool pop(T& out) noexcept {
        if (size_ == 0U) {
            return false;
        }
        out = items_[head_];
        items_[head_] = T{};
        head_ = (head_ + 1U) % N;
        --size_;
        return true;
    }
    // i = 0 is the oldest entry still held.
    [[nodiscard]] const T& at(std::size_t i) const noexcept {
        VTM_ASSERT(i < size_, static_cast<std::int64_t>(i), static_cast<std::int64_t>(size_));
        return items_[(head_ + ((i < size_) ? i : 0U)) % N];
    }
    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    [[nodiscard]] bool empty() const noexcept { return size_ == 0U; }
    [[nodiscard]] static constexpr std::size_t capacity() noexcept { return N; }
    // Entries overwritten before anybody popped them, since construction.
    [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_; }

private:
    T items_[N]{};
    std::size_t head_ = 0U;
    std::size_t size_ = 0U;
    std::uint64_t dropped_ = 0U;
};

}  // namespace vtm
