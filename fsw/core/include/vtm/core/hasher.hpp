// A canonical hash: FNV-1a 64 over a little-endian byte order of each value's bit
// pattern, so that the same values hash the same on big- and little-endian targets.
// The determinism suite hashes every module's products with it; the simulator keys its
// render cache with it (sim/render_cache.hpp). Not a cryptographic hash.
#pragma once

#include <cstdint>
#include <cstring>

#include "vtm/core/pose.hpp"

namespace vtm {

class Hasher {
public:
    void addU64(std::uint64_t v) noexcept {
        for (int i = 0; i < 8; ++i) {  // bound: 8 bytes, least significant first
            h_ ^= (v >> (8 * i)) & 0xFFU;
            h_ *= 0x100000001B3ULL;
        }
    }
    void addI64(std::int64_t v) noexcept { addU64(static_cast<std::uint64_t>(v)); }
    void addDouble(double d) noexcept {
        std::uint64_t bits = 0U;
        std::memcpy(&bits, &d, sizeof bits);
        addU64(bits);
    }
    // Floats with every NaN hashed as one value (NaN payloads may differ between FPUs).
    void addFloat(float f) noexcept {
        if (f != f) {
            addU64(0x7FF8000000000000ULL);
        } else {
            addDouble(static_cast<double>(f));
        }
    }
    // Every coefficient of a fixed-size Eigen matrix or vector, in storage order.
    template <typename M>
    void addMatrix(const M& m) noexcept {
        for (int i = 0; i < static_cast<int>(m.size()); ++i) {  // bound: the matrix's size
            addDouble(m.data()[i]);
        }
    }
    void addPose(const RigidPose& p) noexcept {
        addMatrix(p.R);
        addMatrix(p.t_m);
    }
    [[nodiscard]] std::uint64_t value() const noexcept { return h_; }

private:
    std::uint64_t h_ = 0xCBF29CE484222325ULL;
};

}  // namespace vtm
