// The determinant of the Förstner detector's structure tensor (private to fsw/features).
#pragma once

#include <cstdint>

namespace vtm::features::detail {

// sxx syy - sxy^2 of box sums of gradient products (sxx, syy >= 0, sxy^2 <= sxx syy by
// Cauchy-Schwarz), rounded once to double: the int64 value converted. Below 2^26 each
// product is an exact double and so is their difference, which is that value; the int64
// conversion is a library call on the 32-bit targets, hence the first way where it holds.
[[nodiscard]] inline double tensorDeterminant(std::int32_t sxx, std::int32_t syy, std::int32_t sxy) noexcept {
    constexpr std::int32_t kExact = std::int32_t{1} << 26;
    if (sxx < kExact && syy < kExact) {
        const double xy = static_cast<double>(sxy);
        return static_cast<double>(sxx) * static_cast<double>(syy) - xy * xy;
    }
    return static_cast<double>(static_cast<std::int64_t>(sxx) * syy - static_cast<std::int64_t>(sxy) * sxy);
}

}  // namespace vtm::features::detail
