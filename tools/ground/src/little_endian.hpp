// Little-endian byte encoding of the binary file formats (PLY), independent of the
// host's byte order: values go through their integer bit patterns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace vtm::ground::detail {

inline void appendU32LE(std::vector<unsigned char>& out, std::uint32_t v) {
    for (unsigned i = 0; i < 4U; ++i) {
        out.push_back(static_cast<unsigned char>((v >> (8U * i)) & 0xFFU));
    }
}

inline void appendF32LE(std::vector<unsigned char>& out, float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    appendU32LE(out, bits);
}

// Unsigned integer of `n` bytes (1..8) at p, little endian.
inline std::uint64_t loadUnsignedLE(const unsigned char* p, std::size_t n) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) {
        v |= static_cast<std::uint64_t>(p[i]) << (8U * i);
    }
    return v;
}

inline float loadF32LE(const unsigned char* p) {
    const auto bits = static_cast<std::uint32_t>(loadUnsignedLE(p, 4U));
    float f = 0.0F;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

inline double loadF64LE(const unsigned char* p) {
    const std::uint64_t bits = loadUnsignedLE(p, 8U);
    double d = 0.0;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

}  // namespace vtm::ground::detail
