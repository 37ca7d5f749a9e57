// The orbital image of a descent scenario (sim/scenario.hpp scenarioOrbitalParams).
#include "sim/orbital.hpp"
#include "sim/scenario.hpp"

namespace vtm::sim {

OrbitalParams scenarioOrbitalParams(const Scenario& scenario) noexcept {
    const OrbitalScenario& o = scenario.orbital;
    OrbitalParams p;
    p.centre_north_m = scenario.motion.start_site_m.x() + o.centre_offset_m.x();
    p.centre_east_m = scenario.motion.start_site_m.y() + o.centre_offset_m.y();
    p.cell_m = o.cell_m;
    p.width_px = o.width_px;
    p.height_px = o.height_px;
    p.subsamples = o.subsamples;
    p.to_sun_site = sunDirection(o.sun_azimuth_deg, o.sun_elevation_deg);
    p.shadows = o.shadows;
    p.modality = o.modality;
    p.ambient = o.ambient;
    p.thermal.floor_k = o.thermal_floor_k;
    p.thermal.subsolar_k = o.thermal_subsolar_k;
    // The display scale spans the model's range: 10 K under the floor (so noise on the
    // coldest ground is not clipped) up to the subsolar temperature.
    p.thermal.scale_min_k = o.thermal_floor_k - 10.0 > 0.0 ? o.thermal_floor_k - 10.0 : 0.0;
    p.thermal.scale_max_k = o.thermal_subsolar_k;
    p.bit_depth = o.bit_depth;
    p.noise_fs = o.noise_fs;
    p.noise_seed = o.noise_seed;
    return p;
}

}  // namespace vtm::sim
