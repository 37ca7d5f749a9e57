// Deterministic elementary functions (see vtm/core/math.hpp and docs/math.md).
//
// Every function follows the same pattern: reduce the argument exactly (or to a
// double-double, i.e. an unevaluated sum hi + lo carrying ~106 bits), evaluate a short
// series on the reduced argument, and let the one final rounding dominate the error.
// The error-free transformations below (twoSum, twoProd) are exact in IEEE double
// arithmetic without FMA; that is why the build must keep -ffp-contract=off.
//
// Series coefficients are reciprocals of exactly representable integers (n! for
// n <= 22, 2n + 1), written as quotients so the compiler rounds them correctly once.
// Multi-part constants (pi/2, ln 2, atan(k/4)) were split with 500-bit arithmetic
// (mpmath); each part is a double written in hexadecimal so no decimal conversion is
// involved.
#include "vtm/core/math.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>

namespace vtm::math {
namespace {

constexpr std::uint64_t kSignMask = 0x8000000000000000ULL;
constexpr std::uint64_t kExponentMask = 0x7FF0000000000000ULL;
constexpr std::uint64_t kMantissaMask = 0x000FFFFFFFFFFFFFULL;
constexpr std::uint64_t kExponentOfOne = 0x3FF0000000000000ULL;
constexpr std::int32_t kExponentBias = 1023;
constexpr double kSmallestNormal = 0x1.0p-1022;

// An unevaluated sum hi + lo with |lo| <= ulp(hi) / 2 (roughly): ~106 significant bits.
struct DoubleDouble {
    double hi;
    double lo;
};

// a + b = s.hi + s.lo exactly, for any a, b (Knuth's TwoSum).
DoubleDouble twoSum(double a, double b) noexcept {
    const double s = a + b;
    const double bVirtual = s - a;
    const double aVirtual = s - bVirtual;
    return {s, (a - aVirtual) + (b - bVirtual)};
}

// a + b exactly, when |a| >= |b| or a == 0 (Dekker's Fast2Sum, three operations).
DoubleDouble fastTwoSum(double a, double b) noexcept {
    const double s = a + b;
    return {s, b - (s - a)};
}

// Veltkamp's split: a = hi + lo with at most 26 significant bits each, so that products
// of halves are exact. Requires |a| < 2^996 (no overflow of the scaled copy).
DoubleDouble split(double a) noexcept {
    constexpr double kSplitter = 134217729.0;  // 2^27 + 1
    const double c = kSplitter * a;
    const double hi = c - (c - a);
    return {hi, a - hi};
}

// a * b = p.hi + p.lo exactly (Dekker's product, no FMA needed), barring over/underflow.
DoubleDouble twoProd(double a, double b) noexcept {
    const double p = a * b;
    const DoubleDouble as = split(a);
    const DoubleDouble bs = split(b);
    const double err = (((as.hi * bs.hi - p) + as.hi * bs.lo) + as.lo * bs.hi) + as.lo * bs.lo;
    return {p, err};
}

// c[0] + c[1] z + ... + c[N-1] z^(N-1), Horner's scheme; N is a compile-time bound.
template <std::size_t N>
double horner(const double (&c)[N], double z) noexcept {
    double p = c[N - 1U];
    for (std::size_t i = N - 1U; i > 0U; --i) {
        p = p * z + c[i - 1U];
    }
    return p;
}

// 2^n for -1022 <= n <= 1023, straight from the bit pattern.
double pow2(std::int32_t n) noexcept {
    return fromBits(static_cast<std::uint64_t>(n + kExponentBias) << 52U);
}

// v * 2^n in two exact steps (|n| <= 2098), so only the last multiplication can round:
// subnormal results are rounded once and overflow gives inf, as IEEE multiplication does.
double scaleByPow2(double v, std::int32_t n) noexcept {
    const std::int32_t first = n / 2;
    return (v * pow2(first)) * pow2(n - first);
}

// floor(log2(x)) for finite x > 0, subnormals included.
std::int32_t binaryExponent(double x) noexcept {
    std::int32_t offset = 0;
    if (x < kSmallestNormal) {
        x *= 0x1.0p54;  // exact: brings any subnormal into the normal range
        offset = -54;
    }
    const auto biased = static_cast<std::int32_t>((bitsOf(x) & kExponentMask) >> 52U);
    return biased - kExponentBias + offset;
}

// Nearest integer of |t| < 2^62 (halfway cases away from zero), as an integer.
std::int64_t nearestInteger(double t) noexcept {
    return static_cast<std::int64_t>(t + ((t >= 0.0) ? 0.5 : -0.5));
}

// ---------------------------------------------------------------------------- exp --

// ln 2 = kLn2Hi + kLn2Lo; kLn2Hi has 42 significant bits, so k * kLn2Hi is exact for
// |k| < 2^11, which covers every k exp() and log() use.
constexpr double kLn2Hi = 0x1.62e42fefa3800p-1;
constexpr double kLn2Lo = 0x1.ef35793c76730p-45;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;
// Beyond these exp() is +inf or +0: ln(DBL_MAX) = 709.78..., ln(2^-1075) = -745.13...
constexpr double kExpOverflowArgument = 709.79;
constexpr double kExpUnderflowArgument = -745.2;

// (e^r - 1 - r) / r^2 = 1/2! + r/3! + ... + r^11/13!: the truncation error is below
// 2^-57 relative for |r| <= ln2/2.
constexpr double kExpTail[] = {
    1.0 / 2.0,       1.0 / 6.0,         1.0 / 24.0,         1.0 / 120.0,
    1.0 / 720.0,     1.0 / 5040.0,      1.0 / 40320.0,      1.0 / 362880.0,
    1.0 / 3628800.0, 1.0 / 39916800.0,  1.0 / 479001600.0,  1.0 / 6227020800.0,
};

}  // namespace

std::uint64_t bitsOf(double x) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &x, sizeof bits);
    return bits;
}

