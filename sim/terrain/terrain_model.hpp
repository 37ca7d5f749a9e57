// The terrain's procedural model, shared by the builder, the queries and the rock API:
// relief and hills heights, crater bins and profile, rock density, powers and limits.
// Internal to sim/terrain (docs/sim-terrain.md describes the model).
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim/terrain.hpp"

namespace vtm::sim::model {

// Limits that validate() enforces so that build time and loop bounds stay finite.
inline constexpr std::int64_t kMaxCratersPerBin = 200000;
inline constexpr double kMaxRocksPerTileMean = 600.0;  // Poisson mean; kMaxRocksPerTile caps the draw
inline constexpr int kMaxOctaves = 40;                  // any fractal sum
inline constexpr int kMaxTextureOctaves = 24;
inline constexpr int kRockDiameterDraws = 64;           // rejection-sampling bound per rock

// x^y for x > 0 via vtm::math (bit-identical everywhere).
[[nodiscard]] double power(double x, double y) noexcept;

// Elevation of the analytic plane (plane and dome kinds) and of the dome on it, at an
// offset (d_north_m, d_east_m) from the grid centre (offsets keep dyadic inputs exact).
[[nodiscard]] double planeElevation(const TerrainParams& p, double d_north_m, double d_east_m) noexcept;
[[nodiscard]] double domeElevation(const TerrainParams& p, double d_north_m, double d_east_m) noexcept;

// A fractal sum prepared for one grid cell size: per octave its lattice key, rotation
// scaled by 1/wavelength, lattice offset and amplitude times resolvability weight.
struct OctaveSet {
    int count = 0;
    std::uint64_t key[kMaxOctaves] = {};
    double cos_per_m[kMaxOctaves] = {};
    double sin_per_m[kMaxOctaves] = {};
    double offset[kMaxOctaves] = {};
    double weight[kMaxOctaves] = {};
};

// The Mars kind's low-frequency fields for one level (cell_m): fractal relief + far
// hills (without craters and rocks, which are stamped into the grids), relative to
// base_elevation_m, and the grid albedo before rocks.
class GroundModel {
public:
    GroundModel(const TerrainParams& p, double cell_m) noexcept;
    [[nodiscard]] double relief(double north_m, double east_m) const noexcept;
    [[nodiscard]] double albedo(double north_m, double east_m) const noexcept;  // 0 .. 1

private:
    const TerrainParams& p_;
    OctaveSet relief_;
    OctaveSet hills_;
    OctaveSet albedo_;
};

// Craters of bin k: diameters [lo, hi) drawn within the square of half side half_m
// about the centre (the region of level k plus the ejecta reach of the largest).
struct CraterBin {
    double lo_m = 0.0;
    double hi_m = 0.0;
    double half_m = 0.0;
    std::int64_t count = 0;
};
[[nodiscard]] CraterBin craterBin(const TerrainParams& p, int k) noexcept;
struct Crater {
    double north_m;
    double east_m;
    double diameter_m;
    double depth_m;
    double rim_m;
};
// Relative height of a crater's profile at horizontal distance r_m from its centre:
// parabolic bowl up to the rim, ejecta decaying as r^-3 to zero at two radii.
[[nodiscard]] double craterProfile(const Crater& c, double r_m) noexcept;

// Rocks per square metre with diameter in [min, max] (Golombek number density integrated).
[[nodiscard]] double rockNumberDensity(const TerrainParams& p) noexcept;
// terrainRocksInTile() with the density computed once by the caller.
[[nodiscard]] std::size_t rocksInTile(const TerrainParams& p, double density_per_m2, std::int64_t tile_north,
                                      std::int64_t tile_east, Span<TerrainRock> out) noexcept;
// Height of a rock above the ground at a site position (0 outside its outline).
[[nodiscard]] double rockProfile(const TerrainRock& r, double north_m, double east_m) noexcept;
// Half width of the square around a rock's centre that holds its outline.
[[nodiscard]] double rockReach_m(const TerrainRock& r) noexcept;

}  // namespace vtm::sim::model
