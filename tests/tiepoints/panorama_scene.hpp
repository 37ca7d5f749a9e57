// A small rendered panorama for the tie-point tests and the determinism section: a rover
// mast (1.5 m over the ground) turning its 0.42 m stereo rig (tilt -30 deg) in azimuth by
// `turn_deg` between stations over a Mars terrain of the simulator. Everything goes into
// caller memory (no heap), so the determinism suite can use it too.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::test {

struct PanoramaSpec {
    std::int32_t width = 256, height = 256;
    double hfov_deg = 50.0;
    double turn_deg = 32.0;      // azimuth step between stations
    double tilt_deg = -30.0;     // below the horizon
    double mast_m = 1.5;         // camera height over the ground under the mast
    double baseline_m = 0.42;
    double first_azimuth_deg = -20.0;
    // Pointing error of the approximate poses: a rotation of spoil_rad about an axis and a
    // displacement of spoil_m, both varied per station (not random: fixed directions).
    double spoil_rad = 0.5 * math::kPi / 180.0;
    double spoil_m = 0.02;
    std::uint32_t terrain_seed = 11U;
};

inline sim::TerrainParams panoramaTerrainParams(const PanoramaSpec& spec) noexcept {
    sim::TerrainParams params = sim::defaultMarsTerrainParams();
    params.seed = spec.terrain_seed;
    params.finest_cell_m = 0.02;
    params.samples_log2 = 7;
    params.levels = 8;
    params.rock_region_radius_m = 12.0;
    return params;
}

// TRUE left and right poses of station k.
inline void truePoses(const PanoramaSpec& spec, const sim::Terrain& terrain, std::int32_t k, RigidPose& left,
                      RigidPose& right) noexcept {
    const double deg = math::kPi / 180.0;
    const double az = (spec.first_azimuth_deg + spec.turn_deg * static_cast<double>(k)) * deg;
    const double tilt = spec.tilt_deg * deg;
    const Vec3 side(-math::sin(az), math::cos(az), 0.0);  // the rig's right, level
    const Vec3 head(0.0, 0.0, -(terrain.elevationAt(0.0, 0.0) + spec.mast_m));
    const Vec3 view(math::cos(az) * math::cos(tilt), math::sin(az) * math::cos(tilt), -math::sin(tilt));
    const Vec3 l = head - 0.5 * spec.baseline_m * side;
    const Vec3 r = head + 0.5 * spec.baseline_m * side;
    left = sim::poseLookingAt(l, l + view);
    right = sim::poseLookingAt(r, r + view);
}

// The station as the tie points see it: the calibrated rig (true b_from_a) and the
// APPROXIMATE left pose (the true one spoiled by spec.spoil_rad / spoil_m).
inline NetworkStation approximateStation(const PanoramaSpec& spec, const CameraModel& model, const RigidPose& left,
                                         const RigidPose& right, std::int32_t k) noexcept {
    NetworkStation st;
    st.rig.model_a = model;
    st.rig.model_b = model;
    st.rig.b_from_a = relativePose(left, right);
    const double phase = 2.1 * static_cast<double>(k) + 0.7;
    const Vec3 axis = Vec3(math::cos(phase), math::sin(phase), 0.6).normalized();
    const Vec3 shift = Vec3(math::sin(phase), 0.5, math::cos(phase)).normalized();
    st.site_from_a.R = rotationExp(spec.spoil_rad * axis) * left.R;
    st.site_from_a.t_m = left.t_m + spec.spoil_m * shift;
    for (int d = 0; d < 3; ++d) {
        st.prior_covariance(d, d) = spec.spoil_rad * spec.spoil_rad;
        st.prior_covariance(d + 3, d + 3) = spec.spoil_m * spec.spoil_m;
    }
    return st;
}

// Renders one eye (frame_index distinct per image); range truth when range != nullptr.
inline Status renderEye(const PanoramaSpec& spec, const sim::Terrain& terrain, const CameraModel& model,
                        const RigidPose& pose, std::uint32_t frame_index, std::uint8_t* image, float* range) noexcept {
    sim::FrameRequest r;
    r.terrain = &terrain;
    r.model = model;
    r.pose = pose;
    r.frame_index = frame_index;
    sim::FrameOutput out;
    out.image8 = ImageView<std::uint8_t>(image, spec.width, spec.height);
    if (range != nullptr) {
        out.truth.range_m = ImageView<float>(range, spec.width, spec.height);
    }
    return sim::renderFrame(r, out, nullptr);
}

}  // namespace vtm::test
