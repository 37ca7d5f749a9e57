// Terrain: a deterministic, seeded, procedural Mars-like surface for a whole scenario
// (docs/sim-terrain.md). Built once into memory from a caller's Arena, then queried
// read-only: every const member is thread-safe and allocates nothing.
//
// Geometry. Nested square grids (a clipmap) centred on (centre_north_m, centre_east_m):
// level 0 has 2^samples_log2 cells of finest_cell_m per side, level k doubles the cell,
// so every level has the same sample count and covers four times the area of the one
// inside it. The surface is the bilinear interpolation of the samples of the FINEST
// level that contains a point (independent of any camera, so every camera sees the same
// surface: stereo ground truth is exact). A level's outer eighth is blended towards the
// next coarser level so that on its border the two surfaces agree (continuous surface).
// Heights are stored as float: the surface IS the bilinear interpolation of those
// float samples, so intersect(), elevationAt() and shadingNormal() agree with each other
// to double rounding.
//
// Frames: site frame, x north, y east, z DOWN (metres; hal/include/hal/odometry.hpp).
// Elevation is height UP = -z.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::sim {

enum class TerrainKind : std::uint8_t {
    kMars = 0,   // fractal relief + craters + rocks + far hills + albedo texture
    kPlane = 1,  // analytic plane: base_elevation_m + slopes (for ray-cast tests)
    kDome = 2,   // analytic hemisphere (dome_radius_m) standing on the plane above
};

// Plain data; a scenario file fills it (sim/scenario). Every field has a unit in its
// name; validate() range-checks all of them. defaultMarsTerrainParams() gives a rover
// world; the comments give those defaults.
struct TerrainParams {
    std::uint64_t seed = 1U;
    TerrainKind kind = TerrainKind::kMars;

    // --- grids -------------------------------------------------------------------------
    double centre_north_m = 0.0;   // centre of every level (site frame)
    double centre_east_m = 0.0;
    double finest_cell_m = 0.01;   // level-0 sample spacing, 1e-4 .. 100
    int samples_log2 = 10;         // 2^n cells per side per level, 3 .. 12
    int levels = 12;               // 1 .. kMaxLevels

    // --- base and analytic kinds ---------------------------------------------------------
    double base_elevation_m = 0.0;  // elevation at the centre (all kinds)
    double plane_slope_north = 0.0; // d(elevation)/d(north) [m/m] (plane and dome kinds), |s| <= 10
    double plane_slope_east = 0.0;  // d(elevation)/d(east) [m/m]
    double dome_centre_north_m = 0.0;
    double dome_centre_east_m = 0.0;
    double dome_radius_m = 1.0;     // > 0: elevation = plane + sqrt(R^2 - r^2) inside r < R

    // --- fractal relief (sum of octaves of seeded gradient noise) ------------------------
    double relief_amplitude_m = 4.0;          // amplitude of the longest octave, 0 .. 1000
    double relief_longest_wavelength_m = 64.0;  // > 0 ; octaves halve down to ~2 cells of each level
    double relief_hurst = 0.8;                // amplitude ratio per octave = 2^-hurst, 0 .. 1

    // --- craters (power-law size-frequency distribution) ---------------------------------
    double crater_density_per_km2 = 2000.0;   // cumulative count with D >= crater_min_diameter_m per km^2
    double crater_sfd_slope = 2.0;            // N(>D) ~ D^-slope, 1 .. 4
    double crater_min_diameter_m = 0.5;       // smallest crater (never below 2 cells of level 0)
    double crater_max_diameter_m = 400.0;
    double crater_depth_ratio = 0.15;         // bowl depth / diameter, 0 .. 0.5
    double crater_rim_ratio = 0.03;           // rim height / diameter, 0 .. 0.2 (ejecta to 2 radii)

