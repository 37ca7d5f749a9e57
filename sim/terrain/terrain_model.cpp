#include "terrain_model.hpp"

#include <cmath>

#include "noise.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {
namespace model {

double power(double x, double y) noexcept { return vtm::math::exp(y * vtm::math::log(x)); }

double planeElevation(const TerrainParams& p, double d_north_m, double d_east_m) noexcept {
    return p.base_elevation_m + p.plane_slope_north * d_north_m + p.plane_slope_east * d_east_m;
}

double domeElevation(const TerrainParams& p, double d_north_m, double d_east_m) noexcept {
    const double dn = d_north_m - (p.dome_centre_north_m - p.centre_north_m);
    const double de = d_east_m - (p.dome_centre_east_m - p.centre_east_m);
    const double inside = p.dome_radius_m * p.dome_radius_m - (dn * dn + de * de);
    return planeElevation(p, d_north_m, d_east_m) + (inside > 0.0 ? std::sqrt(inside) : 0.0);
}

namespace {

struct Octaves {
    std::uint64_t seed;
    noise::Stream stream;
    double wavelength_m;
    double amplitude;
    double gain;
    int count;
};

// Octaves from wavelength_m down while resolvable on cell_m (noise::octaveWeight).
OctaveSet prepare(const Octaves& o, double cell_m) noexcept {
    OctaveSet set;
    double wavelength = o.wavelength_m;
    double amplitude = o.amplitude;
    const int count = o.count < kMaxOctaves ? o.count : kMaxOctaves;
    for (int i = 0; i < count; ++i) {  // bound: count <= kMaxOctaves
        const double w = noise::octaveWeight(wavelength, cell_m);
        if (w <= 0.0) {
            break;  // wavelengths only shrink from here
        }
        const std::uint64_t key = noise::hash(o.seed, o.stream, i, 0);
        const noise::Rotation r = noise::octaveRotation(i);
        set.key[i] = key;
        set.cos_per_m[i] = r.c / wavelength;
        set.sin_per_m[i] = r.s / wavelength;
        // A lattice offset in [0, 1) (exact: 24 bits) so octaves do not all vanish at the origin.
        set.offset[i] = static_cast<double>(key >> 40U) * (1.0 / 16777216.0);
        set.weight[i] = w * amplitude;
        set.count = i + 1;
        wavelength *= 0.5;
        amplitude *= o.gain;
    }
    return set;
}

double sum(const OctaveSet& set, double north_m, double east_m, bool gradient_noise) noexcept {
    double total = 0.0;
    for (int i = 0; i < set.count; ++i) {  // bound: count <= kMaxOctaves
        const double x = set.cos_per_m[i] * north_m - set.sin_per_m[i] * east_m + set.offset[i];
        const double y = set.sin_per_m[i] * north_m + set.cos_per_m[i] * east_m + set.offset[i];
        const double n = gradient_noise ? noise::gradient(set.key[i], x, y) : noise::value(set.key[i], x, y);
        total += set.weight[i] * n;
    }
    return total;
}

}  // namespace

GroundModel::GroundModel(const TerrainParams& p, double cell_m) noexcept : p_(p) {
    if (p.relief_amplitude_m > 0.0) {
        relief_ = prepare(Octaves{p.seed, noise::Stream::kRelief, p.relief_longest_wavelength_m, p.relief_amplitude_m,
                                  power(2.0, -p.relief_hurst), kMaxOctaves},
                          cell_m);
    }
    if (p.hills_amplitude_m > 0.0) {
        // Four octaves, gain 1/2, amplitude sum 1.875: gradient noise peaks near 0.7, so
        // the normalised sum stays within about +-0.7 and hills are mostly positive.
        hills_ = prepare(Octaves{p.seed, noise::Stream::kHills, p.hills_wavelength_m, 1.0 / 1.875, 0.5, 4}, cell_m);
    }
    // Five octaves of value noise, gain 1/2, amplitude sum 1.9375 (normalised to +-1).
    albedo_ = prepare(Octaves{p.seed, noise::Stream::kAlbedo, p.albedo_wavelength_m, 1.0 / 1.9375, 0.5, 5}, cell_m);
}

double GroundModel::relief(double north_m, double east_m) const noexcept {
    double h = sum(relief_, north_m, east_m, true);
    if (hills_.count > 0) {
        const double dn = north_m - p_.centre_north_m;
        const double de = east_m - p_.centre_east_m;
        const double r = std::sqrt(dn * dn + de * de);
        const double ramp = noise::smoothstep((r - p_.hills_start_m) / (p_.hills_full_m - p_.hills_start_m));
        if (ramp > 0.0) {
            h += p_.hills_amplitude_m * ramp * (0.55 + sum(hills_, north_m, east_m, true));
        }
    }
    return h;
}

double GroundModel::albedo(double north_m, double east_m) const noexcept {
    const double a = p_.albedo_mean * (1.0 + p_.albedo_variation * sum(albedo_, north_m, east_m, false));
    return a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a);
}

