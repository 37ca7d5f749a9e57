// TerrainParams::validate(), the default rover world and the storage formula.
#include <cmath>

#include "terrain_model.hpp"

namespace vtm::sim {
namespace {

// NaN fails every comparison, so it is rejected too.
bool within(double v, double lo, double hi) noexcept { return v >= lo && v <= hi; }

Status bad(const char* reason) noexcept { return Status(StatusCode::kInvalidConfig, reason); }

Status validateGrid(const TerrainParams& p) noexcept {
    if (p.kind != TerrainKind::kMars && p.kind != TerrainKind::kPlane && p.kind != TerrainKind::kDome) {
        return Status(StatusCode::kInvalidConfig, "kind: must be mars (0), plane (1) or dome (2)",
                      static_cast<std::int64_t>(p.kind));
    }
    if (!within(p.centre_north_m, -1e7, 1e7)) {
        return bad("centre_north_m: must be finite, |value| <= 1e7");
    }
    if (!within(p.centre_east_m, -1e7, 1e7)) {
        return bad("centre_east_m: must be finite, |value| <= 1e7");
    }
    if (!within(p.finest_cell_m, 1e-4, 100.0)) {
        return bad("finest_cell_m: must be 1e-4 .. 100");
    }
    if (p.samples_log2 < 3 || p.samples_log2 > 12) {
        return Status(StatusCode::kInvalidConfig, "samples_log2: must be 3 .. 12", p.samples_log2);
    }
    if (p.levels < 1 || p.levels > kMaxTerrainLevels) {
        return Status(StatusCode::kInvalidConfig, "levels: must be 1 .. 16", p.levels);
    }
    if (!within(p.base_elevation_m, -1e5, 1e5)) {
        return bad("base_elevation_m: must be finite, |value| <= 1e5");
    }
    if (!within(p.plane_slope_north, -10.0, 10.0)) {
        return bad("plane_slope_north: must be -10 .. 10");
    }
    if (!within(p.plane_slope_east, -10.0, 10.0)) {
        return bad("plane_slope_east: must be -10 .. 10");
    }
    if (!within(p.dome_centre_north_m, -1e7, 1e7)) {
        return bad("dome_centre_north_m: must be finite, |value| <= 1e7");
    }
    if (!within(p.dome_centre_east_m, -1e7, 1e7)) {
        return bad("dome_centre_east_m: must be finite, |value| <= 1e7");
    }
    if (!within(p.dome_radius_m, 1e-6, 1e5)) {
        return bad("dome_radius_m: must be 1e-6 .. 1e5");
    }
    return Status::ok();
}

Status validateRelief(const TerrainParams& p) noexcept {
    if (!within(p.relief_amplitude_m, 0.0, 1000.0)) {
        return bad("relief_amplitude_m: must be 0 .. 1000");
    }
    // At most 30 octaves above two level-0 cells keeps the fractal sum bounded.
    if (!within(p.relief_longest_wavelength_m, 2.0 * p.finest_cell_m, 1e5) ||
        p.relief_longest_wavelength_m > p.finest_cell_m * 2147483648.0) {
        return bad("relief_longest_wavelength_m: must be 2 finest cells .. min(1e5, 2^31 cells)");
    }
    if (!within(p.relief_hurst, 0.0, 1.0)) {
        return bad("relief_hurst: must be 0 .. 1");
    }
    if (!within(p.hills_start_m, 0.0, 1e6)) {
        return bad("hills_start_m: must be 0 .. 1e6");
    }
    if (!within(p.hills_full_m, p.hills_start_m + 1e-3, 1e6 + 1.0)) {
        return bad("hills_full_m: must exceed hills_start_m (by 1 mm at least), <= 1e6");
    }
    if (!within(p.hills_amplitude_m, 0.0, 5000.0)) {
        return bad("hills_amplitude_m: must be 0 .. 5000");
    }
    if (!within(p.hills_wavelength_m, 1e-3, 1e6)) {
        return bad("hills_wavelength_m: must be 1e-3 .. 1e6");
    }
    return Status::ok();
}

Status validateCraters(const TerrainParams& p) noexcept {
    if (!within(p.crater_density_per_km2, 0.0, 1e7)) {
        return bad("crater_density_per_km2: must be 0 .. 1e7");
    }
    if (!within(p.crater_sfd_slope, 1.0, 4.0)) {
        return bad("crater_sfd_slope: must be 1 .. 4");
    }
    if (!within(p.crater_min_diameter_m, 1e-3, 1e5)) {
        return bad("crater_min_diameter_m: must be 1e-3 .. 1e5");
    }
    if (!within(p.crater_max_diameter_m, p.crater_min_diameter_m, 1e5)) {
        return bad("crater_max_diameter_m: must be crater_min_diameter_m .. 1e5");
    }
    if (!within(p.crater_depth_ratio, 0.0, 0.5)) {
        return bad("crater_depth_ratio: must be 0 .. 0.5");
    }
    if (!within(p.crater_rim_ratio, 0.0, 0.2)) {
        return bad("crater_rim_ratio: must be 0 .. 0.2");
    }
    for (int k = 0; k < p.levels; ++k) {  // bound: levels <= kMaxTerrainLevels
        const model::CraterBin bin = model::craterBin(p, k);
        if (bin.count > model::kMaxCratersPerBin) {
            return Status(StatusCode::kInvalidConfig,
                          "crater_density_per_km2: more than 200000 craters in one size bin", bin.count);
        }
    }
    return Status::ok();
}

Status validateRocks(const TerrainParams& p) noexcept {
    if (!within(p.rock_k, 0.0, 0.5)) {
        return bad("rock_k: must be 0 .. 0.5");
    }
    if (!within(p.rock_max_diameter_m, 0.01, 3.0)) {
        return bad("rock_max_diameter_m: must be 0.01 .. 3");
    }
    if (!within(p.rock_min_diameter_m, 0.01, p.rock_max_diameter_m)) {
        return bad("rock_min_diameter_m: must be 0.01 .. rock_max_diameter_m");
    }
    if (!within(p.rock_height_ratio, 0.1, 1.0)) {
        return bad("rock_height_ratio: must be 0.1 .. 1");
    }
    if (!within(p.rock_region_radius_m, 0.0, 2000.0)) {
        return bad("rock_region_radius_m: must be 0 .. 2000");
    }
    if (model::rockNumberDensity(p) * kRockTile_m * kRockTile_m > model::kMaxRocksPerTileMean) {
        return bad("rock_min_diameter_m: too small for rock_k (more than 600 rocks per 4 m tile)");
    }
    return Status::ok();
}

Status validateAlbedo(const TerrainParams& p) noexcept {
    if (!within(p.albedo_mean, 0.0, 1.0)) {
        return bad("albedo_mean: must be 0 .. 1");
    }
    if (!within(p.albedo_variation, 0.0, 1.0)) {
        return bad("albedo_variation: must be 0 .. 1");
    }
    if (!within(p.albedo_wavelength_m, 1e-3, 1e6)) {
        return bad("albedo_wavelength_m: must be 1e-3 .. 1e6");
    }
    if (!within(p.rock_albedo_mean, 0.0, 1.0)) {
        return bad("rock_albedo_mean: must be 0 .. 1");
    }
    if (!within(p.rock_albedo_spread, 0.0, 0.5)) {
        return bad("rock_albedo_spread: must be 0 .. 0.5");
    }
    if (!within(p.texture_contrast, 0.0, 1.0)) {
        return bad("texture_contrast: must be 0 .. 1");
    }
    if (!within(p.texture_finest_wavelength_m, 1e-5, 1e3)) {
        return bad("texture_finest_wavelength_m: must be 1e-5 .. 1e3");
    }
    // 2^23 = 8388608: at most 24 texture octaves.
    if (!within(p.texture_longest_wavelength_m, p.texture_finest_wavelength_m,
                p.texture_finest_wavelength_m * 8388608.0)) {
        return bad("texture_longest_wavelength_m: must be texture_finest_wavelength_m .. 2^23 times it");
    }
    return Status::ok();
}

// Arena::allocateArray aligns every block to Arena::kDefaultAlignment (16).
std::size_t block(std::size_t bytes) noexcept { return Arena::blockBytes(bytes, Arena::kDefaultAlignment); }

}  // namespace

Status TerrainParams::validate() const noexcept {
    VTM_RETURN_IF_ERROR(validateGrid(*this));
    VTM_RETURN_IF_ERROR(validateRelief(*this));
    VTM_RETURN_IF_ERROR(validateCraters(*this));
    VTM_RETURN_IF_ERROR(validateRocks(*this));
    return validateAlbedo(*this);
}

TerrainParams defaultMarsTerrainParams() noexcept { return TerrainParams{}; }

std::size_t Terrain::storageBytes(const TerrainParams& params) noexcept {
    if (!params.validate().isOk()) {
        return 0U;
    }
    const std::size_t n = std::size_t{1} << static_cast<unsigned>(params.samples_log2);
    const std::size_t samples = (n + 1U) * (n + 1U);
    std::size_t per_level = block(samples * sizeof(float)) + block(samples * sizeof(std::uint16_t));
    for (int m = 1; m <= params.samples_log2; ++m) {  // bound: samples_log2 <= 12
        const std::size_t side = n >> static_cast<unsigned>(m);
        per_level += block(side * side * sizeof(float));
    }
    // One float scratch grid (rock layer) and one tile of rocks, shared by every level
    // during build().
    return static_cast<std::size_t>(params.levels) * per_level + block(samples * sizeof(float)) +
           block(kMaxRocksPerTile * sizeof(TerrainRock));
}

}  // namespace vtm::sim