    // --- rocks (Golombek & Rapp 1997: cumulative fractional area F(D) = k exp(-q D),
    //     q = 1.79 + 0.152 / k); half-buried ellipsoids, placed within rock_region_radius_m
    double rock_k = 0.07;                     // total fractional area k, 0 (no rocks) .. 0.5
    double rock_min_diameter_m = 0.05;        // 0.01 .. rock_max_diameter_m
    double rock_max_diameter_m = 2.0;         // .. 3.0
    double rock_height_ratio = 0.5;           // mean visible height / diameter, 0.1 .. 1
    double rock_region_radius_m = 60.0;       // around the centre, 0 .. 2000

    // --- far hills (for the horizon) -----------------------------------------------------
    double hills_start_m = 300.0;             // horizontal distance from the centre where they begin
    double hills_full_m = 2000.0;             // ... and reach full amplitude (> start)
    double hills_amplitude_m = 250.0;         // 0 .. 5000
    double hills_wavelength_m = 1500.0;       // > 0

    // --- albedo ----------------------------------------------------------------------------
    double albedo_mean = 0.25;                // 0 .. 1
    double albedo_variation = 0.25;           // relative low-frequency variation, 0 .. 1
    double albedo_wavelength_m = 20.0;        // longest albedo-variation wavelength, > 0
    double rock_albedo_mean = 0.18;           // 0 .. 1
    double rock_albedo_spread = 0.05;         // +- uniform, 0 .. 0.5
    double texture_contrast = 0.35;           // relative amplitude of the fine texture, 0 .. 1
    double texture_longest_wavelength_m = 0.5;  // fine texture from here ...
    double texture_finest_wavelength_m = 0.001; // ... down to here (millimetre), > 0

    // Each bad field gives StatusCode::kInvalidConfig with a reason naming it.
    [[nodiscard]] Status validate() const noexcept;
};

// A rover world: 10 mm finest cell, 1024 cells per side, 12 levels (about 21 km across).
[[nodiscard]] TerrainParams defaultMarsTerrainParams() noexcept;

inline constexpr int kMaxTerrainLevels = 16;

// Rocks are drawn per square tile of kRockTile_m (north/east index = floor((x - centre) /
// kRockTile_m)) from vtm::Random seeded with (seed, tile), so any part of the field can be
// regenerated without storing it. A rock's visible outline is an ellipse of area
// pi * diameter_m^2 / 4 (diameter_m is the equivalent-circle diameter, as in rock counts
// from images); its shape is the cap of a buried ellipsoid.
inline constexpr double kRockTile_m = 4.0;
inline constexpr std::size_t kMaxRocksPerTile = 1024U;
// Plain data (trivial, so an Arena can hold arrays of it).
struct TerrainRock {
    double north_m;       // centre of the outline (site frame)
    double east_m;
    double diameter_m;    // equivalent-circle diameter of the visible outline
    double height_m;      // top above the surrounding ground
    double semi_major_m;  // visible outline semi-axes: semi_major * semi_minor = (D/2)^2
    double semi_minor_m;
    double cos_heading;   // direction of the major axis: (north, east) = (cos, sin)
    double sin_heading;
    double burial;        // buried fraction of the ellipsoid's vertical semi-axis, 0.2 .. 0.6
    double albedo;        // 0 .. 1
    std::uint64_t id;     // seeds the rock's surface noise
};
// Writes the rocks whose centre lies in tile (tile_north, tile_east) and inside
// rock_region_radius_m into `out` (at most kMaxRocksPerTile) and returns how many.
// params must be valid (validate()); kind other than kMars gives 0.
[[nodiscard]] std::size_t terrainRocksInTile(const TerrainParams& params, std::int64_t tile_north,
                                             std::int64_t tile_east, Span<TerrainRock> out) noexcept;
// Golombek & Rapp cumulative fractional area of rocks with diameter >= d_m:
// k exp(-q(k) d), q(k) = 1.79 + 0.152 / k (0 for k = 0).
[[nodiscard]] double golombekCumulativeArea(double k, double d_m) noexcept;

struct TerrainHit {
    double t_m = 0.0;           // ray parameter: distance along the unit direction (m)
    Vec3 point_site_m = Vec3::Zero();
    Vec3 normal_site = Vec3::Zero();  // unit geometric normal of the bilinear patch, pointing up (z < 0)
    int level = -1;             // grid level that governs the hit point
    bool hit = false;
};

