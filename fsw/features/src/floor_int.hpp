// floor() to an integer without a library call, for the bilinear samplers of the template
// matcher and the affine refinement (private to fsw/features).
#pragma once

#include <cstdint>

namespace vtm::features::detail {

// std::floor(v) as an int32, the same value for every finite |v| < 2^31: truncation, one
// down for a negative non-integer. The PowerPC 750 has no rounding instruction, so
// std::floor is a glibc call there (software bit manipulation, and slow under qemu);
// truncation is one fctiwz.
[[nodiscard]] inline std::int32_t floorToInt(double v) noexcept {
    const auto t = static_cast<std::int32_t>(v);
    return (static_cast<double>(t) > v) ? t - 1 : t;
}

// v rounded to the nearest integer, halves up: floor(v + 0.5) (the same range as floorToInt).
[[nodiscard]] inline std::int32_t roundToInt(double v) noexcept { return floorToInt(v + 0.5); }

}  // namespace vtm::features::detail
