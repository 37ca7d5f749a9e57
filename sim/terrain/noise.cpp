#include "noise.hpp"

#include <cmath>

#include "vtm/core/random.hpp"

namespace vtm::sim::noise {
namespace {

// Unit gradients at multiples of 22.5 degrees (correctly rounded literals).
constexpr double kGradX[16] = {1.0, 0.9238795325112867, 0.7071067811865476, 0.3826834323650898,
                               0.0, -0.3826834323650898, -0.7071067811865476, -0.9238795325112867,
                               -1.0, -0.9238795325112867, -0.7071067811865476, -0.3826834323650898,
                               0.0, 0.3826834323650898, 0.7071067811865476, 0.9238795325112867};
constexpr double kGradY[16] = {0.0, 0.3826834323650898, 0.7071067811865476, 0.9238795325112867,
                               1.0, 0.9238795325112867, 0.7071067811865476, 0.3826834323650898,
                               0.0, -0.3826834323650898, -0.7071067811865476, -0.9238795325112867,
                               -1.0, -0.9238795325112867, -0.7071067811865476, -0.3826834323650898};

double fade(double t) noexcept { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// One finaliser over the key and both (odd-multiplied) lattice indices: enough mixing for
// noise, and it is the inner loop of the terrain build.
std::uint64_t corner(std::uint64_t key, std::int64_t ix, std::int64_t iy) noexcept {
    return mixBits64(key ^ (static_cast<std::uint64_t>(ix) * 0xD6E8FEB86659FD93ULL) ^
               (static_cast<std::uint64_t>(iy) * 0x9E3779B97F4A7C15ULL));
}

double gradDot(std::uint64_t h, double dx, double dy) noexcept {
    const std::size_t g = static_cast<std::size_t>(h >> 60U);
    return kGradX[g] * dx + kGradY[g] * dy;
}

// [-1, 1] from the top 53 bits.
double signedUnit(std::uint64_t h) noexcept {
    return static_cast<double>(h >> 11U) * (2.0 / 9007199254740992.0) - 1.0;
}

}  // namespace

std::uint64_t hash(std::uint64_t seed, Stream stream, std::int64_t a, std::int64_t b) noexcept {
    std::uint64_t h = mixBits64(seed + 0x9E3779B97F4A7C15ULL);
    h = mixBits64(h ^ (static_cast<std::uint64_t>(stream) * 0xD1B54A32D192ED03ULL));
    h = mixBits64(h ^ static_cast<std::uint64_t>(a));
    return mixBits64(h ^ (static_cast<std::uint64_t>(b) * 0xA0761D6478BD642FULL));
}

double gradient(std::uint64_t key, double x, double y) noexcept {
    const double fx0 = std::floor(x);
    const double fy0 = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx0);
    const auto iy = static_cast<std::int64_t>(fy0);
    const double dx = x - fx0;
    const double dy = y - fy0;
    const double n00 = gradDot(corner(key, ix, iy), dx, dy);
    const double n10 = gradDot(corner(key, ix + 1, iy), dx - 1.0, dy);
    const double n01 = gradDot(corner(key, ix, iy + 1), dx, dy - 1.0);
    const double n11 = gradDot(corner(key, ix + 1, iy + 1), dx - 1.0, dy - 1.0);
    const double u = fade(dx);
    const double v = fade(dy);
    const double a = n00 + u * (n10 - n00);
    const double b = n01 + u * (n11 - n01);
    return a + v * (b - a);
}

double value(std::uint64_t key, double x, double y) noexcept {
    const double fx0 = std::floor(x);
    const double fy0 = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx0);
    const auto iy = static_cast<std::int64_t>(fy0);
    const double u = fade(x - fx0);
    const double v = fade(y - fy0);
    const double n00 = signedUnit(corner(key, ix, iy));
    const double n10 = signedUnit(corner(key, ix + 1, iy));
    const double n01 = signedUnit(corner(key, ix, iy + 1));
    const double n11 = signedUnit(corner(key, ix + 1, iy + 1));
    const double a = n00 + u * (n10 - n00);
    const double b = n01 + u * (n11 - n01);
    return a + v * (b - a);
}

double smoothstep(double t) noexcept {
    const double c = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return c * c * (3.0 - 2.0 * c);
}

double octaveWeight(double wavelength_m, double cell_m) noexcept {
    return smoothstep((wavelength_m / cell_m - 2.0) * 0.5);
}

Rotation octaveRotation(int octave) noexcept {
    // (3,4,5), (5,12,13), (8,15,17), (7,24,25), (20,21,29) and their swaps/signs.
    constexpr Rotation kTable[8] = {{0.6, 0.8},   {5.0 / 13.0, -12.0 / 13.0}, {15.0 / 17.0, 8.0 / 17.0},
                                    {-0.28, 0.96}, {20.0 / 29.0, 21.0 / 29.0}, {-0.8, -0.6},
                                    {12.0 / 13.0, 5.0 / 13.0}, {-8.0 / 17.0, 15.0 / 17.0}};
    return kTable[static_cast<unsigned>(octave) & 7U];
}

}  // namespace vtm::sim::noise
