// Workspace helpers of the tie-point extractor (internal).
#pragma once

#include <cstddef>
#include <new>

#include "vtm/core/arena.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm::tiepoints::detail {

// Images a tie point can be seen in (its station's two, and two in each of two neighbours).
constexpr std::size_t kMaxSightings = 8U;

template <typename T>
constexpr std::size_t alignmentOf() noexcept {
    return alignof(T) > Arena::kDefaultAlignment ? alignof(T) : Arena::kDefaultAlignment;
}

// Arena bytes of `count` objects of T (construct<T>).
template <typename T>
constexpr std::size_t objectBytes(std::size_t count) noexcept {
    return Arena::blockBytes(count * sizeof(T), alignmentOf<T>());
}

// `count` value-initialised objects of T in arena storage (placement new: these types have
// default member initialisers, so Arena::allocateArray does not take them); nullptr when full.
template <typename T>
T* construct(Arena& arena, std::size_t count) noexcept {
    void* block = arena.allocate(count * sizeof(T), alignmentOf<T>());
    if (block == nullptr) {
        return nullptr;
    }
    T* objects = static_cast<T*>(block);
    for (std::size_t i = 0U; i < count; ++i) {
        ::new (static_cast<void*>(objects + i)) T();
    }
    return objects;
}

// Per-station feature slots: max_stations * detector.max_features.
constexpr std::size_t featureSlots(const Config& c) noexcept {
    return static_cast<std::size_t>(c.max_stations) * static_cast<std::size_t>(c.detector.max_features);
}
// Every point has at least two observations.
constexpr std::size_t pointCapacity(const Config& c) noexcept {
    return static_cast<std::size_t>(c.max_observations) / 2U + 1U;
}
// Image pairs: per station (left, right) and four per adjacent pair.
constexpr std::size_t pairCapacity(const Config& c) noexcept { return 5U * static_cast<std::size_t>(c.max_stations); }

}  // namespace vtm::tiepoints::detail
