// Window sums packed several to a machine word (SWAR): 16-bit sums in the lanes of a
// native unsigned word: eight to a 128-bit GCC vector where the target has SIMD (x86-64,
// aarch64), four to a uint64_t on the other 64-bit ones (riscv64), two to a uint32_t on the
// 32-bit ones (ppc750, leon3, armhf: VFP without NEON). Plain integer adds and subtracts of whole words;
// they equal lane-by-lane arithmetic because every lane's result lies in 0..65535 (the
// proof from maxCost and the window: window_sums.cpp). Unsigned words: wrapping is
// defined, no undefined behaviour.
//
// Layout. A pixel's costs are `slotStride` bytes, slot s = 0..D-1 holding disparity index
// j = D-1-s (the DT row read backwards: see window_sums.hpp). A word of kWordBytes cost
// bytes becomes two words of sums: the bytes at even offsets and those at odd offsets.
// Stored with memcpy, the pixel's uint16 sums lie in the order sumPosition() gives, the
// same on little- and big-endian targets (evenBytes/oddBytes pick the bytes by endianness).
#pragma once

#include <cstdint>
#include <cstring>

namespace vtm::stereo::detail {

// VTM_STEREO_SUM_WORD_BITS (32 or 64) forces a scalar word: how a developer runs the 32-
// and 64-bit paths of the other targets on the host (docs/stereo.md "Cost"); CI runs each
// path where it is native (armhf, ppc750, leon3: 32; riscv64: 64; aarch64: vector), and
// the determinism suite compares their bits with the host's.
#if !defined(VTM_STEREO_SUM_WORD_BITS) && (defined(__SSE2__) || defined(__ARM_NEON))
// Targets with 128-bit SIMD (x86-64 SSE2, aarch64 NEON): eight sums to a GCC vector.
#define VTM_STEREO_VECTOR_SUMS 1
typedef std::uint16_t SumWord __attribute__((vector_size(16)));  // NOLINT(modernize-use-using)
constexpr SumWord kLowBytes = {0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU};
#elif (defined(VTM_STEREO_SUM_WORD_BITS) && VTM_STEREO_SUM_WORD_BITS == 64) || \
    (!defined(VTM_STEREO_SUM_WORD_BITS) && UINTPTR_MAX > 0xFFFFFFFFU)
#define VTM_STEREO_VECTOR_SUMS 0
using SumWord = std::uint64_t;
constexpr SumWord kLowBytes = 0x00FF00FF00FF00FFU;
#else
#define VTM_STEREO_VECTOR_SUMS 0
using SumWord = std::uint32_t;
constexpr SumWord kLowBytes = 0x00FF00FFU;
#endif

constexpr std::int32_t kWordBytes = static_cast<std::int32_t>(sizeof(SumWord));  // cost bytes per load
constexpr std::int32_t kLanes = kWordBytes / 2;                                   // 16-bit sums per word
constexpr std::int32_t kLaneBits = 16;
constexpr std::int32_t kWordBits = 8 * kWordBytes;
constexpr bool kBigEndian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;

// Slot strides are a multiple of this on every target (the widest word group), so the
// workspace does not depend on the target.
constexpr std::int32_t kSlotGroup = 16;
static_assert(kSlotGroup % kWordBytes == 0, "slot groups hold whole words");

inline SumWord loadWord(const void* p) noexcept {
    SumWord w;
    std::memcpy(&w, p, sizeof w);
    return w;
}

inline void storeWord(void* p, SumWord w) noexcept { std::memcpy(p, &w, sizeof w); }

// The cost bytes at even (odd) offsets of the word, zero-extended to 16-bit lanes in
// memory order.
inline SumWord evenBytes(SumWord w) noexcept { return kBigEndian ? (w >> 8U) & kLowBytes : w & kLowBytes; }
inline SumWord oddBytes(SumWord w) noexcept { return kBigEndian ? w & kLowBytes : (w >> 8U) & kLowBytes; }

// Position among the pixel's uint16 sums of slot s, and back.
constexpr std::int32_t sumPosition(std::int32_t s) noexcept {
    const std::int32_t r = s % kWordBytes;
    return s - r + (r % 2) * kLanes + r / 2;
}
constexpr std::int32_t slotOfPosition(std::int32_t q) noexcept {
    const std::int32_t r = q % kWordBytes;
    return q - r + (r < kLanes ? 2 * r : 2 * (r - kLanes) + 1);
}
static_assert(slotOfPosition(sumPosition(kWordBytes - 1)) == kWordBytes - 1 && sumPosition(1) == kLanes,
              "positions invert");

#if !VTM_STEREO_VECTOR_SUMS
// Scalar words only (vector words compare lane by lane: window_sums.cpp).
// threshold(best): a word w has a lane <= best exactly when (w << 16 i) <= threshold for
// some lane i (the top lane compares first; the lower bits of the threshold are all ones).
// best > 65535: every lane qualifies.
inline SumWord atMostThreshold(std::int32_t best) noexcept {
    if (best > 0xFFFF) {
        return ~SumWord{0};
    }
    const SumWord low = (SumWord{1} << static_cast<unsigned>(kWordBits - kLaneBits)) - 1U;
    return (static_cast<SumWord>(best) << static_cast<unsigned>(kWordBits - kLaneBits)) | low;
}

inline bool anyLaneAtMost(SumWord w, SumWord threshold) noexcept {
    for (std::int32_t i = 0; i < kLanes; ++i) {
        if (static_cast<SumWord>(w << static_cast<unsigned>(kLaneBits * i)) <= threshold) {
            return true;
        }
    }
    return false;
}

#endif

}  // namespace vtm::stereo::detail
