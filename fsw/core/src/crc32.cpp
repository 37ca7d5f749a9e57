#include "vtm/core/crc32.hpp"

#include <array>

namespace vtm {
namespace {

constexpr std::uint32_t kPolynomialReflected = 0xEDB88320U;

constexpr std::array<std::uint32_t, 256> makeTable() noexcept {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t n = 0U; n < 256U; ++n) {
        std::uint32_t c = n;
        for (int bit = 0; bit < 8; ++bit) {
            c = ((c & 1U) != 0U) ? (kPolynomialReflected ^ (c >> 1U)) : (c >> 1U);
        }
        table[n] = c;
    }
    return table;
}

constexpr std::array<std::uint32_t, 256> kTable = makeTable();

}  // namespace

std::uint32_t crc32Update(std::uint32_t state, const std::uint8_t* bytes, std::size_t size) noexcept {
    std::uint32_t c = state;
    for (std::size_t i = 0U; i < size; ++i) {
        c = kTable[(c ^ bytes[i]) & 0xFFU] ^ (c >> 8U);
    }
    return c;
}

std::uint32_t crc32(const std::uint8_t* bytes, std::size_t size) noexcept {
    return crc32Final(crc32Update(crc32Init(), bytes, size));
}

}  // namespace vtm