CraterBin craterBin(const TerrainParams& p, int k) noexcept {
    CraterBin bin;
    if (p.kind != TerrainKind::kMars || p.crater_density_per_km2 <= 0.0 || k < 0 || k >= p.levels) {
        return bin;
    }
    const double cell = p.finest_cell_m * power(2.0, static_cast<double>(k));
    const double lo = std::fmax(p.crater_min_diameter_m, 2.0 * cell);
    const double hi = (k == p.levels - 1) ? p.crater_max_diameter_m : std::fmin(p.crater_max_diameter_m, 4.0 * cell);
    if (!(lo < hi)) {
        return bin;
    }
    bin.lo_m = lo;
    bin.hi_m = hi;
    const double n_cells = static_cast<double>(std::int64_t{1} << static_cast<unsigned>(p.samples_log2));
    bin.half_m = 0.5 * n_cells * cell + hi;  // the ejecta of a crater reach one diameter from its centre
    const double per_m2 = p.crater_density_per_km2 * 1e-6;
    const double side = 2.0 * bin.half_m;
    const double mean = per_m2 * side * side *
                        (power(lo / p.crater_min_diameter_m, -p.crater_sfd_slope) -
                         power(hi / p.crater_min_diameter_m, -p.crater_sfd_slope));
    bin.count = static_cast<std::int64_t>(std::floor(mean + 0.5));
    return bin;
}

double craterProfile(const Crater& c, double r_m) noexcept {
    const double rho = r_m / (0.5 * c.diameter_m);
    if (rho <= 1.0) {
        return -c.depth_m + (c.depth_m + c.rim_m) * rho * rho;
    }
    if (rho >= 2.0) {
        return 0.0;
    }
    const double inv = 1.0 / rho;
    return c.rim_m * (inv * inv * inv - 0.125) * (8.0 / 7.0);
}

double rockNumberDensity(const TerrainParams& p) noexcept {
    if (p.kind != TerrainKind::kMars || p.rock_k <= 0.0) {
        return 0.0;
    }
    // n(D) = -(dF/dD) / (pi D^2 / 4) = 4 k q exp(-q D) / (pi D^2); with u = 1/D the
    // integral over [Dmin, Dmax] is int exp(-q/u) du over [1/Dmax, 1/Dmin] (smooth): Simpson.
    const double q = 1.79 + 0.152 / p.rock_k;
    const double u0 = 1.0 / p.rock_max_diameter_m;
    const double u1 = 1.0 / p.rock_min_diameter_m;
    constexpr int kIntervals = 512;
    const double h = (u1 - u0) / kIntervals;
    double sum = 0.0;
    for (int i = 0; i <= kIntervals; ++i) {  // bound: kIntervals + 1
        const double u = u0 + h * i;
        const double f = vtm::math::exp(-q / u);
        const double w = (i == 0 || i == kIntervals) ? 1.0 : ((i % 2 == 1) ? 4.0 : 2.0);
        sum += w * f;
    }
    return 4.0 * p.rock_k * q / vtm::math::kPi * sum * h / 3.0;
}

double rockProfile(const TerrainRock& r, double north_m, double east_m) noexcept {
    const double dn = north_m - r.north_m;
    const double de = east_m - r.east_m;
    const double x = r.cos_heading * dn + r.sin_heading * de;
    const double y = -r.sin_heading * dn + r.cos_heading * de;
    const double xa = x / r.semi_major_m;
    const double yb = y / r.semi_minor_m;
    // Visible outline: the ellipsoid (semi-axes a/s, b/s, C; s = sqrt(1 - burial^2))
    // cut by the ground at burial * C below its centre.
    const double keep = 1.0 - r.burial * r.burial;
    const double rho2 = (xa * xa + yb * yb) * keep;
    if (rho2 >= keep) {
        return 0.0;
    }
    const double c = r.height_m / (1.0 - r.burial);
    const double cap = c * std::sqrt(1.0 - rho2) - r.burial * c;
    const double bumps = 1.0 + 0.12 * noise::value(r.id, 2.0 * xa + 8.0, 2.0 * yb + 8.0);
    return cap > 0.0 ? cap * bumps : 0.0;
}

