// Camera renderer: ray casting through a CameraModel, Lambertian shading with sun, sky
// and cast shadows, the sensor model and per-pixel ground truth (docs/sim-render.md).
#include "sim/render.hpp"

#include <cmath>
#include <limits>

#include "sensor_model.hpp"
#include "sim/render_cache.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {

namespace {

using detail::kNoHitF;

constexpr double kInvPi = 1.0 / math::kPi;
// The footprint never grows beyond 10x the perpendicular footprint (grazing views).
constexpr double kMinFootprintCos = 0.1;

bool finite3(const Vec3& v) noexcept {
    return math::isFinite(v.x()) && math::isFinite(v.y()) && math::isFinite(v.z());
}

Status validatePose(const RigidPose& pose) noexcept {
    for (int c = 0; c < 3; ++c) {
        if (!finite3(pose.R.col(c))) {
            return Status(StatusCode::kInvalidArgument, "pose.R: not finite");
        }
    }
    if (!finite3(pose.t_m)) {
        return Status(StatusCode::kInvalidArgument, "pose.t_m: not finite");
    }
    const Mat3 e = pose.R.transpose() * pose.R - Mat3::Identity();
    if (e.cwiseAbs().maxCoeff() > 1e-6 || pose.R.determinant() < 0.0) {
        return Status(StatusCode::kInvalidArgument, "pose.R: not a rotation (1e-6)");
    }
    return Status::ok();
}

// A view is either absent (no data) or exactly width x height.
Status checkOptionalView(const ImageView<float>& v, std::int32_t width, std::int32_t height,
                         const char* reason) noexcept {
    if (v.data() == nullptr) {
        return Status::ok();
    }
    if (!v.valid() || !v.sameSize(width, height)) {
        return Status(StatusCode::kSizeMismatch, reason, v.width());
    }
    return Status::ok();
}

Status validateOutput(const FrameRequest& r, const FrameOutput& out) noexcept {
    const std::int32_t w = r.model.width_px;
    const std::int32_t h = r.model.height_px;
    if (r.sensor.bit_depth == 8 && (!out.image8.valid() || !out.image8.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "out.image8: must be the frame size (bit_depth 8)",
                      out.image8.width());
    }
    if (r.sensor.bit_depth == 12 && (!out.image16.valid() || !out.image16.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "out.image16: must be the frame size (bit_depth 12)",
                      out.image16.width());
    }
    VTM_RETURN_IF_ERROR(checkOptionalView(out.truth.range_m, w, h, "truth.range_m: must be the frame size"));
    VTM_RETURN_IF_ERROR(checkOptionalView(out.truth.depth_m, w, h, "truth.depth_m: must be the frame size"));
    VTM_RETURN_IF_ERROR(checkOptionalView(out.truth.point_site_m, 3 * w, h,
                                          "truth.point_site_m: must be 3*width x height"));
    return checkOptionalView(out.truth.normal_site, 3 * w, h, "truth.normal_site: must be 3*width x height");
}

Status validateRequest(const FrameRequest& r, const FrameOutput& out) noexcept {
    if (r.terrain == nullptr || !r.terrain->built()) {
        return Status(StatusCode::kInvalidArgument, "request.terrain: null or not built");
    }
    VTM_RETURN_IF_ERROR(validateCameraModel(r.model));
    if (r.model.width_px > kMaxRenderSizePx || r.model.height_px > kMaxRenderSizePx) {
        return Status(StatusCode::kInvalidArgument, "model: width_px/height_px above kMaxRenderSizePx (2048)",
                      r.model.width_px > r.model.height_px ? r.model.width_px : r.model.height_px);
    }
    VTM_RETURN_IF_ERROR(validatePose(r.pose));
    VTM_RETURN_IF_ERROR(validateLighting(r.lighting));
    VTM_RETURN_IF_ERROR(validateSensorParams(r.sensor));
    if (!(r.max_range_m > 0.0) || !math::isFinite(r.max_range_m)) {
        return Status(StatusCode::kInvalidArgument, "request.max_range_m: must be finite and > 0");
    }
    const std::int32_t h = r.model.height_px;
    const std::int32_t count = bandRows(r);
    if (r.first_row < 0 || r.first_row >= h || count > h - r.first_row) {
        return Status(StatusCode::kInvalidArgument, "request.first_row/row_count: band outside the frame",
                      r.first_row);
    }
    return validateOutput(r, out);
}

// Everything per frame that the pixel loop needs.
struct FrameSetup {
    const Terrain* terrain = nullptr;
    const CameraModel* model = nullptr;
    Mat3 R = Mat3::Identity();
    Vec3 t = Vec3::Zero();
    Vec3 axis_ref = Vec3::UnitZ();   // optical axis in the reference frame (depth direction)
    const Lighting* light = nullptr;
    detail::SensorConstants sensor;
    double max_range_m = 0.0;
    std::uint64_t noise_seed = 0U;
    std::uint32_t frame_index = 0U;
};

// Radiance (e-/s) of the sky in the site direction dir: brightest at the horizon.
double skyRadiance(const Lighting& light, const Vec3& dir_site) noexcept {
    const double up = -dir_site.z();
    const double upClamped = up > 0.0 ? up : 0.0;
    return light.sky_radiance * (1.0 - (1.0 - kZenithSkyFactor) * upClamped);
}

struct Shading {
    double radiance = 0.0;  // e-/s
    bool shadowed = false;
};

// Lambertian radiance of a terrain hit seen along dir_site; pixel_angle_rad is the
// angular size of the pixel (sets the texture and normal scale).
Shading shadeHit(const FrameSetup& f, const TerrainHit& hit, const Vec3& dir_site, double pixel_angle_rad) noexcept {
    const double cos_view_raw = -dir_site.dot(hit.normal_site);
    const double cos_view = cos_view_raw > kMinFootprintCos ? cos_view_raw : kMinFootprintCos;
    const double footprint_m = hit.t_m * pixel_angle_rad / cos_view;
    const double north = hit.point_site_m.x();
    const double east = hit.point_site_m.y();
    const double albedo = f.terrain->albedoAt(north, east, footprint_m);
    const Vec3 n = f.terrain->shadingNormal(north, east, footprint_m);
    const Vec3& s = f.light->to_sun_site;
    const double cos_sun = n.dot(s);
    Shading out;
    double direct = 0.0;
    if (cos_sun > 0.0 && hit.normal_site.dot(s) > 0.0) {
        direct = cos_sun;
        if (f.light->shadows) {
            // Start the shadow ray just above the surface so it cannot find its own start.
            const double lift_m = 1e-3 + 1e-5 * hit.t_m;
            const Vec3 origin = hit.point_site_m + hit.normal_site * lift_m;
            const TerrainHit blocker = f.terrain->intersect(origin, s, f.max_range_m);
            if (blocker.hit) {
                direct = 0.0;
                out.shadowed = true;
            }
        }
    }
    out.radiance = albedo * kInvPi * (f.light->sun_irradiance * direct + f.light->sky_irradiance);
    return out;
}

void writeTruth(const FrameTruth& truth, std::int32_t x, std::int32_t y, const TerrainHit* hit,
                double depth_m) noexcept {
    const std::int32_t x3 = 3 * x;
    if (truth.range_m.data() != nullptr) {
        truth.range_m.row(y)[x] = hit != nullptr ? static_cast<float>(hit->t_m) : kNoHitF;
    }
    if (truth.depth_m.data() != nullptr) {
        truth.depth_m.row(y)[x] = hit != nullptr ? static_cast<float>(depth_m) : kNoHitF;
    }
    if (truth.point_site_m.data() != nullptr) {
        float* p = truth.point_site_m.row(y) + x3;
        for (int i = 0; i < 3; ++i) {
            p[i] = hit != nullptr ? static_cast<float>(hit->point_site_m(i)) : kNoHitF;
        }
    }
    if (truth.normal_site.data() != nullptr) {
        float* p = truth.normal_site.row(y) + x3;
        for (int i = 0; i < 3; ++i) {
            p[i] = hit != nullptr ? static_cast<float>(hit->normal_site(i)) : kNoHitF;
        }
    }
}

// Noise-free photo-electrons of pixel (x, y) along the reference-frame ray.
double pixelElectrons(const FrameSetup& f, const FrameOutput& out, std::int32_t x, std::int32_t y,
                      const CameraRay& ray, double pixel_angle_rad, RenderStats& stats) noexcept {
    const Vec3 origin_site = f.R * ray.origin_m + f.t;
    const Vec3 dir_site = f.R * ray.direction;
    const TerrainHit hit = f.terrain->intersect(origin_site, dir_site, f.max_range_m);
    double radiance = 0.0;
    if (hit.hit) {
        ++stats.hit_pixels;
        const Shading s = shadeHit(f, hit, dir_site, pixel_angle_rad);
        stats.shadowed_pixels += s.shadowed ? 1 : 0;
        radiance = s.radiance;
        writeTruth(out.truth, x, y, &hit, hit.t_m * ray.direction.dot(f.axis_ref));
    } else {
        ++stats.sky_pixels;
        radiance = skyRadiance(*f.light, dir_site);
        writeTruth(out.truth, x, y, nullptr, 0.0);
    }
    return radiance * f.sensor.exposure_s * detail::vignettingFactor(f.sensor, x, y);
}

void storeDn(const FrameOutput& out, bool twelve, std::int32_t x, std::int32_t y, std::uint16_t dn) noexcept {
    if (twelve) {
        out.image16.row(y)[x] = dn;
    } else {
        out.image8.row(y)[x] = static_cast<std::uint8_t>(dn);
    }
}

void renderRow(const FrameSetup& f, const FrameOutput& out, std::int32_t y, RenderStats& stats) noexcept {
    Random rng(detail::rowNoiseSeed(f.noise_seed, f.frame_index, y));
    const bool twelve = f.sensor.max_dn > 255.0;
    const double row_px = static_cast<double>(y);
    // The ray of the pixel to the left (x = -1 for the first) gives each pixel's angular
    // size as the chord between neighbouring unit rays.
    CameraRay previous;
    bool previous_ok = backProjectPixel(*f.model, Vec2(-1.0, row_px), previous).isOk();
    const std::int32_t width = f.model->width_px;
    for (std::int32_t x = 0; x < width; ++x) {
        CameraRay ray;
        const bool ok = backProjectPixel(*f.model, Vec2(static_cast<double>(x), row_px), ray).isOk();
        if (!ok) {
            ++stats.bad_ray_pixels;
            writeTruth(out.truth, x, y, nullptr, 0.0);
            storeDn(out, twelve, x, y, 0U);
            previous_ok = false;
            continue;
        }
        const double pixel_angle_rad = previous_ok ? (ray.direction - previous.direction).norm() : 0.0;
        const double electrons = pixelElectrons(f, out, x, y, ray, pixel_angle_rad, stats);
        bool saturated = false;
        const std::uint16_t dn = detail::digitalNumber(f.sensor, electrons, rng, saturated);
        stats.saturated_pixels += saturated ? 1 : 0;
        storeDn(out, twelve, x, y, dn);
        previous = ray;
        previous_ok = true;
    }
}

Vec3 opticalAxis(const CameraModel& model) noexcept {
    if (model.kind == CameraModelKind::kPinholeBrown) {
        return Vec3::UnitZ();
    }
    return Vec3(model.a[0], model.a[1], model.a[2]);
}

}  // namespace

