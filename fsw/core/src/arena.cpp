#include "vtm/core/arena.hpp"

#include <cstring>

namespace vtm {

Arena::Arena(std::byte* pool, std::size_t capacityBytes) noexcept
    : pool_(pool), capacity_(pool != nullptr ? capacityBytes : 0U) {}

void* Arena::allocate(std::size_t bytes, std::size_t alignment) noexcept {
    VTM_ASSERT(!frozen_, static_cast<std::int64_t>(bytes));
    const bool powerOfTwo = alignment != 0U && (alignment & (alignment - 1U)) == 0U;
    VTM_ASSERT(powerOfTwo, static_cast<std::int64_t>(alignment));
    if (frozen_ || !powerOfTwo) {
        return nullptr;
    }
    // Pad from the absolute address so the block is aligned whatever the pool's base.
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): alignment needs the address as an integer
    const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(pool_) + used_;
    const std::size_t padding =
        static_cast<std::size_t>((alignment - (base & (alignment - 1U))) & (alignment - 1U));
    if (padding > capacity_ - used_ || bytes > capacity_ - used_ - padding) {
        return nullptr;
    }
    std::byte* block = pool_ + used_ + padding;
    used_ += padding + bytes;
    if (used_ > highWater_) {
        highWater_ = used_;
    }
    if (bytes > 0U) {
        std::memset(block, 0, bytes);  // never hand out stale or uninitialised bytes
    }
    return block;
}

void Arena::reset() noexcept {
    used_ = 0U;
    frozen_ = false;
}

}  // namespace vtm