double rockReach_m(const TerrainRock& r) noexcept { return r.semi_major_m; }

namespace {

std::size_t poisson(Random& rng, double mean) noexcept {
    const double u = rng.uniform01();
    double p = vtm::math::exp(-mean);
    double cdf = p;
    std::size_t k = 0U;
    while (u > cdf && k < kMaxRocksPerTile) {  // bound: kMaxRocksPerTile
        ++k;
        p *= mean / static_cast<double>(k);
        cdf += p;
    }
    return k;
}

// Diameter with density ~ exp(-q D) / D^2 on [dmin, dmax]: proposal ~ 1/D^2 (inverse
// CDF), accepted with probability exp(-q (D - dmin)).
double drawDiameter(Random& rng, double q, double dmin, double dmax) noexcept {
    const double inv_min = 1.0 / dmin;
    const double inv_span = inv_min - 1.0 / dmax;
    double d = dmin;
    for (int i = 0; i < kRockDiameterDraws; ++i) {  // bound: kRockDiameterDraws
        const double u = rng.uniform01();
        d = 1.0 / (inv_min - u * inv_span);
        const double accept = rng.uniform01();
        if (accept < vtm::math::exp(-q * (d - dmin))) {
            break;
        }
    }
    return d;
}

}  // namespace

std::size_t rocksInTile(const TerrainParams& p, double density_per_m2, std::int64_t tile_north,
                        std::int64_t tile_east, Span<TerrainRock> out) noexcept {
    if (p.kind != TerrainKind::kMars || !(density_per_m2 > 0.0)) {
        return 0U;
    }
    const std::uint64_t tile_key = noise::hash(p.seed, noise::Stream::kRocks, tile_north, tile_east);
    Random rng(tile_key);
    const std::size_t count = poisson(rng, density_per_m2 * kRockTile_m * kRockTile_m);
    const double q = 1.79 + 0.152 / p.rock_k;
    const double region2 = p.rock_region_radius_m * p.rock_region_radius_m;
    std::size_t written = 0U;
    for (std::size_t i = 0U; i < count; ++i) {  // bound: count <= kMaxRocksPerTile
        TerrainRock r{};
        const double un = rng.uniform01();
        const double ue = rng.uniform01();
        r.diameter_m = drawDiameter(rng, q, p.rock_min_diameter_m, p.rock_max_diameter_m);
        const double u_height = rng.uniform01();
        const double u_aspect = rng.uniform01();
        const double u_heading = rng.uniform01();
        const double u_burial = rng.uniform01();
        const double u_albedo = rng.uniform01();
        const double dn = (static_cast<double>(tile_north) + un) * kRockTile_m;
        const double de = (static_cast<double>(tile_east) + ue) * kRockTile_m;
        if (dn * dn + de * de > region2 || written >= out.size()) {
            continue;  // the draws above are consumed all the same: rocks stay where they are
        }
        r.north_m = p.centre_north_m + dn;
        r.east_m = p.centre_east_m + de;
        r.height_m = r.diameter_m * p.rock_height_ratio * (0.6 + 0.8 * u_height);
        const double f = 1.0 + 0.4 * u_aspect;
        r.semi_major_m = 0.5 * r.diameter_m * f;
        r.semi_minor_m = 0.5 * r.diameter_m / f;
        r.cos_heading = vtm::math::cos(vtm::math::kPi * u_heading);
        r.sin_heading = vtm::math::sin(vtm::math::kPi * u_heading);
        r.burial = 0.2 + 0.4 * u_burial;
        const double a = p.rock_albedo_mean + p.rock_albedo_spread * (2.0 * u_albedo - 1.0);
        r.albedo = a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a);
        r.id = noise::hash(tile_key, noise::Stream::kRockSurface, static_cast<std::int64_t>(i), 0);
        out[written] = r;
        ++written;
    }
    return written;
}

}  // namespace model

std::size_t terrainRocksInTile(const TerrainParams& params, std::int64_t tile_north, std::int64_t tile_east,
                               Span<TerrainRock> out) noexcept {
    return model::rocksInTile(params, model::rockNumberDensity(params), tile_north, tile_east, out);
}

double golombekCumulativeArea(double k, double d_m) noexcept {
    if (!(k > 0.0)) {
        return 0.0;
    }
    return k * vtm::math::exp(-(1.79 + 0.152 / k) * d_m);
}

}  // namespace vtm::sim
