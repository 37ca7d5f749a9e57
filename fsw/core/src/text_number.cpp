#include "vtm/core/text_number.hpp"

#include <cstddef>
#include <cstdlib>

namespace vtm::text {

bool parseUnsigned(const char* text, std::uint64_t max_value, std::uint64_t& out) noexcept {
    std::uint64_t value = 0U;
    std::size_t digits = 0U;
    // 20 digits hold any uint64; a longer field is refused rather than scanned.
    for (; digits <= 20U && text[digits] != '\0'; ++digits) {
        const char c = text[digits];
        if (c < '0' || c > '9') {
            return false;
        }
        const auto d = static_cast<std::uint64_t>(c - '0');
        if (d > max_value || value > (max_value - d) / 10U) {
            return false;
        }
        value = value * 10U + d;
    }
    if (digits == 0U || digits > 20U) {
        return false;
    }
    out = value;
    return true;
}

bool parseReal(const char* text, double& out) noexcept {
    if (text[0] == '\0') {
        return false;
    }
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0') {
        return false;
    }
    out = value;
    return true;
}

}  // namespace vtm::text
