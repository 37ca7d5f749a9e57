// Workspace helpers of the tie-point extractor (internal).
#pragma once

#include <cstddef>

#include "vtm/core/arena.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm::tiepoints::detail {

// Images a tie point can be seen in (its station's two, and two in each of two neighbours).
constexpr std::size_t kMaxSightings = 8U;

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
