// Orbital view: nadir orthographic rendering of the terrain in a visible or a thermal-like
// modality, with its own sun and cast shadows (sim/orbital.hpp, docs/sim-render.md).
#include "sim/orbital.hpp"

#include <cmath>

#include "sensor_model.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {

namespace {

using detail::finiteIn;

// Mixed into the row noise seed in place of a frame index, so an orbital image and a
// camera frame with the same noise_seed draw different noise.
constexpr std::uint32_t kOrbitalNoiseStream = 0x4F524249U;  // "ORBI"

Status invalid(const char* reason) noexcept { return Status(StatusCode::kInvalidArgument, reason); }

Status validateThermal(const ThermalParams& t) noexcept {
    if (!finiteIn(t.floor_k, 1.0, 5000.0)) {
        return invalid("orbital.thermal.floor_k: must be in 1 .. 5000 K");
    }
    if (!finiteIn(t.subsolar_k, t.floor_k, 5000.0) || !(t.subsolar_k > t.floor_k)) {
        return invalid("orbital.thermal.subsolar_k: must exceed floor_k and be <= 5000 K");
    }
    if (!finiteIn(t.scale_min_k, 0.0, 5000.0)) {
        return invalid("orbital.thermal.scale_min_k: must be in 0 .. 5000 K");
    }
    if (!finiteIn(t.scale_max_k, t.scale_min_k, 5000.0) || !(t.scale_max_k > t.scale_min_k)) {
        return invalid("orbital.thermal.scale_max_k: must exceed scale_min_k and be <= 5000 K");
    }
    return Status::ok();
}

Status validateGrid(const OrbitalParams& p) noexcept {
    if (!finiteIn(p.centre_north_m, -1e7, 1e7) || !finiteIn(p.centre_east_m, -1e7, 1e7)) {
        return invalid("orbital.centre_north_m/centre_east_m: must be finite, |v| <= 1e7");
    }
    if (!finiteIn(p.cell_m, 1e-3, 1e3)) {
        return invalid("orbital.cell_m: must be in 1e-3 .. 1e3 m");
    }
    if (p.width_px < 1 || p.width_px > kMaxOrbitalSizePx) {
        return Status(StatusCode::kInvalidArgument, "orbital.width_px: must be in 1 .. 4096", p.width_px);
    }
    if (p.height_px < 1 || p.height_px > kMaxOrbitalSizePx) {
        return Status(StatusCode::kInvalidArgument, "orbital.height_px: must be in 1 .. 4096", p.height_px);
    }
    if (p.subsamples < 1 || p.subsamples > kMaxOrbitalSubsamples) {
        return Status(StatusCode::kInvalidArgument, "orbital.subsamples: must be in 1 .. 4", p.subsamples);
    }
    const std::int32_t count = p.row_count < 0 ? p.height_px - p.first_row : p.row_count;
    if (p.first_row < 0 || p.first_row >= p.height_px || count > p.height_px - p.first_row) {
        return Status(StatusCode::kInvalidArgument, "orbital.first_row/row_count: band outside the image",
                      p.first_row);
    }
    return Status::ok();
}

Status validateLight(const OrbitalParams& p) noexcept {
    const Vec3& s = p.to_sun_site;
    const bool finite = math::isFinite(s.x()) && math::isFinite(s.y()) && math::isFinite(s.z());
    if (!finite || std::fabs(s.norm() - 1.0) > 1e-6 || !(s.z() < 0.0)) {
        return invalid("orbital.to_sun_site: must be a unit vector (1e-6) above the horizon (z < 0)");
    }
    if (!finiteIn(p.max_shadow_range_m, 1e-3, 1e7)) {
        return invalid("orbital.max_shadow_range_m: must be in 1e-3 .. 1e7 m");
    }
    if (!finiteIn(p.ambient, 0.0, 10.0)) {
        return invalid("orbital.ambient: must be in 0 .. 10");
    }
    if (!finiteIn(p.full_scale_reflectance, 1e-6, 100.0)) {
        return invalid("orbital.full_scale_reflectance: must be in 1e-6 .. 100");
    }
    if (p.modality != OrbitalModality::kVisible && p.modality != OrbitalModality::kThermal) {
        return invalid("orbital.modality: must be kVisible or kThermal");
    }
    return validateThermal(p.thermal);
}

Status validateSensor(const OrbitalParams& p) noexcept {
    if (p.bit_depth != 8 && p.bit_depth != 16) {
        return Status(StatusCode::kInvalidArgument, "orbital.bit_depth: must be 8 or 16", p.bit_depth);
    }
    if (!finiteIn(p.offset_fs, 0.0, 1.0)) {
        return invalid("orbital.offset_fs: must be in 0 .. 1");
    }
    if (!finiteIn(p.noise_fs, 0.0, 1.0)) {
        return invalid("orbital.noise_fs: must be in 0 .. 1");
    }
    return Status::ok();
}

Status validateOutput(const OrbitalParams& p, const OrbitalOutput& out) noexcept {
    const std::int32_t w = p.width_px;
    const std::int32_t h = p.height_px;
    if (p.bit_depth == 8 && (!out.image8.valid() || !out.image8.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "out.image8: must be the orbital image size (bit_depth 8)",
                      out.image8.width());
    }
    if (p.bit_depth == 16 && (!out.image16.valid() || !out.image16.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "out.image16: must be the orbital image size (bit_depth 16)",
                      out.image16.width());
    }
    if (out.elevation_m.data() != nullptr && (!out.elevation_m.valid() || !out.elevation_m.sameSize(w, h))) {
        return Status(StatusCode::kSizeMismatch, "out.elevation_m: must be the orbital image size",
                      out.elevation_m.width());
    }
    return Status::ok();
}

// Everything per image the pixel loop needs.
struct OrbitalSetup {
    const Terrain* terrain = nullptr;
    const OrbitalParams* p = nullptr;
    OrbitalGeoreference geo;
    double sub_step_m = 0.0;       // distance between sub-samples (cell / s)
    double sub_origin_m = 0.0;     // offset of the first sub-sample from the pixel centre
    double floor4 = 0.0;           // T_floor^4
    double subsolar4 = 0.0;        // T_subsolar^4
    double max_dn = 255.0;
};

double fourth(double t) noexcept {
    const double t2 = t * t;
    return t2 * t2;
}

// Whether the sub-sample at (north, east) on the terrain sees the sun (1) or not (0).
double litFraction(const OrbitalSetup& f, double north, double east, double footprint_m,
                   OrbitalStats& stats) noexcept {
    if (!f.p->shadows) {
        return 1.0;
    }
    // Start just above the surface (vertically, by a small part of the footprint) so the
    // ray cannot find its own start; blockers within that height are sub-footprint relief.
    const double lift_m = 1e-3 + 1e-2 * footprint_m;
    const Vec3 origin(north, east, -(f.terrain->elevationAt(north, east) + lift_m));
    const TerrainHit blocker = f.terrain->intersect(origin, f.p->to_sun_site, f.p->max_shadow_range_m);
    if (blocker.hit) {
        ++stats.shadowed_subsamples;
        return 0.0;
    }
    return 1.0;
}

// Sub-sample contribution: visible signal s, or thermal T^4 (kelvin^4).
double subsampleValue(const OrbitalSetup& f, double north, double east, double footprint_m,
                      OrbitalStats& stats) noexcept {
    const double albedo = f.terrain->albedoAt(north, east, footprint_m);
    const Vec3 n = f.terrain->shadingNormal(north, east, footprint_m);
    const double cos_raw = n.dot(f.p->to_sun_site);
    const double cos_i = cos_raw > 0.0 ? cos_raw : 0.0;
    const double lit = cos_i > 0.0 ? litFraction(f, north, east, footprint_m, stats) : 0.0;
    if (f.p->modality == OrbitalModality::kThermal) {
        return f.floor4 + f.subsolar4 * (1.0 - albedo) * lit * cos_i;
    }
    return albedo * (lit * cos_i + f.p->ambient) / f.p->full_scale_reflectance;
}

// Noise-free signal s of pixel (col, row): the mean over its s x s sub-samples.
double pixelSignal(const OrbitalSetup& f, std::int32_t col, std::int32_t row, OrbitalStats& stats) noexcept {
    const Vec2 centre = orbitalSiteFromPixel(f.geo, static_cast<double>(col), static_cast<double>(row));
    const std::int32_t s = f.p->subsamples;
    double sum = 0.0;
    for (std::int32_t i = 0; i < s; ++i) {      // bound: subsamples <= 4 (rows of sub-samples, south)
        const double north = centre.x() - (f.sub_origin_m + f.sub_step_m * static_cast<double>(i));
        for (std::int32_t j = 0; j < s; ++j) {  // bound: subsamples <= 4 (east)
            const double east = centre.y() + f.sub_origin_m + f.sub_step_m * static_cast<double>(j);
            sum += subsampleValue(f, north, east, f.sub_step_m, stats);
        }
    }
    const double mean = sum / static_cast<double>(s * s);
    if (f.p->modality == OrbitalModality::kThermal) {
        const double t_b = math::sqrt(math::sqrt(mean));  // brightness temperature of the mean radiance
        const ThermalParams& t = f.p->thermal;
        return (t_b - t.scale_min_k) / (t.scale_max_k - t.scale_min_k);
    }
    return mean;
}

std::uint16_t quantise(const OrbitalSetup& f, double signal, Random& rng, OrbitalStats& stats) noexcept {
    double dn = f.max_dn * (f.p->offset_fs + signal);
    if (f.p->noise_fs > 0.0) {
        const double noise = rng.normal();
        dn += f.max_dn * f.p->noise_fs * noise;
    }
    dn = std::floor(dn + 0.5);
    if (dn <= 0.0 || dn >= f.max_dn) {
        ++stats.saturated_pixels;
    }
    dn = dn < 0.0 ? 0.0 : dn;
    dn = dn > f.max_dn ? f.max_dn : dn;
    return static_cast<std::uint16_t>(dn);
}

void renderRow(const OrbitalSetup& f, const OrbitalOutput& out, std::int32_t row, OrbitalStats& stats) noexcept {
    Random rng(detail::rowNoiseSeed(f.p->noise_seed, kOrbitalNoiseStream, row));
    const bool sixteen = f.p->bit_depth == 16;
    for (std::int32_t col = 0; col < f.p->width_px; ++col) {  // bound: width_px
        const double signal = pixelSignal(f, col, row, stats);
        const std::uint16_t dn = quantise(f, signal, rng, stats);
        if (sixteen) {
            out.image16.row(row)[col] = dn;
        } else {
            out.image8.row(row)[col] = static_cast<std::uint8_t>(dn);
        }
        if (out.elevation_m.data() != nullptr) {
            const Vec2 site = orbitalSiteFromPixel(f.geo, static_cast<double>(col), static_cast<double>(row));
            out.elevation_m.row(row)[col] = static_cast<float>(f.terrain->elevationAt(site.x(), site.y()));
        }
        ++stats.pixels;
    }
}

}  // namespace

