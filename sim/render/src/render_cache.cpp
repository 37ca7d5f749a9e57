// frameKey() and the process's render-cache hook (sim/render_cache.hpp).
#include "sim/render_cache.hpp"

#include <cstddef>

#include "sim/terrain.hpp"
#include "vtm/core/hasher.hpp"

namespace vtm::sim {

namespace {

// Every field below enters the key. A field added to one of these structs must be added
// here too, or two different frames would share a key: on x86-64 the sizes are checked.
#if defined(__x86_64__)
static_assert(sizeof(TerrainParams) == 304, "TerrainParams changed: update addTerrain() in render_cache.cpp");
static_assert(sizeof(CameraModel) == 224, "CameraModel changed: update addModel() in render_cache.cpp");
static_assert(sizeof(Lighting) == 56, "Lighting changed: update addLighting() in render_cache.cpp");
static_assert(sizeof(SensorParams) == 72, "SensorParams changed: update addSensor() in render_cache.cpp");
static_assert(sizeof(FrameRequest) == 480, "FrameRequest changed: update frameKey() in render_cache.cpp");
#endif

// Version of the cached bytes: raise it when the renderer's output changes for equal
// inputs, so that no cache written by another renderer is read.
constexpr std::uint64_t kRendererVersion = 1U;

template <std::size_t N>
void addDoubles(Hasher& h, const double (&v)[N]) noexcept {
    for (const double x : v) {  // bound: N
        h.addDouble(x);
    }
}

void addTerrain(Hasher& h, const TerrainParams& p) noexcept {
    h.addU64(p.seed);
    h.addU64(static_cast<std::uint64_t>(p.kind));
    const double grid[] = {p.centre_north_m, p.centre_east_m, p.finest_cell_m};
    addDoubles(h, grid);
    h.addI64(p.samples_log2);
    h.addI64(p.levels);
    const double shape[] = {p.base_elevation_m,    p.plane_slope_north,  p.plane_slope_east,
                            p.dome_centre_north_m, p.dome_centre_east_m, p.dome_radius_m,
                            p.relief_amplitude_m,  p.relief_longest_wavelength_m, p.relief_hurst};
    addDoubles(h, shape);
    const double craters_rocks[] = {p.crater_density_per_km2, p.crater_sfd_slope,     p.crater_min_diameter_m,
                                    p.crater_max_diameter_m,  p.crater_depth_ratio,   p.crater_rim_ratio,
                                    p.rock_k,                 p.rock_min_diameter_m,  p.rock_max_diameter_m,
                                    p.rock_height_ratio,      p.rock_region_radius_m};
    addDoubles(h, craters_rocks);
    const double hills_albedo[] = {p.hills_start_m,      p.hills_full_m,          p.hills_amplitude_m,
                                   p.hills_wavelength_m, p.albedo_mean,           p.albedo_variation,
                                   p.albedo_wavelength_m, p.rock_albedo_mean,     p.rock_albedo_spread,
                                   p.texture_contrast,   p.texture_longest_wavelength_m,
                                   p.texture_finest_wavelength_m};
    addDoubles(h, hills_albedo);
}

void addModel(Hasher& h, const CameraModel& m) noexcept {
    h.addU64(static_cast<std::uint64_t>(m.kind));
    h.addU64(m.width_px);
    h.addU64(m.height_px);
    const double pinhole[] = {m.fx_px, m.fy_px, m.cx_px, m.cy_px, m.k1, m.k2, m.k3, m.p1, m.p2};
    addDoubles(h, pinhole);
    addDoubles(h, m.c);
    addDoubles(h, m.a);
    addDoubles(h, m.h);
    addDoubles(h, m.v);
    addDoubles(h, m.o);
    addDoubles(h, m.r);
}

void addLighting(Hasher& h, const Lighting& l) noexcept {
    h.addMatrix(l.to_sun_site);
    h.addDouble(l.sun_irradiance);
    h.addDouble(l.sky_irradiance);
    h.addU64(l.shadows ? 1U : 0U);
    h.addDouble(l.sky_radiance);
}

void addSensor(Hasher& h, const SensorParams& s) noexcept {
    h.addI64(s.bit_depth);
    const double values[] = {s.exposure_s, s.gain_dn_per_e, s.full_well_e, s.read_noise_e};
    addDoubles(h, values);
    h.addU64(s.shot_noise ? 1U : 0U);
    h.addDouble(s.vignetting);
    h.addDouble(s.dark_offset_dn);
    h.addU64(s.noise_seed);
}

RenderCache* g_render_cache = nullptr;

}  // namespace

std::uint64_t frameKey(const FrameRequest& request, const FrameOutput& out) noexcept {
    Hasher h;
    h.addU64(kRendererVersion);
    if (request.terrain != nullptr) {
        addTerrain(h, request.terrain->params());
    }
    addModel(h, request.model);
    h.addPose(request.pose);
    addLighting(h, request.lighting);
    addSensor(h, request.sensor);
    h.addU64(request.frame_index);
    h.addI64(request.first_row);
    h.addI64(bandRows(request));
    h.addDouble(request.max_range_m);
    h.addU64(renderedViews(request, out));
    return h.value();
}

std::uint32_t renderedViews(const FrameRequest& request, const FrameOutput& out) noexcept {
    std::uint32_t mask = request.sensor.bit_depth == 12 ? kViewImage16 : 0U;
    mask |= out.truth.range_m.data() != nullptr ? kViewRange : 0U;
    mask |= out.truth.depth_m.data() != nullptr ? kViewDepth : 0U;
    mask |= out.truth.point_site_m.data() != nullptr ? kViewPoint : 0U;
    mask |= out.truth.normal_site.data() != nullptr ? kViewNormal : 0U;
    return mask;
}

void setRenderCache(RenderCache* cache) noexcept { g_render_cache = cache; }

RenderCache* renderCache() noexcept { return g_render_cache; }

}  // namespace vtm::sim
