// Camera renderer of the simulated world (docs/sim-render.md): ray-casts a Terrain through
// any vtm::CameraModel (pinhole + Brown, CAHV, CAHVOR) from any pose, shades it
// (Lambertian sun + sky, optional cast shadows, procedural albedo at the pixel's
// footprint), runs the result through a sensor model (vignetting, shot and read noise,
// gain, offset, clipping, 8 or 12 bit) and, on request, writes per-pixel ground truth
// (range, depth, 3-D point, normal) and the true disparity of a rectified pair.
//
// Frames: site frame x north, y east, z DOWN (metres; elevation = -z). The camera
// reference frame is the frame of the CameraModel (camera_model.hpp): the optical frame
// for a pinhole, the frame C/A/H/V are expressed in for CAHV(OR). A vtm::RigidPose
// site_from_cam (vtm/core/pose.hpp) places that frame in the site: p_site = R p_ref + t_m.
//
// Determinism: same inputs => same output bytes on every target (vtm::math only, one
// random draw per statement, noise generator seeded per (noise_seed, frame_index, row) so
// that any row band renders the same bytes alone as inside the whole frame).
// No heap: everything goes into caller views.
#pragma once

#include <cstdint>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"

namespace vtm::sim {

class Terrain;  // sim/terrain.hpp

// Largest frame the renderer accepts (width and height, pixels).
constexpr std::int32_t kMaxRenderSizePx = 2048;

// Pose of a pinhole's optical frame (+z along the view direction, +x to the image right,
// +y image down) at eye_site_m looking at target_site_m, with the image rows horizontal
// (no roll: +x is perpendicular to the site's up axis -z). A view straight up or down
// (no horizontal component) gets +x = site east (y) instead.
[[nodiscard]] RigidPose poseLookingAt(const Vec3& eye_site_m, const Vec3& target_site_m) noexcept;

// Illumination. Radiometric unit: "electron rate" (e-/s). A Lambertian surface of albedo
// a facing the sun, not shadowed, seen at the image centre, yields
// a / pi * (sun_irradiance + sky_irradiance) photo-electrons per second of exposure.
// The defaults put albedo 0.25 facing the sun at ~10700 e- with the default sensor
// (0.01 s): ~107 DN of 255 at 0.01 DN/e-.
struct Lighting {
    Vec3 to_sun_site = Vec3(-0.5, 0.0, -0.8660254037844386);  // unit vector towards the sun (z down: sun up => z < 0)
    double sun_irradiance = 1.2e7;     // e-/s on a surface facing the sun (>= 0)
    double sky_irradiance = 1.5e6;     // e-/s, diffuse sky/ambient term, direction-independent (>= 0)
    bool shadows = true;               // cast shadows: one shadow ray per lit pixel towards the sun
    double sky_radiance = 1.0e6;       // e-/s of a sky pixel at the horizon; the zenith is kZenithSkyFactor of it
};
// The sky is a smooth gradient: radiance(up) = sky_radiance * (1 - (1 - kZenithSkyFactor) * max(0, up)),
// up = -(ray direction).z in the site frame (0 at the horizon, 1 at the zenith).
constexpr double kZenithSkyFactor = 0.55;

// Sensor model (docs/sim-render.md):
//   electrons = radiance * exposure_s * V(x, y)       V = 1 - vignetting * rho^2,
//       rho = distance from the image centre / distance from the centre to a corner
//       (so a corner pixel receives (1 - vignetting) of the centre's light)
//   electrons += N(0, electrons) if shot_noise, clipped to [0, full_well_e]
//   DN = round(dark_offset_dn + gain_dn_per_e * electrons + N(0, read_noise_e * gain_dn_per_e)),
//       clipped to [0, 2^bit_depth - 1].
struct SensorParams {
    std::int32_t bit_depth = 8;        // 8 (out8) or 12 (out16, values 0..4095)
    double exposure_s = 0.01;          // > 0
    double gain_dn_per_e = 0.01;       // > 0
    double full_well_e = 30000.0;      // > 0
    double read_noise_e = 10.0;        // >= 0 (0: none)
    bool shot_noise = true;            // Poisson photon noise (normal approximation)
    double vignetting = 0.2;           // 0 .. 1
    double dark_offset_dn = 4.0;       // >= 0
    std::uint64_t noise_seed = 1U;
};

// Checks every field of the lighting and the sensor (finite, in the ranges above,
// to_sun_site of unit length within 1e-6); the reason names the field.
[[nodiscard]] Status validateLighting(const Lighting& lighting) noexcept;
[[nodiscard]] Status validateSensorParams(const SensorParams& sensor) noexcept;

// Per-pixel ground truth. Every view is optional (an empty view = not wanted); a given
// view must have the frame's height and width (x3 for the vector views). Sky pixels
// (no terrain along the ray) get NaN everywhere.
struct FrameTruth {
    ImageView<float> range_m;       // |hit - projection centre|, metres
    ImageView<float> depth_m;       // (hit - projection centre) . optical axis (pinhole +z, CAHV(OR) A), metres
    ImageView<float> point_site_m;  // width*3 floats per row: hit point x, y, z in the site frame
    ImageView<float> normal_site;   // width*3 floats per row: unit geometric normal (site frame, pointing up: z < 0)
};

// What one renderFrame() call produced.
struct RenderStats {
    std::int64_t hit_pixels = 0;        // rays that hit the terrain
    std::int64_t sky_pixels = 0;        // rays that did not
    std::int64_t shadowed_pixels = 0;   // hits facing the sun whose shadow ray was blocked
    std::int64_t saturated_pixels = 0;  // DN at the top code (full well or ADC limit)
    std::int64_t bad_ray_pixels = 0;    // pixels whose back-projection failed (rendered as black, NaN truth)
};

// One frame to render. Rows [first_row, first_row + row_count) are rendered (row_count
// < 0: to the last row); the result of a band is byte-identical to the same rows of a
// full render. Output views always have the full frame size.
struct FrameRequest {
    const Terrain* terrain = nullptr;
    CameraModel model;               // validated; width/height give the frame size (1..kMaxRenderSizePx)
    RigidPose pose;                  // site_from_cam: the camera reference frame in the site frame
    Lighting lighting;
    SensorParams sensor;
    std::uint32_t frame_index = 0U;  // enters the noise seed: consecutive frames get fresh noise
    std::int32_t first_row = 0;
    std::int32_t row_count = -1;
    double max_range_m = 1.0e5;      // rays find no terrain beyond this (sky), > 0
};

// Rows a request renders: row_count, or from first_row to the last row when it is < 0.
[[nodiscard]] inline std::int32_t bandRows(const FrameRequest& request) noexcept {
    return request.row_count < 0 ? request.model.height_px - request.first_row : request.row_count;
}

struct FrameOutput {
    ImageView<std::uint8_t> image8;    // bit_depth 8: frame size; may be empty otherwise
    ImageView<std::uint16_t> image16;  // bit_depth 12: frame size; may be empty otherwise
    FrameTruth truth;
};

// Renders one frame (or a band of it). Failures (nothing written): kInvalidArgument for
// a null terrain, an invalid model/lighting/sensor, a size over kMaxRenderSizePx or a
// bad band; kSizeMismatch for an output view of the wrong size. stats may be null.
[[nodiscard]] Status renderFrame(const FrameRequest& request, const FrameOutput& out,
                                 RenderStats* stats) noexcept;

// True disparity of a rectified pair: two identical undistorted pinholes (kPinholeBrown
// with k1 = k2 = k3 = p1 = p2 = 0), the right one displaced by baseline_m along the left
// optical frame's +x, same orientation. Left-image convention:
//   disparity_px(x, y) = x_left - x_right = fx * baseline_m / depth_m  (> 0 for points in front),
// so the matching right pixel is (x - d, y).
enum class DisparityTruthCode : std::uint8_t {
    kVisible = 0,    // the point is seen by both cameras
    kOccluded = 1,   // hidden from the right camera by other terrain (disparity still given)
    kOutOfView = 2,  // projects outside the right image (disparity still given)
    kNoHit = 3,      // sky: disparity NaN
};

struct StereoTruthRequest {
    const Terrain* terrain = nullptr;
    CameraModel left_model;      // undistorted pinhole, the rectified model of both cameras
    RigidPose left_pose;         // site_from_left: left optical frame in the site frame
    double baseline_m = 0.0;     // > 0
    double max_range_m = 1.0e5;  // > 0
};

struct StereoTruthOutput {
    ImageView<float> disparity_px;      // left image size; NaN where no hit
    ImageView<std::uint8_t> code;       // left image size (DisparityTruthCode), may be empty
    ImageView<float> left_depth_m;      // optional: left depth (as FrameTruth::depth_m)
};

// Visibility in the right camera is decided by a ray from the right projection centre to
// the left hit point (exact at depth edges, needs no right-image depth map): occluded if
// the terrain is hit more than max(1 mm, 1e-4 * distance) before the point.
// Failures: kInvalidArgument (null terrain, model not an undistorted pinhole, baseline <= 0),
// kSizeMismatch (views).
[[nodiscard]] Status rectifiedDisparity(const StereoTruthRequest& request, const StereoTruthOutput& out) noexcept;

// site_from_right of that pair (R the same, t_m + R * (baseline_m, 0, 0)).
[[nodiscard]] RigidPose rightPoseOfRectifiedPair(const RigidPose& site_from_left, double baseline_m) noexcept;

}  // namespace vtm::sim
