// Numbers in text fields (configuration files, manifests, camera models): one parser for
// every reader in flight code, so that "what is a number" is defined once.
// No heap, no locale state beyond the C library's "C" locale (flight programs never call
// setlocale), every loop bounded.
#pragma once

#include <cstdint>

namespace vtm::text {

// Unsigned decimal integer (digits only, no sign, no leading '+', at most 20 digits) not
// above max_value. False for anything else; `out` is then unchanged.
[[nodiscard]] bool parseUnsigned(const char* text, std::uint64_t max_value, std::uint64_t& out) noexcept;

// A decimal or hexadecimal floating-point number as std::strtod reads it in the "C"
// locale (correctly rounded, so the 17 significant digits "%.17g" writes give the same
// bits back), the whole NUL-terminated field consumed. NaN and infinity parse; callers
// check finiteness where it matters. False for anything else; `out` is then unchanged.
[[nodiscard]] bool parseReal(const char* text, double& out) noexcept;

}  // namespace vtm::text