double fromBits(std::uint64_t bits) noexcept {
    double x = 0.0;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}

bool isNaN(double x) noexcept {
    const std::uint64_t b = bitsOf(x);
    return (b & kExponentMask) == kExponentMask && (b & kMantissaMask) != 0U;
}

bool isFinite(double x) noexcept { return (bitsOf(x) & kExponentMask) != kExponentMask; }

double exp(double x) noexcept {
    if (isNaN(x)) {
        return kNaN;
    }
    if (x > kExpOverflowArgument) {
        return kInfinity;
    }
    if (x < kExpUnderflowArgument) {
        return 0.0;
    }
    // x = k ln2 + r with |r| <= ln2/2 (Cody-Waite); e^x = 2^k e^r.
    const auto k = static_cast<std::int32_t>(nearestInteger(x * kInvLn2));
    const double kd = static_cast<double>(k);
    const double head = x - kd * kLn2Hi;  // exact: product exact, Sterbenz subtraction
    const DoubleDouble r = twoSum(head, -(kd * kLn2Lo));
    // e^r = 1 + r + r^2 * tail(r); 1 + r is kept exactly as a double-double so the only
    // sizeable rounding is the final one. e^(r.hi + r.lo) ~ e^r.hi * (1 + r.lo).
    const double tail = (r.hi * r.hi) * horner(kExpTail, r.hi);
    const DoubleDouble onePlusR = fastTwoSum(1.0, r.hi);
    const double low = (onePlusR.lo + (r.lo + r.lo * r.hi)) + tail;
    return scaleByPow2(onePlusR.hi + low, k);
}

