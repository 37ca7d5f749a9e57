// The small checks every module's Config::validate() makes, in one place: the refusal
// (kInvalidConfig with a reason that names the field, and the offending value as detail),
// and the tests of a double field. docs/core.md.
#pragma once

#include <cstdint>

#include "vtm/core/math.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

// A configuration field refused: `reason` names the field and its allowed range
// ("kriging.max_samples: must be 16..1048576"), `value` is what it held.
[[nodiscard]] constexpr Status invalidConfig(const char* reason, std::int64_t value = 0) noexcept {
    return Status(StatusCode::kInvalidConfig, reason, value);
}

// Finite and > 0.
[[nodiscard]] inline bool isPositiveFinite(double v) noexcept { return math::isFinite(v) && v > 0.0; }

// Finite and within [lo, hi].
[[nodiscard]] inline bool isInRange(double v, double lo, double hi) noexcept {
    return math::isFinite(v) && v >= lo && v <= hi;
}

// A double field as integer milli-units for a Status detail (-1 when not finite or too
// large to convert).
[[nodiscard]] inline std::int64_t milliUnits(double v) noexcept {
    return math::isFinite(v) && v < 1e15 && v > -1e15 ? static_cast<std::int64_t>(v * 1000.0) : -1;
}

}  // namespace vtm
