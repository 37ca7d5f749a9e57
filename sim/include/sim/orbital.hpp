// Orbital view of the simulated world (docs/sim-render.md "Orbital view"): a nadir,
// orthographic image of a Terrain on a north/east grid, in a second modality and under
// its own sun, with the georeference of every pixel as ground truth. Used as the
// reference image a descent frame is registered to (issue 24: local-entropy matching).
//
// Grid (the georeference, OrbitalGeoreference): pixel (col, row), (0, 0) = the centre of
// the north-west corner cell; columns go EAST, rows go SOUTH (a map with north up):
//   north_m = north0_m - row * cell_m,   east_m = east0_m + col * cell_m.
// Orthographic and nadir: a pixel shows the terrain straight below its centre whatever
// its elevation (no relief displacement).
//
// Modalities (per sub-sample of a pixel; i = angle between the shading normal at the
// sub-sample's footprint and the sun, lit = 0 in a cast shadow, a = albedo at that footprint):
//   kVisible: reflected light, Lambertian as the camera renderer:
//       s = a * (lit * max(cos i, 0) + ambient) / full_scale_reflectance
//   kThermal: emitted light of a surface in radiative equilibrium:
//       T^4 = T_floor^4 + (T_subsolar^4) * (1 - a) * lit * max(cos i, 0)
//       (absorbed insolation (1 - a) cos i; a night/ambient floor T_floor); the pixel's
//       radiance is the mean of T^4 over its sub-samples (Stefan-Boltzmann), shown as the
//       brightness temperature T_b = (mean T^4)^(1/4):
//       s = (T_b - scale_min_k) / (scale_max_k - scale_min_k)
//   Dark ground is warm, bright ground cool; sunward slopes warm, shadows at the floor:
//   not a monotonic function of the visible image.
// Sensor: DN = round(max_dn * (offset_fs + s + noise_fs * N(0, 1))), clipped to
// [0, max_dn], max_dn = 2^bit_depth - 1 (8 or 16 bit).
//
// Determinism: IEEE + - * / and sqrt only (the fourth root is sqrt(sqrt)), -ffp-contract=off;
// one noise generator per row seeded by (noise_seed, row): same bytes on every target and
// for any row band. No heap: everything goes into caller views.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"

namespace vtm::sim {

class Terrain;  // sim/terrain.hpp

// Largest orbital image (width and height, pixels) and sub-samples per pixel axis.
constexpr std::int32_t kMaxOrbitalSizePx = 4096;
constexpr std::int32_t kMaxOrbitalSubsamples = 4;

enum class OrbitalModality : std::uint8_t {
    kVisible = 0,  // reflected sunlight (Lambertian)
    kThermal = 1,  // emitted: brightness temperature of radiative equilibrium
};

// Where the pixels are: the per-pixel ground truth of an orbital image.
struct OrbitalGeoreference {
    double north0_m = 0.0;  // site north of the centre of pixel (0, 0) (north-west corner)
    double east0_m = 0.0;   // site east of the centre of pixel (0, 0)
    double cell_m = 1.0;    // pixel size on the ground, both axes
    std::int32_t width_px = 0;
    std::int32_t height_px = 0;
    // Orientation: columns go east, rows go south (fixed; stated here for the file format).
};

// Pixel (col, row) of a site position (north, east), continuous (pixel centres at integers).
[[nodiscard]] Vec2 orbitalPixelFromSite(const OrbitalGeoreference& geo, double north_m, double east_m) noexcept;
// Site position (north, east) of a pixel position (col, row).
[[nodiscard]] Vec2 orbitalSiteFromPixel(const OrbitalGeoreference& geo, double col_px, double row_px) noexcept;

// Thermal model (kelvin). Defaults: a Mars-like noon: a black flat surface facing the sun
// reaches 300 K; nothing falls below 180 K (night, sky and conduction floor).
struct ThermalParams {
    double floor_k = 180.0;      // temperature of unlit ground, > 0
    double subsolar_k = 300.0;   // equilibrium temperature of a black surface facing the sun, > floor_k
    double scale_min_k = 170.0;  // brightness temperature at s = 0 (DN = offset)
    double scale_max_k = 300.0;  // ... at s = 1 (full scale), > scale_min_k
};

struct OrbitalParams {
    double centre_north_m = 0.0;  // site position of the image centre
    double centre_east_m = 0.0;
    double cell_m = 1.0;          // ground sample distance, metres per pixel, 1e-3 .. 1e3
    std::int32_t width_px = 512;  // 1 .. kMaxOrbitalSizePx
    std::int32_t height_px = 512;
    std::int32_t subsamples = 2;  // per pixel axis (1 .. kMaxOrbitalSubsamples): s x s sub-samples
    Vec3 to_sun_site = Vec3(0.0, -0.70710678118654752, -0.70710678118654752);  // unit, z down: sun up => z < 0
    bool shadows = true;          // cast shadows: one ray per sub-sample towards the sun
    double max_shadow_range_m = 5000.0;  // > 0
    OrbitalModality modality = OrbitalModality::kVisible;
    // kVisible
    double ambient = 0.125;                // sky light as a fraction of the direct sun, 0 .. 10
    double full_scale_reflectance = 0.5;   // a * (cos i + ambient) giving s = 1, > 0
    ThermalParams thermal{};
    // sensor
    std::int32_t bit_depth = 8;   // 8 (image8) or 16 (image16)
    double offset_fs = 0.02;      // dark offset, fraction of full scale, 0 .. 1
    double noise_fs = 0.004;      // noise sigma, fraction of full scale, 0 .. 1 (0: none)
    std::uint64_t noise_seed = 1U;
    // Rows [first_row, first_row + row_count) are rendered (row_count < 0: to the end).
    std::int32_t first_row = 0;
    std::int32_t row_count = -1;
};

// Checks every field; the reason names it ("orbital.cell_m: ...").
[[nodiscard]] Status validateOrbitalParams(const OrbitalParams& params) noexcept;

// The georeference of the image params describe (params need not be valid).
[[nodiscard]] OrbitalGeoreference orbitalGeoreference(const OrbitalParams& params) noexcept;

struct OrbitalOutput {
    ImageView<std::uint8_t> image8;    // bit_depth 8: width x height
    ImageView<std::uint16_t> image16;  // bit_depth 16: width x height
    ImageView<float> elevation_m;      // optional: terrain elevation (m, up) at each pixel centre
};

struct OrbitalStats {
    std::int64_t pixels = 0;
    std::int64_t shadowed_subsamples = 0;  // facing the sun but blocked by terrain
    std::int64_t saturated_pixels = 0;     // DN at 0 or max_dn after clipping
};

// Renders the orbital image (or a band of it). Failures (nothing written):
// kInvalidArgument for a null/unbuilt terrain or an invalid field (validateOrbitalParams),
// kSizeMismatch for an output view of the wrong size. stats may be null.
[[nodiscard]] Status renderOrbital(const Terrain& terrain, const OrbitalParams& params, const OrbitalOutput& out,
                                   OrbitalStats* stats) noexcept;

}  // namespace vtm::sim