// Optional per-caller counters (one per thread): intersect() adds to them.
struct TerrainRayStats {
    std::uint64_t rays = 0U;
    std::uint64_t steps = 0U;            // traversal iterations, all levels
    std::uint64_t bound_exceeded = 0U;   // rays given up at their loop bound (reported as no hit)
};

class Terrain {
public:
    Terrain() noexcept = default;

    // Arena bytes build() takes at most (exact formula, docs/sim-terrain.md). Invalid
    // params give 0.
    [[nodiscard]] static std::size_t storageBytes(const TerrainParams& params) noexcept;

    // Validates, carves storageBytes(params) from the arena (kOutOfMemory if it cannot)
    // and computes every grid. Deterministic: same params => same bytes on every target.
    [[nodiscard]] Status build(const TerrainParams& params, Arena& arena) noexcept;
    [[nodiscard]] bool built() const noexcept { return built_; }
    [[nodiscard]] const TerrainParams& params() const noexcept { return params_; }

    // Elevation (metres UP) of the surface at a horizontal site position. Outside the
    // outermost grid the nearest border point's elevation is returned.
    [[nodiscard]] double elevationAt(double north_m, double east_m) const noexcept;

    // First intersection of the ray origin + t * dir (site frame, z down, dir unit) with
    // the surface for t in (0, t_max_m]; hit = false for sky, for rays leaving the
    // outermost grid and for rays given up at their loop bound (counted in stats).
    [[nodiscard]] TerrainHit intersect(const Vec3& origin_site_m, const Vec3& dir_site, double t_max_m,
                                       TerrainRayStats* stats = nullptr) const noexcept;

    // Unit upward normal (site frame) of the surface smoothed to scale_m (finite
    // differences over max(scale_m, governing cell)); pass max(cell, pixel footprint) to
    // avoid aliasing.
    [[nodiscard]] Vec3 shadingNormal(double north_m, double east_m, double scale_m) const noexcept;

    // Albedo 0..1: grid albedo (low-frequency variation, rocks) times a procedural
    // texture down to texture_finest_wavelength_m. Octaves finer than footprint_m are
    // replaced by their mean, so distant pixels do not alias.
    [[nodiscard]] double albedoAt(double north_m, double east_m, double footprint_m) const noexcept;

    // Grid geometry, for renderers and tests.
    [[nodiscard]] int levelCount() const noexcept { return levels_; }
    [[nodiscard]] double cellSize_m(int level) const noexcept;
    // Half side of the square a level covers (metres, about the centre).
    [[nodiscard]] double halfExtent_m(int level) const noexcept;
    // Finest level containing the point, or -1 outside the outermost grid.
    [[nodiscard]] int governingLevel(double north_m, double east_m) const noexcept;

    // FNV-1a 64 over every grid value in a fixed (little-endian) byte order: equal on
    // every target for equal params.
    [[nodiscard]] std::uint64_t contentHash() const noexcept;

private:
    struct Level {
        float* height_m = nullptr;       // (n+1)^2 samples, row = north index
        std::uint16_t* albedo = nullptr; // (n+1)^2 samples, albedo * 65535
        float* mip_max_m[kMaxTerrainLevels] = {};  // mip m >= 1: (n >> m)^2 cell maxima
        double cell_m = 0.0;
    };

    TerrainParams params_{};
    Level level_[kMaxTerrainLevels] = {};
    int levels_ = 0;
    int n_log2_ = 0;
    std::int32_t n_ = 0;  // cells per side
    int texture_octaves_ = 0;
    double texture_norm_ = 1.0;  // sum of the texture octave amplitudes
    bool built_ = false;

    [[nodiscard]] double gridValue(int level, bool albedo, double u, double v) const noexcept;
    [[nodiscard]] double gridU(int level, double d_finest_cells) const noexcept;

    friend class TerrainBuilder;
    friend class TerrainRayCaster;
};

}  // namespace vtm::sim