namespace {

// ---------------------------------------------------------------------------- log --

constexpr double kSqrtTwo = 0x1.6a09e667f3bcdp+0;

// 2 atanh(s) = 2s + s * R(s^2), R(z) = 2z/3 + 2z^2/5 + ...; with |s| <= 0.1716 the
// terms beyond 2z^11/23 are below 2^-60 relative.
constexpr double kLogSeries[] = {
    2.0 / 3.0,  2.0 / 5.0,  2.0 / 7.0,  2.0 / 9.0,  2.0 / 11.0, 2.0 / 13.0,
    2.0 / 15.0, 2.0 / 17.0, 2.0 / 19.0, 2.0 / 21.0, 2.0 / 23.0,
};

// Splits finite x > 0 into x = 2^k * m with m in (sqrt(2)/2, sqrt(2)].
double splitMantissa(double x, std::int32_t& k) noexcept {
    k = binaryExponent(x);
    if (x < kSmallestNormal) {
        x *= 0x1.0p54;  // exact; binaryExponent() accounted for it
    }
    double m = fromBits((bitsOf(x) & kMantissaMask) | kExponentOfOne);  // [1, 2)
    if (m > kSqrtTwo) {
        m *= 0.5;
        ++k;
    }
    return m;
}

}  // namespace

double log(double x) noexcept {
    if (isNaN(x) || x < 0.0) {
        return kNaN;
    }
    if (x == 0.0) {
        return -kInfinity;
    }
    if (x == kInfinity) {
        return kInfinity;
    }
    std::int32_t k = 0;
    const double m = splitMantissa(x, k);
    // log(m) = log(1 + f) = f - f^2/2 + s (f^2/2 + R(s^2)), s = f / (2 + f) (atanh
    // series). f = m - 1 is exact (Sterbenz) and f^2/2 is kept exactly, so the rounding
    // of s only touches the small last term.
    const double f = m - 1.0;
    const double s = f / (2.0 + f);
    const double z = s * s;
    const DoubleDouble fSquared = twoProd(f, f);
    const double halfSq = 0.5 * fSquared.hi;
    const double correction = s * (halfSq + z * horner(kLogSeries, z));
    // k ln2 + f - f^2/2 accumulated with exact sums (|k ln2| >= |f| when k != 0, and
    // |f^2/2| < |k ln2 + f| always), then all low-order parts are added at the end.
    const double kd = static_cast<double>(k);
    const DoubleDouble head = fastTwoSum(kd * kLn2Hi, f);
    const DoubleDouble body = fastTwoSum(head.hi, -halfSq);
    const double low = ((head.lo + body.lo) - 0.5 * fSquared.lo) + (correction + kd * kLn2Lo);
    return body.hi + low;
}

double log1p(double x) noexcept {
    if (isNaN(x) || x < -1.0) {
        return kNaN;
    }
    if (x == kInfinity) {
        return kInfinity;
    }
    const double u = 1.0 + x;
    if (u == 1.0) {
        return x;  // |x| below half an ulp of 1: ln(1 + x) = x to within x^2 / 2 (keeps -0)
    }
    if (u == 0.0) {
        return -kInfinity;  // x = -1
    }
    // u - 1 is exact (Sterbenz for u in [0.5, 2]; a multiple of u's ulp below u beyond),
    // so c = x - (u - 1) is exactly the error of rounding 1 + x, and
    // ln(1 + x) = ln(u) + ln(1 + c/u) = ln(u) + c/u to within (c/u)^2 / 2.
    const double c = x - (u - 1.0);
    return log(u) + c / u;
}

