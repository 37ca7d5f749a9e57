// Terrain (sim/terrain): ray casting against analytic surfaces, continuity, first-hit
// property, rock statistics, determinism, validation and the no-heap run path.
// Worlds are tiny (64 cells per level) so the suite stays fast under qemu.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {
namespace {

// A built terrain with its own pool.
struct World {
    explicit World(const TerrainParams& p) : pool(Terrain::storageBytes(p)), arena(pool.data(), pool.size()) {
        status = terrain.build(p, arena);
    }
    std::vector<std::byte> pool;
    Arena arena;
    Terrain terrain;
    Status status;
};

// Dyadic plane: every sample, blend and bilinear value is exact in float and double.
TerrainParams planeParams() {
    TerrainParams p;
    p.kind = TerrainKind::kPlane;
    p.centre_north_m = 1.5;
    p.centre_east_m = -2.25;
    p.finest_cell_m = 0.0625;
    p.samples_log2 = 6;
    p.levels = 5;  // level 4: half side 32 m
    p.base_elevation_m = 1.5;
    p.plane_slope_north = 0.25;
    p.plane_slope_east = -0.125;
    return p;
}

TerrainParams smallMarsParams() {
    TerrainParams p;
    p.seed = 42U;
    p.finest_cell_m = 0.02;
    p.samples_log2 = 6;
    p.levels = 6;  // level 5: half side 20.48 m, cell 0.64 m
    p.relief_amplitude_m = 0.5;
    p.relief_longest_wavelength_m = 8.0;
    p.crater_density_per_km2 = 2e5;
    p.crater_min_diameter_m = 0.1;
    p.crater_max_diameter_m = 10.0;
    p.rock_k = 0.15;
    p.rock_region_radius_m = 15.0;
    p.hills_start_m = 10.0;
    p.hills_full_m = 20.0;
    p.hills_amplitude_m = 2.0;
    p.hills_wavelength_m = 10.0;
    return p;
}

Vec3 unit(const Vec3& v) { return v / std::sqrt(v.squaredNorm()); }

// Ray parameter where the ray leaves the outermost grid square (horizontal slab test).
double gridExit(const Terrain& t, const Vec3& o, const Vec3& d) {
    const int top = t.levelCount() - 1;
    const double half = t.halfExtent_m(top);
    const TerrainParams& p = t.params();
    double hi = 1e300;
    const double c[2] = {p.centre_north_m, p.centre_east_m};
    for (int a = 0; a < 2; ++a) {
        if (d[a] != 0.0) {
            hi = std::min(hi, std::max((c[a] - half - o[a]) / d[a], (c[a] + half - o[a]) / d[a]));
        }
    }
    return hi;
}

TEST(Terrain, PlaneRaysHitTheAnalyticPlaneExactlyOnEveryLevel) {
    const TerrainParams p = planeParams();
    World w(p);
    ASSERT_TRUE(w.status.isOk()) << w.status.reason();
    Random rng(7U);
    int hits = 0;
    int crossings = 0;
    int levels_seen[kMaxTerrainLevels] = {};
    for (int r = 0; r < 2000; ++r) {
        const double on = p.centre_north_m + (rng.uniform01() * 2.0 - 1.0) * 25.0;
        const double oe = p.centre_east_m + (rng.uniform01() * 2.0 - 1.0) * 25.0;
        const double height = 0.2 + rng.uniform01() * 20.0;
        const double plane = p.base_elevation_m + p.plane_slope_north * (on - p.centre_north_m) +
                             p.plane_slope_east * (oe - p.centre_east_m);
        const Vec3 o(on, oe, -(plane + height));
        const double dn = rng.uniform01() * 2.0 - 1.0;
        const double de = rng.uniform01() * 2.0 - 1.0;
        const double dz = 0.02 + rng.uniform01() * 1.5;  // from grazing to steep
        const Vec3 d = unit(Vec3(dn, de, dz));
        // -(oz + t dz) = base + sn (n - cn) + se (e - ce)
        const double t_true = -(o.z() + p.base_elevation_m + p.plane_slope_north * (o.x() - p.centre_north_m) +
                                p.plane_slope_east * (o.y() - p.centre_east_m)) /
                              (d.z() + p.plane_slope_north * d.x() + p.plane_slope_east * d.y());
        const TerrainHit hit = w.terrain.intersect(o, d, 1000.0);
        const bool inside = t_true > 0.0 && t_true < gridExit(w.terrain, o, d);
        ASSERT_EQ(hit.hit, inside) << "ray " << r << " t_true " << t_true;
        if (!hit.hit) {
            continue;
        }
        ++hits;
        EXPECT_NEAR(hit.t_m, t_true, 1e-9) << "ray " << r;
        EXPECT_NEAR(hit.normal_site.x(), unit(Vec3(-0.25, 0.125, -1.0)).x(), 1e-12);
        const int start_level = w.terrain.governingLevel(o.x(), o.y());
        crossings += (start_level != hit.level) ? 1 : 0;
        ++levels_seen[hit.level];
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(crossings, 300);  // rays that cross at least one level border before the hit
    for (int k = 0; k < p.levels; ++k) {
        EXPECT_GT(levels_seen[k], 0) << "no hit governed by level " << k;
    }
}

// Largest |d2z/dx2| + |d2z/dy2| of the hemisphere z = sqrt(R^2 - r^2) over a cell whose
// lowest dome height is zmin: |z_xx| = (R^2 - y^2)/z^3 <= R^2/z^3, same for z_yy.
double domeCurvatureBound(double radius, double zmin) { return 2.0 * radius * radius / (zmin * zmin * zmin); }

TEST(Terrain, DomeHitsLieOnTheSurfaceWithinTheBilinearInterpolationBound) {
    TerrainParams p;
    p.kind = TerrainKind::kDome;
    p.finest_cell_m = 0.01;
    p.samples_log2 = 6;
    p.levels = 5;  // level 0 half side 0.32 m .. level 4 5.12 m
    p.dome_radius_m = 2.0;
    p.base_elevation_m = 0.0;
    World w(p);
    ASSERT_TRUE(w.status.isOk()) << w.status.reason();
    Random rng(11U);
    int checked = 0;
    double worst_ratio = 0.0;
    for (int r = 0; r < 3000; ++r) {
        const double an = (rng.uniform01() * 2.0 - 1.0) * 1.6;
        const double ae = (rng.uniform01() * 2.0 - 1.0) * 1.6;
        const double tilt_n = (rng.uniform01() * 2.0 - 1.0) * 0.6;
        const double tilt_e = (rng.uniform01() * 2.0 - 1.0) * 0.6;
        const Vec3 d = unit(Vec3(tilt_n, tilt_e, 1.0));
        const Vec3 o = Vec3(an, ae, 0.0) - 5.0 * d;  // aimed at (an, ae, ground)
        const TerrainHit hit = w.terrain.intersect(o, d, 100.0);
        ASSERT_TRUE(hit.hit);
        const double n = hit.point_site_m.x();
        const double e = hit.point_site_m.y();
        // The hit is on the terrain's own surface ...
        EXPECT_NEAR(w.terrain.elevationAt(n, e), -hit.point_site_m.z(), 1e-9);
        // ... and that surface is within the interpolation bound of the sphere. In a
        // level's blend band the surface mixes it with the next coarser level, so the
        // coarser cell h = 2 * cell bounds both: |f - I f| <= h^2 / 8 (|f_xx| + |f_yy|).
        const double rr = std::sqrt(n * n + e * e);
        const double h = 2.0 * w.terrain.cellSize_m(hit.level);
        const double r_far = rr + h * std::sqrt(2.0);
        if (r_far >= 0.8 * p.dome_radius_m) {
            continue;  // near the rim the curvature is unbounded
        }
        const double zmin = std::sqrt(p.dome_radius_m * p.dome_radius_m - r_far * r_far);
        const double bound = h * h / 8.0 * domeCurvatureBound(p.dome_radius_m, zmin) + 1e-6;  // + float samples
        const double sphere = std::sqrt(p.dome_radius_m * p.dome_radius_m - rr * rr);
        const double err = std::fabs(-hit.point_site_m.z() - sphere);
        EXPECT_LE(err, bound) << "at r = " << rr << " level " << hit.level;
        worst_ratio = std::max(worst_ratio, err / bound);
        ++checked;
    }
    EXPECT_GT(checked, 1500);
    EXPECT_GT(worst_ratio, 0.01);  // the bound is tight enough to mean something
}

TEST(Terrain, SurfaceIsContinuousAcrossLevelBorders) {
    const TerrainParams p = smallMarsParams();
    World w(p);
    ASSERT_TRUE(w.status.isOk()) << w.status.reason();
    const Terrain& t = w.terrain;
    double worst = 0.0;
    double typical_step = 0.0;
    for (int k = 0; k + 1 < t.levelCount(); ++k) {
        const double half = t.halfExtent_m(k);
        for (int s = 0; s < 400; ++s) {
            const double along = (static_cast<double>(s) / 400.0 * 2.0 - 1.0) * half * 0.999;
            const double eps = 1e-9 * half;
            // North border and east border, just inside and just outside.
            const double pairs[2][4] = {{half - eps, along, half + eps, along}, {along, -half + eps, along, -half - eps}};
            for (const auto& q : pairs) {
                const double in = t.elevationAt(p.centre_north_m + q[0], p.centre_east_m + q[1]);
                const double out = t.elevationAt(p.centre_north_m + q[2], p.centre_east_m + q[3]);
                ASSERT_EQ(t.governingLevel(p.centre_north_m + q[0], p.centre_east_m + q[1]), k);
                ASSERT_EQ(t.governingLevel(p.centre_north_m + q[2], p.centre_east_m + q[3]), k + 1);
                worst = std::max(worst, std::fabs(in - out));
            }
            // For scale: the change across one cell of level k next to the border.
            const double cell = t.cellSize_m(k);
            typical_step = std::max(typical_step, std::fabs(t.elevationAt(p.centre_north_m + half - cell, p.centre_east_m + along) -
                                                             t.elevationAt(p.centre_north_m + half - 2.0 * cell, p.centre_east_m + along)));
        }
    }
    EXPECT_LT(worst, 1e-5);  // float rounding of the border samples only
    EXPECT_GT(typical_step, 1e-3);
}

// Brute force: march the ray in small steps until it is at or below the surface, then
// bisect. Returns -1 when the ray leaves the grid or t_max first.
double marchFirstHit(const Terrain& t, const Vec3& o, const Vec3& d, double t_max, double step) {
    const double end = std::min(t_max, gridExit(t, o, d));
    const auto below = [&](double s) {
        const Vec3 q = o + s * d;
        return -q.z() <= t.elevationAt(q.x(), q.y());
    };
    double prev = 0.0;
    for (double s = step; s <= end + step; s += step) {
        const double cur = std::min(s, end);
        if (below(cur)) {
            double a = prev;
            double b = cur;
            for (int i = 0; i < 80; ++i) {
                const double m = 0.5 * (a + b);
                (below(m) ? b : a) = m;
            }
            return b;
        }
        prev = cur;
        if (cur >= end) {
            break;
        }
    }
    return -1.0;
}

TEST(Terrain, FirstHitAgreesWithBruteForceMarchOnMarsWorld) {
    const TerrainParams p = smallMarsParams();
    World w(p);
    ASSERT_TRUE(w.status.isOk()) << w.status.reason();
    const Terrain& t = w.terrain;
    Random rng(3U);
    int agree = 0;
    int hits = 0;
    int total = 0;
    TerrainRayStats stats;
    for (int r = 0; r < 180; ++r) {
        const int kind = r % 3;
        const double on = p.centre_north_m + (rng.uniform01() * 2.0 - 1.0) * 6.0;
        const double oe = p.centre_east_m + (rng.uniform01() * 2.0 - 1.0) * 6.0;
        const double az = rng.uniform01() * 6.283185307179586;
        const double ground = t.elevationAt(on, oe);
        Vec3 o;
        Vec3 d;
        if (kind == 0) {  // rover mast: 1.5 m up, 1 .. 8 degrees below the horizon
            const double dip = 0.017 + rng.uniform01() * 0.12;
            o = Vec3(on, oe, -(ground + 1.5));
            d = unit(Vec3(std::cos(az), std::sin(az), dip));
        } else if (kind == 1) {  // straight down from 50 m
            o = Vec3(on, oe, -(ground + 50.0));
            d = Vec3(0.0, 0.0, 1.0);
        } else {  // anything looking down
            o = Vec3(on, oe, -(ground + 0.3 + rng.uniform01() * 5.0));
            d = unit(Vec3(std::cos(az), std::sin(az), 0.05 + rng.uniform01() * 2.0));
        }
        const TerrainHit hit = t.intersect(o, d, 60.0, &stats);
        const double march = marchFirstHit(t, o, d, 60.0, 0.002);
        ++total;
        if (march < 0.0 && !hit.hit) {
            ++agree;
            continue;
        }
        ASSERT_TRUE(hit.hit) << "ray " << r << ": march found t = " << march;
        ++hits;
        // The cast never passes through surface the march found ...
        EXPECT_LE(hit.t_m, march + 1e-6) << "ray " << r;
        // ... and every hit it reports is on the surface.
        const Vec3 q = hit.point_site_m;
        EXPECT_NEAR(-q.z(), t.elevationAt(q.x(), q.y()), 1e-7) << "ray " << r;
        agree += (std::fabs(hit.t_m - march) < 1e-6) ? 1 : 0;
    }
    EXPECT_EQ(stats.bound_exceeded, 0U);
    EXPECT_EQ(stats.rays, static_cast<std::uint64_t>(total));
    EXPECT_GT(hits, 150);
    // A march with 2 mm steps may step over a sliver the exact cast finds; allow 2 %.
    EXPECT_GE(agree, total - total / 50);
}

TEST(Terrain, RockCumulativeAreaFollowsGolombekModel) {
    TerrainParams p;
    p.rock_k = 0.07;
    p.rock_region_radius_m = 1000.0;
    std::vector<TerrainRock> rocks(kMaxRocksPerTile);
    const Span<TerrainRock> out(rocks.data(), rocks.size());
    const double diameters[3] = {0.1, 0.3, 0.6};
    double area[3] = {};
    double area_sq[3] = {};
    constexpr int kTiles = 24;  // 24 x 24 tiles of 4 m: 9216 m^2
    for (int tn = -kTiles / 2; tn < kTiles / 2; ++tn) {
        for (int te = -kTiles / 2; te < kTiles / 2; ++te) {
            const std::size_t n = terrainRocksInTile(p, tn, te, out);
            for (std::size_t i = 0; i < n; ++i) {
                const TerrainRock& r = rocks[i];
                ASSERT_GE(r.diameter_m, p.rock_min_diameter_m);
                ASSERT_LE(r.diameter_m, p.rock_max_diameter_m);
                EXPECT_NEAR(r.semi_major_m * r.semi_minor_m, 0.25 * r.diameter_m * r.diameter_m, 1e-12);
                const double a = 0.7853981633974483 * r.diameter_m * r.diameter_m;
                for (int k = 0; k < 3; ++k) {
                    if (r.diameter_m >= diameters[k]) {
                        area[k] += a;
                        area_sq[k] += a * a;
                    }
                }
            }
        }
    }
    const double total = kTiles * kTiles * kRockTile_m * kRockTile_m;
    for (int k = 0; k < 3; ++k) {
        const double model = golombekCumulativeArea(p.rock_k, diameters[k]) - golombekCumulativeArea(p.rock_k, 2.0);
        const double realised = area[k] / total;
        const double sigma = std::sqrt(area_sq[k]) / total;  // Poisson sampling error of the sum
        EXPECT_NEAR(realised, model, 4.0 * sigma) << "D >= " << diameters[k] << " sigma " << sigma;
        EXPECT_LT(sigma, 0.25 * model);  // the area is large enough for the check to bite
    }
}

TEST(Terrain, SameParamsGiveSameBytesAndOtherSeedsDiffer) {
    const TerrainParams p = smallMarsParams();
    World a(p);
    World b(p);
    TerrainParams q = p;
    q.seed = p.seed + 1U;
    World c(q);
    ASSERT_TRUE(a.status.isOk() && b.status.isOk() && c.status.isOk());
    EXPECT_EQ(a.terrain.contentHash(), b.terrain.contentHash());
    EXPECT_NE(a.terrain.contentHash(), c.terrain.contentHash());
    EXPECT_NE(a.terrain.elevationAt(1.0, 1.0), c.terrain.elevationAt(1.0, 1.0));
}

TEST(Terrain, ValidateNamesEachBadField) {
    struct Case {
        const char* field;
        std::function<void(TerrainParams&)> spoil;
    };
    const double nan = std::nan("");
    const std::vector<Case> cases = {
        {"kind", [](TerrainParams& p) { p.kind = static_cast<TerrainKind>(7); }},
        {"centre_north_m", [&](TerrainParams& p) { p.centre_north_m = nan; }},
        {"centre_east_m", [](TerrainParams& p) { p.centre_east_m = 1e9; }},
        {"finest_cell_m", [](TerrainParams& p) { p.finest_cell_m = 0.0; }},
        {"samples_log2", [](TerrainParams& p) { p.samples_log2 = 2; }},
        {"levels", [](TerrainParams& p) { p.levels = 17; }},
        {"base_elevation_m", [&](TerrainParams& p) { p.base_elevation_m = nan; }},
        {"plane_slope_north", [](TerrainParams& p) { p.plane_slope_north = 11.0; }},
        {"plane_slope_east", [](TerrainParams& p) { p.plane_slope_east = -11.0; }},
        {"dome_centre_north_m", [&](TerrainParams& p) { p.dome_centre_north_m = nan; }},
        {"dome_centre_east_m", [&](TerrainParams& p) { p.dome_centre_east_m = nan; }},
        {"dome_radius_m", [](TerrainParams& p) { p.dome_radius_m = 0.0; }},
        {"relief_amplitude_m", [](TerrainParams& p) { p.relief_amplitude_m = -1.0; }},
        {"relief_longest_wavelength_m", [](TerrainParams& p) { p.relief_longest_wavelength_m = 0.001; }},
        {"relief_hurst", [](TerrainParams& p) { p.relief_hurst = 1.5; }},
        {"hills_start_m", [](TerrainParams& p) { p.hills_start_m = -1.0; }},
        {"hills_full_m", [](TerrainParams& p) { p.hills_full_m = p.hills_start_m; }},
        {"hills_amplitude_m", [](TerrainParams& p) { p.hills_amplitude_m = 6000.0; }},
        {"hills_wavelength_m", [](TerrainParams& p) { p.hills_wavelength_m = 0.0; }},
        {"crater_density_per_km2", [](TerrainParams& p) { p.crater_density_per_km2 = -1.0; }},
        {"crater_density_per_km2", [](TerrainParams& p) { p.crater_density_per_km2 = 9e6; }},  // too many
        {"crater_sfd_slope", [](TerrainParams& p) { p.crater_sfd_slope = 0.5; }},
        {"crater_min_diameter_m", [](TerrainParams& p) { p.crater_min_diameter_m = 0.0; }},
        {"crater_max_diameter_m", [](TerrainParams& p) { p.crater_max_diameter_m = 0.1; }},
        {"crater_depth_ratio", [](TerrainParams& p) { p.crater_depth_ratio = 0.6; }},
        {"crater_rim_ratio", [](TerrainParams& p) { p.crater_rim_ratio = 0.3; }},
        {"rock_k", [](TerrainParams& p) { p.rock_k = 0.6; }},
        {"rock_max_diameter_m", [](TerrainParams& p) { p.rock_max_diameter_m = 5.0; }},
        {"rock_min_diameter_m", [](TerrainParams& p) { p.rock_min_diameter_m = 0.001; }},
        {"rock_min_diameter_m", [](TerrainParams& p) { p.rock_k = 0.5; p.rock_min_diameter_m = 0.01; }},
        {"rock_height_ratio", [](TerrainParams& p) { p.rock_height_ratio = 0.0; }},
        {"rock_region_radius_m", [](TerrainParams& p) { p.rock_region_radius_m = 3000.0; }},
        {"albedo_mean", [](TerrainParams& p) { p.albedo_mean = 1.5; }},
        {"albedo_variation", [](TerrainParams& p) { p.albedo_variation = -0.1; }},
        {"albedo_wavelength_m", [](TerrainParams& p) { p.albedo_wavelength_m = 0.0; }},
        {"rock_albedo_mean", [](TerrainParams& p) { p.rock_albedo_mean = 2.0; }},
        {"rock_albedo_spread", [](TerrainParams& p) { p.rock_albedo_spread = 0.6; }},
        {"texture_contrast", [](TerrainParams& p) { p.texture_contrast = 1.1; }},
        {"texture_finest_wavelength_m", [](TerrainParams& p) { p.texture_finest_wavelength_m = 0.0; }},
        {"texture_longest_wavelength_m", [](TerrainParams& p) { p.texture_longest_wavelength_m = 1e-4; }},
    };
    EXPECT_TRUE(defaultMarsTerrainParams().validate().isOk());
    EXPECT_TRUE(planeParams().validate().isOk());
    for (const Case& c : cases) {
        TerrainParams p = defaultMarsTerrainParams();
        c.spoil(p);
        const Status s = p.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << c.field;
        EXPECT_EQ(std::string(s.reason()).rfind(std::string(c.field) + ":", 0), 0U)
            << c.field << " gave \"" << s.reason() << "\"";
        EXPECT_EQ(Terrain::storageBytes(p), 0U) << c.field;
    }
}

TEST(Terrain, BuildAndIntersectDoNotTouchTheHeapAndFitStorageBytes) {
    const TerrainParams p = smallMarsParams();
    const std::size_t bytes = Terrain::storageBytes(p);
    std::vector<std::byte> pool(bytes);
    Arena arena(pool.data(), pool.size());
    Terrain t;
    TerrainHit hit;
    {
        test::NoHeapScope scope;
        ASSERT_TRUE(t.build(p, arena).isOk());
        hit = t.intersect(Vec3(0.0, 0.0, -10.0), unit(Vec3(1.0, 0.5, 1.0)), 100.0);
        const double a = t.albedoAt(0.3, 0.2, 0.001);
        const Vec3 n = t.shadingNormal(0.3, 0.2, 0.01);
        EXPECT_GE(a, 0.0);
        EXPECT_LE(a, 1.0);
        EXPECT_LT(n.z(), 0.0);
        EXPECT_EQ(scope.heapCalls(), 0U);
    }
    EXPECT_TRUE(hit.hit);
    EXPECT_LE(arena.highWaterBytes(), bytes);
    // Half the storage is not enough: a status, not a crash.
    std::vector<std::byte> small(bytes / 2U);
    Arena small_arena(small.data(), small.size());
    Terrain u;
    EXPECT_EQ(u.build(p, small_arena).code(), StatusCode::kOutOfMemory);
    EXPECT_FALSE(u.built());
    EXPECT_FALSE(u.intersect(Vec3(0.0, 0.0, -10.0), Vec3(0.0, 0.0, 1.0), 100.0).hit);
}

TEST(Terrain, AlbedoTextureIsBandLimitedByFootprint) {
    const TerrainParams p = smallMarsParams();
    World w(p);
    ASSERT_TRUE(w.status.isOk());
    // Across 1 mm steps the millimetre texture varies; with a 0.2 m footprint the octaves
    // below 0.2 m are replaced by their mean, so neighbouring values barely change.
    double fine_var = 0.0;
    double coarse_var = 0.0;
    for (int i = 0; i < 200; ++i) {
        const double x = 0.1 + 0.001 * i;
        const double df = w.terrain.albedoAt(x + 0.001, 0.05, 0.0005) - w.terrain.albedoAt(x, 0.05, 0.0005);
        const double dc = w.terrain.albedoAt(x + 0.001, 0.05, 0.2) - w.terrain.albedoAt(x, 0.05, 0.2);
        fine_var += df * df;
        coarse_var += dc * dc;
    }
    EXPECT_GT(fine_var, 100.0 * coarse_var);
}

}  // namespace
}  // namespace vtm::sim
