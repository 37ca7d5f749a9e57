// The renderer's sensor model (docs/sim-render.md "Sensor"): from the noise-free
// photo-electron count a pixel collects to its digital number, and the two definitions the
// renderer's sources share (kNoHitF, finiteIn). Internal to vtm_sim_render.
#pragma once

#include <cstdint>
#include <limits>

#include "sim/render.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim::detail {

// A depth or range where the ray hits nothing (sky): NaN in the float products.
constexpr float kNoHitF = std::numeric_limits<float>::quiet_NaN();

// True when v is finite and within [lo, hi]: the renderer's parameter checks.
inline bool finiteIn(double v, double lo, double hi) noexcept { return math::isFinite(v) && v >= lo && v <= hi; }

// Per-frame constants of the sensor model, derived once from SensorParams and the size.
struct SensorConstants {
    double exposure_s = 0.0;
    double gain_dn_per_e = 0.0;
    double full_well_e = 0.0;
    double read_sigma_dn = 0.0;    // read noise expressed in DN (read_noise_e * gain)
    double dark_offset_dn = 0.0;
    double max_dn = 255.0;         // 2^bit_depth - 1
    double vignetting = 0.0;
    double centre_x_px = 0.0;      // image centre ((w - 1) / 2, (h - 1) / 2)
    double centre_y_px = 0.0;
    double inv_corner_r2_px2 = 0.0;  // 1 / (distance centre..corner)^2 (0 for a 1x1 image)
    bool shot_noise = false;
};

[[nodiscard]] SensorConstants makeSensorConstants(const SensorParams& sensor, std::int32_t width_px,
                                                  std::int32_t height_px) noexcept;

// Relative illumination V = 1 - vignetting * rho^2 at pixel (x, y) (rho: distance from
// the centre over the centre-to-corner distance): 1 at the centre, 1 - vignetting at a corner.
[[nodiscard]] double vignettingFactor(const SensorConstants& k, std::int32_t x, std::int32_t y) noexcept;

// Digital number of a pixel that collects mean_electrons on average. Draws from rng
// (shot noise first, then read noise, each only when enabled). saturated: the result is
// the top code or the charge hit the full well.
[[nodiscard]] std::uint16_t digitalNumber(const SensorConstants& k, double mean_electrons, Random& rng,
                                          bool& saturated) noexcept;

// Seed of the noise generator of one image row: a splitmix64 chain over
// (noise_seed, frame_index, row), so every row's noise is independent of the others and
// of the order in which rows are rendered.
[[nodiscard]] std::uint64_t rowNoiseSeed(std::uint64_t noise_seed, std::uint32_t frame_index,
                                         std::int32_t row) noexcept;

}  // namespace vtm::sim::detail