namespace {

// -------------------------------------------------------------------- sin and cos --

// pi/2 = P1 + P2 + P3 + P4 to 2^-163 (Cody-Waite). P1 and P2 have 26 significant bits,
// so k*P1 and k*P2 are exact for |k| < 2^27; k*P3 is taken exactly with twoProd. The
// usual three parts (33 + 33 + 53 bits) are not enough near multiples of pi/2: the
// double nearest 9206271 * pi/2 (about 1.45e7) lies only 2^-59 from it, and a 119-bit
// constant would be ~4800 ulp off there (3.3 ulp already at x = 321307.96, k = 204551).
constexpr double kHalfPiPart1 = 0x1.921fb58000000p+0;
constexpr double kHalfPiPart2 = -0x1.dde9740000000p-27;
constexpr double kHalfPiPart3 = 0x1.1a62633145c07p-54;
constexpr double kHalfPiPart4 = -0x1.f1976b7ed8fbcp-110;
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
// Below this |x|, sin x rounds to x and cos x to 1 (x^3/6, x^2/2 under half an ulp).
constexpr double kTrigTinyArgument = 0x1.0p-27;

// (sin r - r + r^3/6) / r^5 as a series in z = r^2, to r^21/21!: accurate for
// |r| <= 1.3, wider than the reduced range, so arguments beyond kTrigAccurateLimit
// stay well-behaved.
constexpr double kSinSeries[] = {
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362880.0,
    -1.0 / 39916800.0,
    1.0 / 6227020800.0,
    -1.0 / 1307674368000.0,
    1.0 / 355687428096000.0,
    -1.0 / 121645100408832000.0,
    1.0 / 51090942171709440000.0,
};
// (cos r - 1 + r^2/2) / r^4 as a series in z = r^2, to r^22/22!.
constexpr double kCosSeries[] = {
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40320.0,
    -1.0 / 3628800.0,
    1.0 / 479001600.0,
    -1.0 / 87178291200.0,
    1.0 / 20922789888000.0,
    -1.0 / 6402373705728000.0,
    1.0 / 2432902008176640000.0,
    -1.0 / 1124000727777607680000.0,
};

struct ReducedAngle {
    DoubleDouble r;          // x - k pi/2, |r| <~ pi/4, to ~106 bits
    std::int32_t quadrant;   // k mod 4, in 0..3
};

// x - k pi/2 for |x| < 2^52 with k = nearest integer to x * 2/pi.
ReducedAngle reduceHalfPi(double x) noexcept {
    const std::int64_t k = nearestInteger(x * kTwoOverPi);
    const double kd = static_cast<double>(k);
    const double t1 = x - kd * kHalfPiPart1;  // exact for |k| < 2^27 (Sterbenz)
    const DoubleDouble t2 = twoSum(t1, -(kd * kHalfPiPart2));
    const DoubleDouble p3 = twoProd(kd, kHalfPiPart3);
    const DoubleDouble t3 = twoSum(t2.hi, -p3.hi);
    const double low = ((t2.lo + t3.lo) - p3.lo) - kd * kHalfPiPart4;
    // Two's complement: k & 3 is k mod 4 for negative k too.
    const auto quadrant = static_cast<std::int32_t>(static_cast<std::uint64_t>(k) & 3U);
    return {twoSum(t3.hi, low), quadrant};
}

// sin(r.hi + r.lo) ~ sin(r.hi) + r.lo cos(r.hi). r - r^3/6 is formed as a
// double-double (exact r^3, r^3/6 with its exact division remainder), so the result
// carries one rounding plus a small share of the r^5 series' error.
double sinKernel(const DoubleDouble& r) noexcept {
    const DoubleDouble sq = twoProd(r.hi, r.hi);
    const DoubleDouble cube = twoProd(r.hi, sq.hi);
    const double cubeLo = cube.lo + r.hi * sq.lo;
    const double sixth = cube.hi / 6.0;
    const DoubleDouble back = twoProd(sixth, 6.0);
    const double sixthLo = (((cube.hi - back.hi) - back.lo) + cubeLo) / 6.0;
    const DoubleDouble head = fastTwoSum(r.hi, -sixth);  // |r| > |r^3/6|
    const double z = sq.hi;
    const double series = (cube.hi * z) * horner(kSinSeries, z);
    return head.hi + ((head.lo - sixthLo) + (series + r.lo * (1.0 - 0.5 * z)));
}

// cos(r.hi + r.lo) ~ cos(r.hi) - r.lo sin(r.hi). 1 - r^2/2 is formed exactly so the
// result carries one rounding plus a small share of the series' error.
double cosKernel(const DoubleDouble& r) noexcept {
    const DoubleDouble sq = twoProd(r.hi, r.hi);
    const double halfSq = 0.5 * sq.hi;
    const double w = 1.0 - halfSq;
    const double wErr = (1.0 - w) - halfSq;  // exact (Fast2Sum, 1 >= halfSq)
    const double series = (sq.hi * sq.hi) * horner(kCosSeries, sq.hi);
    return w + ((wErr - 0.5 * sq.lo) + (series - r.hi * r.lo));
}

}  // namespace

