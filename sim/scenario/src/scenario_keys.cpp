// The scenario key table (scenario_keys.hpp). Ranges are the documented ones
// (docs/sim-scenarios.md); TerrainParams::validate() and validateCameraModel() check the
// combinations of fields afterwards.
#include "scenario_keys.hpp"

namespace vtm::sim::detail {
namespace {

// One row. The reasons are string literals assembled at compile time so that each names
// its section.key (a Status reason must have static storage).
#define VTM_SCENARIO_KEY(sec, prefix, key, type, lo, hi, kinds, models, required, member)      \
    KeySpec {                                                                                  \
        Section::k##sec, key, ValueType::type, (lo), (hi), (kinds), (models), (required),      \
            [](Scenario& s) -> void* { return static_cast<void*>(&s.member); },                \
            "scenario: " prefix key " has a bad value (wrong count, not a number or unknown word)", \
            "scenario: " prefix key " is out of range " #lo " .. " #hi,                        \
            "scenario: " prefix key " given twice", "scenario: " prefix key " missing",         \
            "scenario: " prefix key " does not belong to this kind or camera model"             \
    }

constexpr KeySpec kKeys[] = {
    VTM_SCENARIO_KEY(Top, "", "name", kName, 0, 0, kAnyKind, kAnyModel, true, name[0]),
    VTM_SCENARIO_KEY(Top, "", "kind", kKind, 0, 0, kAnyKind, kAnyModel, true, kind),
    VTM_SCENARIO_KEY(Top, "", "seed", kUint64, 0, 0, kAnyKind, kAnyModel, true, seed),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "seed", kUint64, 0, 0, kAnyKind, kAnyModel, false, terrain.seed),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "kind", kTerrainKind, 0, 0, kAnyKind, kAnyModel, false, terrain.kind),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "centre_north_m", kDouble, -1e6, 1e6, kAnyKind, kAnyModel, false, terrain.centre_north_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "centre_east_m", kDouble, -1e6, 1e6, kAnyKind, kAnyModel, false, terrain.centre_east_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "finest_cell_m", kDouble, 1e-4, 100, kAnyKind, kAnyModel, false, terrain.finest_cell_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "samples_log2", kInt32, 3, 12, kAnyKind, kAnyModel, false, terrain.samples_log2),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "levels", kInt32, 1, 16, kAnyKind, kAnyModel, false, terrain.levels),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "base_elevation_m", kDouble, -1e4, 1e4, kAnyKind, kAnyModel, false, terrain.base_elevation_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "plane_slope_north", kDouble, -10, 10, kAnyKind, kAnyModel, false, terrain.plane_slope_north),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "plane_slope_east", kDouble, -10, 10, kAnyKind, kAnyModel, false, terrain.plane_slope_east),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "dome_centre_north_m", kDouble, -1e6, 1e6, kAnyKind, kAnyModel, false, terrain.dome_centre_north_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "dome_centre_east_m", kDouble, -1e6, 1e6, kAnyKind, kAnyModel, false, terrain.dome_centre_east_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "dome_radius_m", kDouble, 1e-3, 1e5, kAnyKind, kAnyModel, false, terrain.dome_radius_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "relief_amplitude_m", kDouble, 0, 1000, kAnyKind, kAnyModel, false, terrain.relief_amplitude_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "relief_longest_wavelength_m", kDouble, 1e-3, 1e6, kAnyKind, kAnyModel, false, terrain.relief_longest_wavelength_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "relief_hurst", kDouble, 0, 1, kAnyKind, kAnyModel, false, terrain.relief_hurst),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_density_per_km2", kDouble, 0, 1e7, kAnyKind, kAnyModel, false, terrain.crater_density_per_km2),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_sfd_slope", kDouble, 1, 4, kAnyKind, kAnyModel, false, terrain.crater_sfd_slope),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_min_diameter_m", kDouble, 1e-3, 1e5, kAnyKind, kAnyModel, false, terrain.crater_min_diameter_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_max_diameter_m", kDouble, 1e-3, 1e5, kAnyKind, kAnyModel, false, terrain.crater_max_diameter_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_depth_ratio", kDouble, 0, 0.5, kAnyKind, kAnyModel, false, terrain.crater_depth_ratio),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "crater_rim_ratio", kDouble, 0, 0.2, kAnyKind, kAnyModel, false, terrain.crater_rim_ratio),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_k", kDouble, 0, 0.5, kAnyKind, kAnyModel, false, terrain.rock_k),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_min_diameter_m", kDouble, 0.01, 3, kAnyKind, kAnyModel, false, terrain.rock_min_diameter_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_max_diameter_m", kDouble, 0.01, 3, kAnyKind, kAnyModel, false, terrain.rock_max_diameter_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_height_ratio", kDouble, 0.1, 1, kAnyKind, kAnyModel, false, terrain.rock_height_ratio),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_region_radius_m", kDouble, 0, 2000, kAnyKind, kAnyModel, false, terrain.rock_region_radius_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "hills_start_m", kDouble, 0, 1e6, kAnyKind, kAnyModel, false, terrain.hills_start_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "hills_full_m", kDouble, 0, 1e6, kAnyKind, kAnyModel, false, terrain.hills_full_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "hills_amplitude_m", kDouble, 0, 5000, kAnyKind, kAnyModel, false, terrain.hills_amplitude_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "hills_wavelength_m", kDouble, 1e-3, 1e6, kAnyKind, kAnyModel, false, terrain.hills_wavelength_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "albedo_mean", kDouble, 0, 1, kAnyKind, kAnyModel, false, terrain.albedo_mean),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "albedo_variation", kDouble, 0, 1, kAnyKind, kAnyModel, false, terrain.albedo_variation),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "albedo_wavelength_m", kDouble, 1e-3, 1e6, kAnyKind, kAnyModel, false, terrain.albedo_wavelength_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_albedo_mean", kDouble, 0, 1, kAnyKind, kAnyModel, false, terrain.rock_albedo_mean),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "rock_albedo_spread", kDouble, 0, 0.5, kAnyKind, kAnyModel, false, terrain.rock_albedo_spread),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "texture_contrast", kDouble, 0, 1, kAnyKind, kAnyModel, false, terrain.texture_contrast),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "texture_longest_wavelength_m", kDouble, 1e-4, 1e3, kAnyKind, kAnyModel, false, terrain.texture_longest_wavelength_m),
    VTM_SCENARIO_KEY(Terrain, "terrain.", "texture_finest_wavelength_m", kDouble, 1e-5, 1e3, kAnyKind, kAnyModel, false, terrain.texture_finest_wavelength_m),
    VTM_SCENARIO_KEY(Camera, "camera.", "model", kModel, 0, 0, kAnyKind, kAnyModel, true, camera.kind),
    VTM_SCENARIO_KEY(Camera, "camera.", "width_px", kUint16, 1, 2048, kAnyKind, kAnyModel, true, camera.width_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "height_px", kUint16, 1, 2048, kAnyKind, kAnyModel, true, camera.height_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "bit_depth", kInt32, 8, 12, kAnyKind, kAnyModel, false, sensor.bit_depth),
    VTM_SCENARIO_KEY(Camera, "camera.", "hfov_deg", kDouble, 1, 170, kAnyKind, kPinholeOnly, false, camera_hfov_deg),
    VTM_SCENARIO_KEY(Camera, "camera.", "fx_px", kDouble, 1e-3, 1e6, kAnyKind, kPinholeOnly, false, camera.fx_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "fy_px", kDouble, 1e-3, 1e6, kAnyKind, kPinholeOnly, false, camera.fy_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "cx_px", kDouble, -1e5, 1e5, kAnyKind, kPinholeOnly, false, camera.cx_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "cy_px", kDouble, -1e5, 1e5, kAnyKind, kPinholeOnly, false, camera.cy_px),
    VTM_SCENARIO_KEY(Camera, "camera.", "k1", kDouble, -10, 10, kAnyKind, kPinholeOnly, false, camera.k1),
    VTM_SCENARIO_KEY(Camera, "camera.", "k2", kDouble, -10, 10, kAnyKind, kPinholeOnly, false, camera.k2),
    VTM_SCENARIO_KEY(Camera, "camera.", "k3", kDouble, -10, 10, kAnyKind, kPinholeOnly, false, camera.k3),
    VTM_SCENARIO_KEY(Camera, "camera.", "p1", kDouble, -10, 10, kAnyKind, kPinholeOnly, false, camera.p1),
    VTM_SCENARIO_KEY(Camera, "camera.", "p2", kDouble, -10, 10, kAnyKind, kPinholeOnly, false, camera.p2),
    VTM_SCENARIO_KEY(Camera, "camera.", "c", kArray3, -1e6, 1e6, kAnyKind, kCahvModels, false, camera.c[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "a", kArray3, -1e6, 1e6, kAnyKind, kCahvModels, false, camera.a[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "h", kArray3, -1e6, 1e6, kAnyKind, kCahvModels, false, camera.h[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "v", kArray3, -1e6, 1e6, kAnyKind, kCahvModels, false, camera.v[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "o", kArray3, -1e6, 1e6, kAnyKind, kCahvorOnly, false, camera.o[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "r", kArray3, -1e6, 1e6, kAnyKind, kCahvorOnly, false, camera.r[0]),
    VTM_SCENARIO_KEY(Camera, "camera.", "mount_position_m", kVec3, -100, 100, kAnyKind, kAnyModel, false, mount.position_vehicle_m),
    VTM_SCENARIO_KEY(Camera, "camera.", "mount_pan_deg", kDouble, -180, 180, kMovingKinds, kAnyModel, false, mount.pan_deg),
    VTM_SCENARIO_KEY(Camera, "camera.", "mount_tilt_deg", kDouble, -90, 90, kMovingKinds, kAnyModel, false, mount.tilt_deg),
    VTM_SCENARIO_KEY(Camera, "camera.", "mount_roll_deg", kDouble, -180, 180, kMovingKinds, kAnyModel, false, mount.roll_deg),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "exposure_s", kDouble, 1e-6, 100, kAnyKind, kAnyModel, false, sensor.exposure_s),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "gain_dn_per_e", kDouble, 1e-6, 1e3, kAnyKind, kAnyModel, false, sensor.gain_dn_per_e),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "full_well_e", kDouble, 1, 1e7, kAnyKind, kAnyModel, false, sensor.full_well_e),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "read_noise_e", kDouble, 0, 1e4, kAnyKind, kAnyModel, false, sensor.read_noise_e),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "shot_noise", kBool, 0, 0, kAnyKind, kAnyModel, false, sensor.shot_noise),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "vignetting", kDouble, 0, 1, kAnyKind, kAnyModel, false, sensor.vignetting),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "dark_offset_dn", kDouble, 0, 4095, kAnyKind, kAnyModel, false, sensor.dark_offset_dn),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "noise_seed", kUint64, 0, 0, kAnyKind, kAnyModel, false, sensor.noise_seed),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "exposure_variation_percent", kDouble, 0, 50, kAnyKind, kAnyModel, false, variation.exposure_variation_percent),
    VTM_SCENARIO_KEY(Sensor, "sensor.", "gain_variation_percent", kDouble, 0, 50, kAnyKind, kAnyModel, false, variation.gain_variation_percent),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "sun_azimuth_deg", kDouble, 0, 360, kAnyKind, kAnyModel, false, sun_azimuth_deg),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "sun_elevation_deg", kDouble, 1, 90, kAnyKind, kAnyModel, false, sun_elevation_deg),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "sun_irradiance", kDouble, 0, 1e9, kAnyKind, kAnyModel, false, lighting.sun_irradiance),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "sky_irradiance", kDouble, 0, 1e9, kAnyKind, kAnyModel, false, lighting.sky_irradiance),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "sky_radiance", kDouble, 0, 1e9, kAnyKind, kAnyModel, false, lighting.sky_radiance),
    VTM_SCENARIO_KEY(Lighting, "lighting.", "shadows", kBool, 0, 0, kAnyKind, kAnyModel, false, lighting.shadows),
    VTM_SCENARIO_KEY(Motion, "motion.", "start_m", kVec2, -1e6, 1e6, kAnyKind, kAnyModel, false, motion.start_site_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "heading_deg", kDouble, -360, 360, kAnyKind, kAnyModel, false, motion.heading_deg),
    VTM_SCENARIO_KEY(Motion, "motion.", "start_time_s", kDouble, 0, 1e9, kAnyKind, kAnyModel, false, motion.start_time_s),
    VTM_SCENARIO_KEY(Motion, "motion.", "speed_m_per_s", kDouble, 1e-4, 1e3, kAnyKind, kAnyModel, false, motion.speed_m_per_s),
    VTM_SCENARIO_KEY(Motion, "motion.", "baseline_m", kDouble, 0.05, 100, kPairOnly, kAnyModel, false, motion.baseline_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "convergence_deg", kDouble, 0, 45, kPairOnly, kAnyModel, false, motion.convergence_deg),
    VTM_SCENARIO_KEY(Motion, "motion.", "stereo_baseline_m", kDouble, 0.01, 10, kPairOrPanorama, kAnyModel, false, motion.stereo_baseline_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "stereo_hfov_deg", kDouble, 1, 170, kPairOnly, kAnyModel, false, motion.stereo_hfov_deg),
    VTM_SCENARIO_KEY(Motion, "motion.", "start_altitude_m", kDouble, 1, 1e5, kDescentOnly, kAnyModel, false, motion.start_altitude_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "end_altitude_m", kDouble, 0.1, 1e5, kDescentOnly, kAnyModel, false, motion.end_altitude_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "frames", kInt32, 2, 32, kDescentOnly, kAnyModel, false, motion.frames),
    VTM_SCENARIO_KEY(Motion, "motion.", "drift_m", kVec2, -1e4, 1e4, kDescentOnly, kAnyModel, false, motion.drift_site_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "attitude_noise_deg", kDouble, 0, 10, kDescentOnly, kAnyModel, false, motion.attitude_noise_deg),
    VTM_SCENARIO_KEY(Motion, "motion.", "stops", kInt32, 2, 60, kTraverseOnly, kAnyModel, false, motion.stops),
    VTM_SCENARIO_KEY(Motion, "motion.", "step_m", kDouble, 0.01, 100, kTraverseOnly, kAnyModel, false, motion.step_m),
    VTM_SCENARIO_KEY(Motion, "motion.", "turn_deg_per_stop", kDouble, -90, 90, kTraverseOnly, kAnyModel, false, motion.turn_deg_per_stop),
    VTM_SCENARIO_KEY(Motion, "motion.", "columns", kInt32, 3, 32, kPanoramaOnly, kAnyModel, false, motion.columns),
    VTM_SCENARIO_KEY(Motion, "motion.", "tier_tilts_deg", kTierTilts, -90, 45, kPanoramaOnly, kAnyModel, false, motion.tiers),
    VTM_SCENARIO_KEY(Motion, "motion.", "station_interval_s", kDouble, 0, 3600, kPanoramaOnly, kAnyModel, false, motion.station_interval_s),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "pan_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.pan_sigma_deg),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "tilt_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.tilt_sigma_deg),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "mast_tilt_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.mast_tilt_sigma_deg),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "head_offset_sigma_m", kDouble, 0, 1, kPanoramaOnly, kAnyModel, false, pointing.head_offset_sigma_m),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "rover_roll_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.rover_roll_sigma_deg),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "rover_pitch_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.rover_pitch_sigma_deg),
    VTM_SCENARIO_KEY(Pointing, "pointing.", "rover_heading_sigma_deg", kDouble, 0, 10, kPanoramaOnly, kAnyModel, false, pointing.rover_heading_sigma_deg),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "scale_error_percent", kDouble, -50, 50, kMovingKinds, kAnyModel, false, odometry.scale_error_percent),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "scale_error_sigma_percent", kDouble, 0, 50, kMovingKinds, kAnyModel, false, odometry.scale_error_sigma_percent),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "heading_drift_deg_per_m", kDouble, -10, 10, kMovingKinds, kAnyModel, false, odometry.heading_drift_deg_per_m),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "heading_drift_sigma_deg_per_m", kDouble, 0, 10, kMovingKinds, kAnyModel, false, odometry.heading_drift_sigma_deg_per_m),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "tilt_drift_sigma_deg_per_m", kDouble, 0, 10, kMovingKinds, kAnyModel, false, odometry.tilt_drift_sigma_deg_per_m),
    VTM_SCENARIO_KEY(Odometry, "odometry.", "random_walk_m_per_sqrt_m", kDouble, 0, 10, kMovingKinds, kAnyModel, false, odometry.random_walk_m_per_sqrt_m),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "cell_m", kDouble, 0.01, 100, kDescentOnly, kAnyModel, false, orbital.cell_m),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "width_px", kInt32, 16, 4096, kDescentOnly, kAnyModel, false, orbital.width_px),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "height_px", kInt32, 16, 4096, kDescentOnly, kAnyModel, false, orbital.height_px),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "subsamples", kInt32, 1, 4, kDescentOnly, kAnyModel, false, orbital.subsamples),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "centre_offset_m", kVec2, -1e5, 1e5, kDescentOnly, kAnyModel, false, orbital.centre_offset_m),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "sun_azimuth_deg", kDouble, 0, 360, kDescentOnly, kAnyModel, false, orbital.sun_azimuth_deg),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "sun_elevation_deg", kDouble, 1, 90, kDescentOnly, kAnyModel, false, orbital.sun_elevation_deg),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "modality", kModality, 0, 0, kDescentOnly, kAnyModel, false, orbital.modality),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "bit_depth", kInt32, 8, 16, kDescentOnly, kAnyModel, false, orbital.bit_depth),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "shadows", kBool, 0, 0, kDescentOnly, kAnyModel, false, orbital.shadows),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "noise_fs", kDouble, 0, 0.5, kDescentOnly, kAnyModel, false, orbital.noise_fs),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "noise_seed", kUint64, 0, 0, kDescentOnly, kAnyModel, false, orbital.noise_seed),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "ambient", kDouble, 0, 10, kDescentOnly, kAnyModel, false, orbital.ambient),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "thermal_floor_k", kDouble, 1, 1000, kDescentOnly, kAnyModel, false, orbital.thermal_floor_k),
    VTM_SCENARIO_KEY(Orbital, "orbital.", "thermal_subsolar_k", kDouble, 1, 2000, kDescentOnly, kAnyModel, false, orbital.thermal_subsolar_k),
};

#undef VTM_SCENARIO_KEY

}  // namespace

const KeySpec* scenarioKeys(std::size_t& count) noexcept {
    count = sizeof(kKeys) / sizeof(kKeys[0]);
    return kKeys;
}

}  // namespace vtm::sim::detail