Vec2 orbitalPixelFromSite(const OrbitalGeoreference& geo, double north_m, double east_m) noexcept {
    return Vec2((east_m - geo.east0_m) / geo.cell_m, (geo.north0_m - north_m) / geo.cell_m);
}

Vec2 orbitalSiteFromPixel(const OrbitalGeoreference& geo, double col_px, double row_px) noexcept {
    return Vec2(geo.north0_m - row_px * geo.cell_m, geo.east0_m + col_px * geo.cell_m);
}

OrbitalGeoreference orbitalGeoreference(const OrbitalParams& params) noexcept {
    OrbitalGeoreference geo;
    geo.cell_m = params.cell_m;
    geo.width_px = params.width_px;
    geo.height_px = params.height_px;
    geo.north0_m = params.centre_north_m + 0.5 * static_cast<double>(params.height_px - 1) * params.cell_m;
    geo.east0_m = params.centre_east_m - 0.5 * static_cast<double>(params.width_px - 1) * params.cell_m;
    return geo;
}

Status validateOrbitalParams(const OrbitalParams& params) noexcept {
    VTM_RETURN_IF_ERROR(validateGrid(params));
    VTM_RETURN_IF_ERROR(validateLight(params));
    return validateSensor(params);
}

Status renderOrbital(const Terrain& terrain, const OrbitalParams& params, const OrbitalOutput& out,
                     OrbitalStats* stats) noexcept {
    if (!terrain.built()) {
        return invalid("orbital: terrain not built");
    }
    VTM_RETURN_IF_ERROR(validateOrbitalParams(params));
    VTM_RETURN_IF_ERROR(validateOutput(params, out));
    OrbitalSetup f;
    f.terrain = &terrain;
    f.p = &params;
    f.geo = orbitalGeoreference(params);
    f.sub_step_m = params.cell_m / static_cast<double>(params.subsamples);
    f.sub_origin_m = 0.5 * f.sub_step_m - 0.5 * params.cell_m;
    f.floor4 = fourth(params.thermal.floor_k);
    f.subsolar4 = fourth(params.thermal.subsolar_k);
    f.max_dn = params.bit_depth == 16 ? 65535.0 : 255.0;
    const std::int32_t end = params.row_count < 0 ? params.height_px : params.first_row + params.row_count;
    OrbitalStats local;
    for (std::int32_t row = params.first_row; row < end; ++row) {  // bound: height_px
        renderRow(f, out, row, local);
    }
    if (stats != nullptr) {
        *stats = local;
    }
    return Status::ok();
}

}  // namespace vtm::sim
