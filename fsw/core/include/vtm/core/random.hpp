// Random: a deterministic pseudo-random generator for flight code (RANSAC sampling,
// simulated noise, test inputs). The same seed gives the same sequence of bits on every
// target, and so do the derived draws (uniform doubles, bounded integers, normals),
// because they use only integer arithmetic and vtm::math, never <random>'s distributions
// (whose output differs between standard-library versions).
//
// Generator: xoshiro256** (Blackman & Vigna, "Scrambled linear pseudorandom number
// generators", 2021): 256-bit state, period 2^256 - 1, passes BigCrush. Not for
// cryptography. Seeding: the four state words are four consecutive outputs of
// splitmix64 started at the seed, as the xoshiro authors recommend.
//
// No heap, no exceptions, bounded work per call (see uniformInt()).
#pragma once

#include <cstdint>

#include "vtm/core/assert.hpp"

namespace vtm {

// The splitmix64 output function (a bijective 64-bit mixer): also a hash of integer
// keys (procedural noise in sim/terrain hashes lattice coordinates with it).
[[nodiscard]] constexpr std::uint64_t mixBits64(std::uint64_t z) noexcept {
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
}

// One step of splitmix64 (Steele, Lea & Flood 2014, as in Vigna's splitmix64.c):
// advances `state` by 0x9E3779B97F4A7C15 and returns a mixed 64-bit value.
[[nodiscard]] std::uint64_t splitMix64(std::uint64_t& state) noexcept;

class Random {
public:
    // Upper bound on the 64-bit draws one uniformInt() call consumes (see there).
    static constexpr std::int32_t kMaxUniformIntDraws = 8;

    explicit Random(std::uint64_t seed) noexcept;

    // A generator with the given raw xoshiro256** state, for replaying a recorded state
    // and for the published reference vectors. An all-zero state is a programmer error
    // (the generator would output 0 forever): assertion, then seeded from 0 instead.
    [[nodiscard]] static Random fromState(std::uint64_t s0, std::uint64_t s1, std::uint64_t s2,
                                          std::uint64_t s3) noexcept;

    // Next 64 raw bits.
    [[nodiscard]] std::uint64_t nextU64() noexcept;
    // Next 32 bits: the upper half of nextU64() (the generator's best bits).
    [[nodiscard]] std::uint32_t nextU32() noexcept;
    // Uniform double in [0, 1): the upper 53 bits of nextU64() times 2^-53, so every
    // value is a multiple of 2^-53 and 1.0 never occurs.
    [[nodiscard]] double uniform01() noexcept;

    // Uniform integer in [lo, hi], both included (lo <= hi; lo > hi is a programmer
    // error: assertion, returns lo). lo == hi returns lo without consuming a draw. Lemire's multiply-shift: the value is the high
    // 64 bits of draw * range; the few draws that would bias it are redrawn, at most
    // kMaxUniformIntDraws draws in all. A redraw happens with probability < range/2^64,
    // so the fallback (keep the last, slightly biased draw) has probability below
    // (range/2^64)^8: < 2^-256 for ranges up to 2^32, up to 2^-8 only for ranges
    // near 2^64. The 64x64->128-bit product is done in 32-bit halves, so it is the same
    // code on 32-bit targets.
    [[nodiscard]] std::int64_t uniformInt(std::int64_t lo, std::int64_t hi) noexcept;

    // Standard normal deviate (mean 0, variance 1) by the Box-Muller transform, using
    // vtm::math::log/sqrt/sin/cos so it is bit-identical across targets. Each pair of
    // uniforms gives two deviates; the second is kept and returned by the next call.
    // |result| <= 8.5717 (sqrt(-2 ln 2^-53)): the far tails beyond are never produced.
    [[nodiscard]] double normal() noexcept;
    // mean + sigma * normal(); sigma >= 0 (negative or NaN sigma is a programmer
    // error: assertion, and the value is still mean + sigma * normal()).
    [[nodiscard]] double normal(double mean, double sigma) noexcept;

private:
    Random() noexcept = default;

    std::uint64_t s_[4] = {0U, 0U, 0U, 0U};
    double spareNormal_ = 0.0;
    bool hasSpareNormal_ = false;
};

}  // namespace vtm
