// Deterministic elementary functions: the same input bits give the same output bits on
// every target we ship (x86-64, aarch64, armhf, PowerPC 750, SPARC LEON3, riscv64).
//
// Why not <cmath>: the C library's exp/log/sin/cos/atan2 are not specified to the bit.
// glibc's differ by 1 ulp between ports (and even between x86 CPUs, through FMA and
// ifunc dispatch), so a map built on the ground would not match the one built on the
// rover. These functions use only IEEE-754 double + - * / (correctly rounded by every
// FPU, with -ffp-contract=off so no FMA), integer operations and bit manipulation.
// std::sqrt is the one exception: IEEE 754 requires it to be correctly rounded.
//
// Accuracy (docs/math.md has the measured figures and how they were measured):
//   exp, log, atan2:       < 1 ulp for all finite arguments.
//   sin, cos:              < 1 ulp for |x| <= kTrigAccurateLimit (about 2.1e8 rad);
//                          beyond it see sin() below.
//   sqrt:                  correctly rounded (IEEE).
//   floor:                 exact (std::floor's value).
// Every NaN result is the canonical quiet NaN (bits 0x7FF8000000000000), whatever NaN
// came in: hardware NaN payloads and signs differ between targets.
//
// No heap, no exceptions, no recursion, every loop has a fixed trip count.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "vtm/core/platform.hpp"

namespace vtm::math {

// Correctly rounded double values of the constants.
constexpr double kPi = 0x1.921fb54442d18p+1;
constexpr double kHalfPi = 0x1.921fb54442d18p+0;
constexpr double kTwoPi = 0x1.921fb54442d18p+2;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The one NaN these functions return (bits 0x7FF8000000000000 on every target).
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// sin/cos keep their documented accuracy for |x| below this (radians). It is just under
// 2^27 * pi/2: up to there the multiples of pi/2 subtracted during argument reduction
// are exact (docs/math.md).
constexpr double kTrigAccurateLimit = 2.1e8;
// sin/cos return NaN for |x| at or above this (2^52 rad): adjacent doubles are 1 rad or
// more apart there, so the argument no longer names an angle.
constexpr double kTrigMaxArgument = 0x1.0p52;

// Bit pattern of a double, and back (std::memcpy: no aliasing or endianness tricks).
[[nodiscard]] std::uint64_t bitsOf(double x) noexcept;
[[nodiscard]] double fromBits(std::uint64_t bits) noexcept;

// Classification by bit pattern, so it holds even if a caller's build assumed finite math.
[[nodiscard]] bool isNaN(double x) noexcept;
[[nodiscard]] bool isFinite(double x) noexcept;

// e^x. Overflow (x > ~709.78) gives +inf; results below the smallest subnormal give +0;
// subnormal results are rounded once from a double-precision intermediate (< 1 ulp of
// the subnormal spacing). exp(+-0) = 1, exp(-inf) = +0, exp(+inf) = +inf, exp(NaN) = NaN.
[[nodiscard]] double exp(double x) noexcept;

// Natural logarithm. log(+-0) = -inf, log(x < 0) = NaN, log(+inf) = +inf, log(1) = +0,
// log(NaN) = NaN. Subnormal arguments are exact-scaled first, so they are as accurate as
// normal ones.
[[nodiscard]] double log(double x) noexcept;

// ln(1 + x), accurate also where 1 + x rounds away most of x (|x| << 1): u = 1 + x,
// c = x - (u - 1) its exact rounding error, ln(u) + c / u. Within 2 ulp (docs/math.md).
// log1p(-1) = -inf, log1p(x < -1) = NaN, log1p(+inf) = +inf, log1p(+-0) = +-0,
// log1p(NaN) = NaN.
[[nodiscard]] double log1p(double x) noexcept;

// Sine and cosine of x in radians. |x| < kTrigAccurateLimit: < 1 ulp. From there up to
// kTrigMaxArgument the result is the accurate sine/cosine of an argument within about
// 1 ulp of x, i.e. the absolute error grows with |x| (about |x| * 2^-53); results stay in
// [-1, 1] and are still bit-identical across targets. |x| >= kTrigMaxArgument, +-inf and
// NaN give NaN. sin(+-0) = +-0, cos(+-0) = 1.
[[nodiscard]] double sin(double x) noexcept;
[[nodiscard]] double cos(double x) noexcept;

// Angle of the vector (x, y) in radians, in [-pi, pi], < 1 ulp. Special values follow
// C99 Annex F: atan2(+-0, +0 or x > 0) = +-0, atan2(+-0, -0 or x < 0) = +-pi,
// atan2(y != 0, +-0) = +-pi/2, atan2(+-inf, +inf) = +-pi/4, atan2(+-inf, -inf) = +-3pi/4,
// atan2(+-inf, finite) = +-pi/2, atan2(finite y, +inf) = +-0, atan2(finite y, -inf) = +-pi
// (sign from y throughout); NaN in either argument gives NaN.
[[nodiscard]] double atan2(double y, double x) noexcept;

// Square root, correctly rounded (IEEE 754 requires it of every FPU and of glibc's
// software sqrt on the PowerPC 750, which has no sqrt instruction). sqrt(-0) = -0,
// sqrt(x < 0) = NaN, sqrt(NaN) = NaN (canonical, unlike the hardware's default NaN).
[[nodiscard]] double sqrt(double x) noexcept;

// The largest integer not above x without a library call: x rounded to an integer by
// adding and subtracting 2^52 with its sign (exact: below 2^52 the sum's ulp is 1, and
// -ffp-contract=off keeps the two operations apart), then moved down when that went up.
// The same double as std::floor for every x but NaN (-0 stays -0, +-inf and |x| >= 2^52
// are themselves; NaN gives the canonical NaN). floor() uses it where it pays.
[[nodiscard]] inline double floorByRounding(double x) noexcept {
    constexpr double kTwo52 = 4503599627370496.0;
    if (!(x < kTwo52 && x > -kTwo52)) {
        return x == x ? x : kNaN;  // integral already, or infinite, or NaN
    }
    const double m = x < 0.0 ? -kTwo52 : kTwo52;
    const double t = (x + m) - m;  // x rounded to the nearest integer
    if (t == x) {
        return x;  // an integer already (-0 stays -0)
    }
    return t > x ? t - 1.0 : t;
}

// The largest integer not above x, std::floor's double (NaN: the canonical NaN). The
// PowerPC 750, 32-bit ARM and SPARC have no rounding instruction the compiler uses, so
// std::floor is glibc's software routine there (about 45 instructions on the 750):
// floorByRounding() instead. Elsewhere std::floor (aarch64: one instruction).
[[nodiscard]] inline double floor(double x) noexcept {
#if defined(__powerpc__) || defined(__arm__) || defined(__sparc__)
    return floorByRounding(x);
#else
    return x == x ? std::floor(x) : kNaN;
#endif
}

}  // namespace vtm::math