Status validateLighting(const Lighting& lighting) noexcept {
    const Vec3& s = lighting.to_sun_site;
    if (!finite3(s) || std::fabs(s.norm() - 1.0) > 1e-6) {
        return Status(StatusCode::kInvalidArgument, "lighting.to_sun_site: must be a finite unit vector (1e-6)");
    }
    if (!math::isFinite(lighting.sun_irradiance) || lighting.sun_irradiance < 0.0) {
        return Status(StatusCode::kInvalidArgument, "lighting.sun_irradiance: must be finite and >= 0");
    }
    if (!math::isFinite(lighting.sky_irradiance) || lighting.sky_irradiance < 0.0) {
        return Status(StatusCode::kInvalidArgument, "lighting.sky_irradiance: must be finite and >= 0");
    }
    if (!math::isFinite(lighting.sky_radiance) || lighting.sky_radiance < 0.0) {
        return Status(StatusCode::kInvalidArgument, "lighting.sky_radiance: must be finite and >= 0");
    }
    return Status::ok();
}

RigidPose poseLookingAt(const Vec3& eye_site_m, const Vec3& target_site_m) noexcept {
    RigidPose site_from_cam;
    site_from_cam.t_m = eye_site_m;
    const Vec3 view = target_site_m - eye_site_m;
    const double n = view.norm();
    VTM_ASSERT(n > 0.0);
    const Vec3 z = n > 0.0 ? Vec3(view / n) : Vec3(Vec3::UnitX());
    const Vec3 down = Vec3::UnitZ();
    Vec3 x = down.cross(z);
    const double xn = x.norm();
    // Straight up or down: the image x axis points east.
    x = xn > 1e-12 ? Vec3(x / xn) : Vec3(Vec3::UnitY());
    const Vec3 y = z.cross(x);
    site_from_cam.R.col(0) = x;
    site_from_cam.R.col(1) = y;
    site_from_cam.R.col(2) = z;
    return site_from_cam;
}

