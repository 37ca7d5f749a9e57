// Arena: the one place flight modules get memory, at initialisation only.
//
// An Arena hands out aligned, zero-filled blocks from a byte pool it does not own
// (StaticArena<N> below owns one as a member, so the pool lands in .bss). Modules state
// their need as workspaceBytes(config) and carve it in init(). After freeze() every
// allocation is a programmer error (VTM_ASSERT) — the run path never allocates.
// Running out of pool during init is a configuration error: allocate() returns nullptr
// and the module's init() turns that into StatusCode::kOutOfMemory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>

#include "vtm/core/assert.hpp"
#include "vtm/core/span.hpp"

namespace vtm {

class Arena {
public:
    // Alignment every block gets at least; larger power-of-two alignments on request.
    static constexpr std::size_t kDefaultAlignment = 16U;

    Arena(std::byte* pool, std::size_t capacityBytes) noexcept;
    ~Arena() = default;
    Arena(const Arena&) = delete;
    Arena& operator=(const Arena&) = delete;

    // Zero-filled block of `bytes` aligned to `alignment` (a power of two), or nullptr if
    // the pool cannot hold it. After freeze(): assertion failure and nullptr.
    [[nodiscard]] void* allocate(std::size_t bytes, std::size_t alignment = kDefaultAlignment) noexcept;

    // Typed array of `count` value-initialised (zero) elements of a trivial type.
    template <typename T>
    [[nodiscard]] Span<T> allocateArray(std::size_t count) noexcept {
        static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_default_constructible_v<T>,
                      "Arena hands out storage for trivial types only");
        if (count > maxElements(sizeof(T))) {
            return Span<T>();
        }
        const std::size_t align = alignof(T) > kDefaultAlignment ? alignof(T) : kDefaultAlignment;
        void* block = allocate(count * sizeof(T), align);
        return (block != nullptr) ? Span<T>(static_cast<T*>(block), count) : Span<T>();
    }

    // Bytes allocateArray<T>(count) needs at most (its alignment's worst padding included):
    // the term of a workspaceBytes() formula for one array.
    template <typename T>
    [[nodiscard]] static constexpr std::size_t arrayBytes(std::size_t count) noexcept {
        return blockBytes(count * sizeof(T), alignof(T) > kDefaultAlignment ? alignof(T) : kDefaultAlignment);
    }

    // `count` value-initialised objects of a type with a constructor (default member
    // initialisers, Eigen members: what allocateArray refuses), constructed in place;
    // nullptr when the pool cannot hold them. They are never destroyed: such types must
    // not own resources (flight types do not).
    template <typename T>
    [[nodiscard]] T* construct(std::size_t count) noexcept {
        if (count > maxElements(sizeof(T))) {
            return nullptr;
        }
        void* block = allocate(count * sizeof(T), alignOf<T>());
        if (block == nullptr) {
            return nullptr;
        }
        T* objects = static_cast<T*>(block);
        for (std::size_t i = 0U; i < count; ++i) {  // bound: count
            ::new (static_cast<void*>(objects + i)) T();
        }
        return objects;
    }

    // Bytes construct<T>(count) needs at most: the term of a workspaceBytes() formula.
    template <typename T>
    [[nodiscard]] static constexpr std::size_t constructBytes(std::size_t count) noexcept {
        return blockBytes(count * sizeof(T), alignOf<T>());
    }

    // Ends initialisation: from now on allocate() is an assertion failure.
    void freeze() noexcept { frozen_ = true; }
    [[nodiscard]] bool frozen() const noexcept { return frozen_; }

    // Returns every block (for re-initialisation in a new mode). Blocks handed out before
    // must no longer be used. The high-water mark is kept.
    void reset() noexcept;

    [[nodiscard]] std::size_t capacityBytes() const noexcept { return capacity_; }
    [[nodiscard]] std::size_t usedBytes() const noexcept { return used_; }
    [[nodiscard]] std::size_t remainingBytes() const noexcept { return capacity_ - used_; }
    // Largest usedBytes() ever reached (alignment padding included).
    [[nodiscard]] std::size_t highWaterBytes() const noexcept { return highWater_; }

    // Bytes an allocation sequence needs at most: each block may lose up to
    // (alignment - 1) bytes to padding. Used by workspaceBytes() formulas.
    [[nodiscard]] static constexpr std::size_t blockBytes(std::size_t bytes,
                                                          std::size_t alignment = kDefaultAlignment) noexcept {
        return bytes + alignment - 1U;
    }

private:
    template <typename T>
    [[nodiscard]] static constexpr std::size_t alignOf() noexcept {
        return alignof(T) > kDefaultAlignment ? alignof(T) : kDefaultAlignment;
    }
    [[nodiscard]] static constexpr std::size_t maxElements(std::size_t elementSize) noexcept {
        return static_cast<std::size_t>(-1) / elementSize;
    }

    std::byte* pool_;
    std::size_t capacity_;
    std::size_t used_ = 0U;
    std::size_t highWater_ = 0U;
    bool frozen_ = false;
};

// An Arena that owns its pool as a member: declare it static (or inside a statically
// allocated executive) and the pool is part of the image's .bss, sized at build time.
template <std::size_t kBytes>
class StaticArena : public Arena {
public:
    StaticArena() noexcept : Arena(pool_, kBytes) {}

private:
    alignas(Arena::kDefaultAlignment) std::byte pool_[kBytes]{};
};

}  // namespace vtm