double sin(double x) noexcept {
    const double ax = std::fabs(x);
    if (!(ax < kTrigMaxArgument)) {  // also NaN and +-inf
        return kNaN;
    }
    if (ax < kTrigTinyArgument) {
        return x;  // keeps the sign of zero
    }
    const ReducedAngle a = reduceHalfPi(x);
    switch (a.quadrant) {
        case 0: return sinKernel(a.r);
        case 1: return cosKernel(a.r);
        case 2: return -sinKernel(a.r);
        default: return -cosKernel(a.r);
    }
}

double cos(double x) noexcept {
    const double ax = std::fabs(x);
    if (!(ax < kTrigMaxArgument)) {
        return kNaN;
    }
    if (ax < kTrigTinyArgument) {
        return 1.0;
    }
    const ReducedAngle a = reduceHalfPi(x);
    switch (a.quadrant) {
        case 0: return cosKernel(a.r);
        case 1: return -sinKernel(a.r);
        case 2: return -cosKernel(a.r);
        default: return sinKernel(a.r);
    }
}

namespace {

// ---------------------------------------------------------------------------- atan2 --

constexpr DoubleDouble kPiDD = {0x1.921fb54442d18p+1, 0x1.1a62633145c07p-53};
constexpr DoubleDouble kHalfPiDD = {0x1.921fb54442d18p+0, 0x1.1a62633145c07p-54};
constexpr double kQuarterPi = 0x1.921fb54442d18p-1;
constexpr double kThreeQuarterPi = 0x1.2d97c7f3321d2p+1;
// atan(i/4), i = 0..4, as double-doubles: the breakpoints of the argument reduction.
constexpr DoubleDouble kAtanQuarters[] = {
    {0.0, 0.0},
    {0x1.f5b75f92c80ddp-3, 0x1.8ab6e3cf7afbdp-57},
    {0x1.dac670561bb4fp-2, 0x1.a2b7f222f65e2p-56},
    {0x1.4978fa3269ee1p-1, 0x1.2419a87f2a458p-56},
    {0x1.921fb54442d18p-1, 0x1.1a62633145c07p-55},
};
// (atan u - u) / u^3 as a series in z = u^2, to u^19/19: with |u| <= 1/8 the next term
// is below 2^-60 relative.
constexpr double kAtanSeries[] = {
    -1.0 / 3.0,  1.0 / 5.0,  -1.0 / 7.0,  1.0 / 9.0,   -1.0 / 11.0,
    1.0 / 13.0,  -1.0 / 15.0, 1.0 / 17.0, -1.0 / 19.0,
};
// Exponent gap beyond which atan(n/d) = n/d to within a fraction of an ulp
// (the next term, t^3/3, is below 2^-120 relative).
constexpr std::int32_t kAtanLinearExponentGap = 60;

// atan(t.hi + t.lo) for 0 <= t <= 1. Reduction: atan t = atan b + atan u with b = i/4
// the nearest quarter and u = (t - b) / (1 + t b), |u| <= 1/8, formed as a
// double-double (the subtraction t.hi - b is exact by Sterbenz).
DoubleDouble atanUnit(const DoubleDouble& t) noexcept {
    const auto i = static_cast<std::size_t>(nearestInteger(4.0 * t.hi));
    const double b = 0.25 * static_cast<double>(i);
    const DoubleDouble num = twoSum(t.hi - b, t.lo);
    const DoubleDouble tb = twoProd(t.hi, b);
    const DoubleDouble den = fastTwoSum(1.0, tb.hi);
    const double denLo = (den.lo + tb.lo) + t.lo * b;
    const double uHi = num.hi / den.hi;
    const DoubleDouble q = twoProd(uHi, den.hi);
    // Remainder num - uHi * den: the first two steps are exact (Sterbenz, and the
    // remainder of a correctly rounded division is representable).
    const double uLo = ((((num.hi - q.hi) - q.lo) + num.lo) - uHi * denLo) / den.hi;
    const double z = uHi * uHi;
    const DoubleDouble sum = twoSum(kAtanQuarters[i].hi, uHi);
    const double low = (sum.lo + kAtanQuarters[i].lo) + (uLo * (1.0 - z) + (uHi * z) * horner(kAtanSeries, z));
    return {sum.hi, low};
}

// atan(num / den) for finite 0 < num <= den, as a double-double.
DoubleDouble atanRatio(double num, double den) noexcept {
    const std::int32_t e = binaryExponent(den);
    if (e - binaryExponent(num) > kAtanLinearExponentGap) {
        return {num / den, 0.0};
    }
    // Scale so den is in [1, 2): exact, and num >= 2^-61 stays normal, so the
    // error-free products below cannot underflow or overflow.
    const double n = scaleByPow2(num, -e);
    const double d = scaleByPow2(den, -e);
    const double tHi = n / d;
    const DoubleDouble p = twoProd(tHi, d);
    const double tLo = ((n - p.hi) - p.lo) / d;
    return atanUnit({tHi, tLo});
}

// Angle of (ax, ay), ax, ay finite and > 0, with the x sign given: result in (0, pi).
double atan2Positive(double ay, double ax, bool xNegative) noexcept {
    const bool steep = ay > ax;  // angle from the y axis is the smaller one
    DoubleDouble a = steep ? atanRatio(ax, ay) : atanRatio(ay, ax);
    DoubleDouble base = {0.0, 0.0};
    bool subtract = false;
    if (steep) {
        base = kHalfPiDD;  // pi/2 -+ atan(|x|/|y|)
        subtract = !xNegative;
    } else if (xNegative) {
        base = kPiDD;  // pi - atan(|y|/|x|)
        subtract = true;
    }
    if (subtract) {
        a = {-a.hi, -a.lo};
    }
    const DoubleDouble s = twoSum(base.hi, a.hi);
    return s.hi + (s.lo + (base.lo + a.lo));
}

}  // namespace

double atan2(double y, double x) noexcept {
    if (isNaN(x) || isNaN(y)) {
        return kNaN;
    }
    const bool yNegative = (bitsOf(y) & kSignMask) != 0U;
    const bool xNegative = (bitsOf(x) & kSignMask) != 0U;  // -0 counts as negative (C99)
    const double ay = std::fabs(y);
    const double ax = std::fabs(x);
    double angle = 0.0;
    if (ay == kInfinity) {
        angle = (ax == kInfinity) ? (xNegative ? kThreeQuarterPi : kQuarterPi) : kHalfPi;
    } else if (ay == 0.0 || ax == kInfinity) {
        angle = xNegative ? kPi : 0.0;  // on the x axis, or x infinitely longer than y
    } else if (ax == 0.0) {
        angle = kHalfPi;
    } else {
        angle = atan2Positive(ay, ax, xNegative);
    }
    return yNegative ? -angle : angle;
}

double sqrt(double x) noexcept {
    // Screened first: the hardware's NaN for sqrt(-1) is negative on x86 and positive
    // on ARM, and NaN payloads propagate differently.
    if (isNaN(x) || x < 0.0) {
        return kNaN;
    }
    return std::sqrt(x);
}

}  // namespace vtm::math
