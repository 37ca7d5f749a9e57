// Seeded lattice noise for the procedural terrain: integer hashing, 2-D gradient (Perlin)
// noise for relief and value noise for texture, and the octave fade that band-limits a
// fractal sum to a grid cell or pixel footprint. Only + - * / floor and integer operations:
// bit-identical on every target.
#pragma once

#include <cstdint>

namespace vtm::sim::noise {

// Streams keep the hash inputs of different uses apart.
enum class Stream : std::uint64_t {
    kRelief = 1U,
    kHills = 2U,
    kAlbedo = 3U,
    kTexture = 4U,
    kCraters = 5U,
    kRocks = 6U,
    kRockSurface = 7U,
};

// 64-bit hash of (seed, stream, a, b): splitmix64 finaliser over each word.
[[nodiscard]] std::uint64_t hash(std::uint64_t seed, Stream stream, std::int64_t a, std::int64_t b) noexcept;

// Gradient noise at (x, y) in lattice units, about [-0.7, 0.7], zero on lattice points,
// C2 (quintic fade). `key` selects the lattice (hash of seed, stream, octave).
[[nodiscard]] double gradient(std::uint64_t key, double x, double y) noexcept;
// Value noise at (x, y) in lattice units, in [-1, 1], C2.
[[nodiscard]] double value(std::uint64_t key, double x, double y) noexcept;

// Weight of an octave of wavelength_m on a grid of cell cell_m or a pixel footprint:
// 0 at wavelength <= 2 cells (unresolvable), 1 at >= 4 cells, smooth in between.
[[nodiscard]] double octaveWeight(double wavelength_m, double cell_m) noexcept;

// 3t^2 - 2t^3 on t clamped to [0, 1].
[[nodiscard]] double smoothstep(double t) noexcept;

// Per-octave lattice rotations (exact Pythagorean cosines/sines), so octaves do not share
// grid-aligned artefacts.
struct Rotation {
    double c;
    double s;
};
[[nodiscard]] Rotation octaveRotation(int octave) noexcept;

}  // namespace vtm::sim::noise