Status renderFrame(const FrameRequest& request, const FrameOutput& out, RenderStats* stats) noexcept {
    VTM_RETURN_IF_ERROR(validateRequest(request, out));
    RenderCache* const cache = renderCache();
    const std::uint64_t key = cache != nullptr ? frameKey(request, out) : 0U;
    RenderStats cached;
    if (cache != nullptr && cache->load(key, request, out, cached)) {
        if (stats != nullptr) {
            *stats = cached;
        }
        return Status::ok();
    }
    FrameSetup f;
    f.terrain = request.terrain;
    f.model = &request.model;
    f.R = request.pose.R;
    f.t = request.pose.t_m;
    f.axis_ref = opticalAxis(request.model);
    f.light = &request.lighting;
    f.sensor = detail::makeSensorConstants(request.sensor, request.model.width_px, request.model.height_px);
    f.max_range_m = request.max_range_m;
    f.noise_seed = request.sensor.noise_seed;
    f.frame_index = request.frame_index;
    const std::int32_t end = request.first_row + bandRows(request);
    RenderStats local;
    for (std::int32_t y = request.first_row; y < end; ++y) {
        renderRow(f, out, y, local);
    }
    if (cache != nullptr) {
        cache->store(key, request, out, local);
    }
    if (stats != nullptr) {
        *stats = local;
    }
    return Status::ok();
}

}  // namespace vtm::sim
