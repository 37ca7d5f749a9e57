// Sensor model of the renderer: vignetting, shot and read noise, gain, offset, clipping.
#include "sensor_model.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm::sim {

using detail::finiteIn;

Status validateSensorParams(const SensorParams& sensor) noexcept {
    if (sensor.bit_depth != 8 && sensor.bit_depth != 12) {
        return Status(StatusCode::kInvalidArgument, "sensor.bit_depth: must be 8 or 12", sensor.bit_depth);
    }
    if (!finiteIn(sensor.exposure_s, 1e-9, 1e6)) {
        return Status(StatusCode::kInvalidArgument, "sensor.exposure_s: must be finite and > 0");
    }
    if (!finiteIn(sensor.gain_dn_per_e, 1e-9, 1e6)) {
        return Status(StatusCode::kInvalidArgument, "sensor.gain_dn_per_e: must be finite and > 0");
    }
    if (!finiteIn(sensor.full_well_e, 1.0, 1e12)) {
        return Status(StatusCode::kInvalidArgument, "sensor.full_well_e: must be finite and >= 1");
    }
    if (!finiteIn(sensor.read_noise_e, 0.0, 1e9)) {
        return Status(StatusCode::kInvalidArgument, "sensor.read_noise_e: must be finite and >= 0");
    }
    if (!finiteIn(sensor.vignetting, 0.0, 1.0)) {
        return Status(StatusCode::kInvalidArgument, "sensor.vignetting: must be in 0..1");
    }
    if (!finiteIn(sensor.dark_offset_dn, 0.0, 65535.0)) {
        return Status(StatusCode::kInvalidArgument, "sensor.dark_offset_dn: must be finite and >= 0");
    }
    return Status::ok();
}

}  // namespace vtm::sim

namespace vtm::sim::detail {

SensorConstants makeSensorConstants(const SensorParams& sensor, std::int32_t width_px,
                                    std::int32_t height_px) noexcept {
    SensorConstants k;
    k.exposure_s = sensor.exposure_s;
    k.gain_dn_per_e = sensor.gain_dn_per_e;
    k.full_well_e = sensor.full_well_e;
    k.read_sigma_dn = sensor.read_noise_e * sensor.gain_dn_per_e;
    k.dark_offset_dn = sensor.dark_offset_dn;
    k.max_dn = sensor.bit_depth == 12 ? 4095.0 : 255.0;
    k.vignetting = sensor.vignetting;
    k.centre_x_px = 0.5 * static_cast<double>(width_px - 1);
    k.centre_y_px = 0.5 * static_cast<double>(height_px - 1);
    const double corner_r2 = k.centre_x_px * k.centre_x_px + k.centre_y_px * k.centre_y_px;
    k.inv_corner_r2_px2 = corner_r2 > 0.0 ? 1.0 / corner_r2 : 0.0;
    k.shot_noise = sensor.shot_noise;
    return k;
}

double vignettingFactor(const SensorConstants& k, std::int32_t x, std::int32_t y) noexcept {
    const double dx = static_cast<double>(x) - k.centre_x_px;
    const double dy = static_cast<double>(y) - k.centre_y_px;
    const double rho2 = (dx * dx + dy * dy) * k.inv_corner_r2_px2;
    return 1.0 - k.vignetting * rho2;
}

std::uint16_t digitalNumber(const SensorConstants& k, double mean_electrons, Random& rng,
                            bool& saturated) noexcept {
    double electrons = mean_electrons > 0.0 ? mean_electrons : 0.0;
    if (k.shot_noise && electrons > 0.0) {
        // Poisson(e) ~ N(e, e): good to a few percent in variance from ~10 e- up, and
        // exact in mean and variance, which is what the noise tests and stereo care about.
        const double shot = rng.normal();
        electrons += math::sqrt(electrons) * shot;
    }
    electrons = electrons < 0.0 ? 0.0 : electrons;
    bool full = false;
    if (electrons >= k.full_well_e) {
        electrons = k.full_well_e;
        full = true;
    }
    double dn = k.dark_offset_dn + k.gain_dn_per_e * electrons;
    if (k.read_sigma_dn > 0.0) {
        const double read = rng.normal();
        dn += k.read_sigma_dn * read;
    }
    dn = std::floor(dn + 0.5);
    dn = dn < 0.0 ? 0.0 : dn;
    if (dn >= k.max_dn) {
        dn = k.max_dn;
        full = true;
    }
    saturated = full;
    return static_cast<std::uint16_t>(dn);
}

std::uint64_t rowNoiseSeed(std::uint64_t noise_seed, std::uint32_t frame_index, std::int32_t row) noexcept {
    std::uint64_t state = noise_seed;
    std::uint64_t mixed = splitMix64(state);
    state = mixed ^ (static_cast<std::uint64_t>(frame_index) * 0xD1B54A32D192ED03ULL);
    mixed = splitMix64(state);
    state = mixed ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(row)) * 0xAEF17502108EF2D9ULL);
    return splitMix64(state);
}

}  // namespace vtm::sim::detail
