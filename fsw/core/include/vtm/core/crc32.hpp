// CRC-32 as IEEE 802.3 / zlib / PNG define it: reflected polynomial 0xEDB88320, initial
// value 0xFFFFFFFF, final XOR 0xFFFFFFFF. Check value: crc32("123456789") = 0xCBF43926.
// Table-driven (one 256-entry table in .rodata, computed at compile time), byte-wise, so
// the result does not depend on the target's endianness or word size. Used by the HIL
// link (hal/link) and the ground side's PNG writer (tools/ground).
#pragma once

#include <cstddef>
#include <cstdint>

namespace vtm {

// Running form: crc = crc32Update(crc32Init(), ...); ...; value = crc32Final(crc).
[[nodiscard]] constexpr std::uint32_t crc32Init() noexcept { return 0xFFFFFFFFU; }
[[nodiscard]] std::uint32_t crc32Update(std::uint32_t state, const std::uint8_t* bytes, std::size_t size) noexcept;
[[nodiscard]] constexpr std::uint32_t crc32Final(std::uint32_t state) noexcept { return state ^ 0xFFFFFFFFU; }

// CRC-32 of bytes[0, size) in one call.
[[nodiscard]] std::uint32_t crc32(const std::uint8_t* bytes, std::size_t size) noexcept;

}  // namespace vtm
