#include "vtm/core/random.hpp"

#include "vtm/core/math.hpp"

namespace vtm {
namespace {

constexpr std::uint64_t rotateLeft(std::uint64_t x, unsigned k) noexcept {
    return (x << k) | (x >> (64U - k));
}

constexpr std::uint64_t kAllOnes64 = 0xFFFFFFFFFFFFFFFFULL;

struct Product128 {
    std::uint64_t hi;
    std::uint64_t lo;
};

// Full 128-bit product of two 64-bit values from four 32x32->64 products, so the same
// code runs on targets without __int128 (armhf, PowerPC 750, LEON3).
Product128 multiply64x64(std::uint64_t a, std::uint64_t b) noexcept {
    constexpr std::uint64_t kLow32 = 0xFFFFFFFFULL;
    const std::uint64_t a0 = a & kLow32;
    const std::uint64_t a1 = a >> 32U;
    const std::uint64_t b0 = b & kLow32;
    const std::uint64_t b1 = b >> 32U;
    const std::uint64_t p00 = a0 * b0;
    const std::uint64_t p01 = a0 * b1;
    const std::uint64_t p10 = a1 * b0;
    const std::uint64_t p11 = a1 * b1;
    // Sum of the three terms landing on bits 32..63; below 3 * 2^32, cannot overflow.
    const std::uint64_t middle = (p00 >> 32U) + (p01 & kLow32) + (p10 & kLow32);
    return {p11 + (p01 >> 32U) + (p10 >> 32U) + (middle >> 32U), (middle << 32U) | (p00 & kLow32)};
}

}  // namespace

std::uint64_t splitMix64(std::uint64_t& state) noexcept {
    state += 0x9E3779B97F4A7C15ULL;
    return mixBits64(state);
}

Random::Random(std::uint64_t seed) noexcept {
    // Four consecutive splitmix64 outputs are never all zero (splitmix64 is a bijection
    // of its counter, so it outputs zero at most once in a row).
    std::uint64_t sm = seed;
    for (std::uint64_t& word : s_) {
        word = splitMix64(sm);
    }
}

Random Random::fromState(std::uint64_t s0, std::uint64_t s1, std::uint64_t s2, std::uint64_t s3) noexcept {
    const bool allZero = (s0 | s1 | s2 | s3) == 0U;
    VTM_ASSERT(!allZero);
    if (allZero) {
        return Random(0U);
    }
    Random r;
    r.s_[0] = s0;
    r.s_[1] = s1;
    r.s_[2] = s2;
    r.s_[3] = s3;
    return r;
}

std::uint64_t Random::nextU64() noexcept {
    // xoshiro256**: the ** scrambler (multiply, rotate, multiply) over the xoshiro
    // linear engine.
    const std::uint64_t result = rotateLeft(s_[1] * 5U, 7U) * 9U;
    const std::uint64_t t = s_[1] << 17U;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotateLeft(s_[3], 45U);
    return result;
}

std::uint32_t Random::nextU32() noexcept { return static_cast<std::uint32_t>(nextU64() >> 32U); }

double Random::uniform01() noexcept {
    // 53 bits fit a double's significand exactly; the product by 2^-53 is exact.
    return static_cast<double>(nextU64() >> 11U) * 0x1.0p-53;
}

std::int64_t Random::uniformInt(std::int64_t lo, std::int64_t hi) noexcept {
    VTM_ASSERT(lo <= hi, lo, hi);
    if (lo >= hi) {
        return lo;
    }
    // Arithmetic modulo 2^64 (two's complement): hi - lo fits, hi - lo + 1 may not.
    const auto base = static_cast<std::uint64_t>(lo);
    const std::uint64_t span = static_cast<std::uint64_t>(hi) - base;
    // cppcheck 2.10 misreads the wrap-around: lo = INT64_MIN, hi = INT64_MAX gives this
    // (RandomUniformInt.StaysWithinInclusiveBounds).
    // cppcheck-suppress knownConditionTrueFalse
    if (span == kAllOnes64) {
        return static_cast<std::int64_t>(base + nextU64());  // the full 2^64 range
    }
    const std::uint64_t range = span + 1U;
    Product128 m = multiply64x64(nextU64(), range);
    // cppcheck-suppress knownConditionTrueFalse ; false positive: any low half can occur
    if (m.lo < range) {
        // Draws whose low half falls below 2^64 mod range would make some values one
        // count more likely than others (Lemire 2019); redraw those, a bounded number
        // of times.
        const std::uint64_t threshold = (0U - range) % range;
        for (std::int32_t draw = 1; draw < kMaxUniformIntDraws && m.lo < threshold; ++draw) {
            m = multiply64x64(nextU64(), range);
        }
    }
    return static_cast<std::int64_t>(base + m.hi);
}

double Random::normal() noexcept {
    if (hasSpareNormal_) {
        hasSpareNormal_ = false;
        return spareNormal_;
    }
    // u1 in (0, 1] so log(u1) is finite; u2 in [0, 1).
    const double u1 = static_cast<double>((nextU64() >> 11U) + 1U) * 0x1.0p-53;
    const double u2 = uniform01();
    const double radiusSquared = -2.0 * math::log(u1);
    // u1 = 1 gives -0: take +0 so a zero deviate has no stray sign.
    const double radius = math::sqrt(radiusSquared > 0.0 ? radiusSquared : 0.0);
    const double angle = math::kTwoPi * u2;
    spareNormal_ = radius * math::sin(angle);
    hasSpareNormal_ = true;
    return radius * math::cos(angle);
}

double Random::normal(double mean, double sigma) noexcept {
    VTM_ASSERT(sigma >= 0.0);
    return mean + sigma * normal();
}

}  // namespace vtm
