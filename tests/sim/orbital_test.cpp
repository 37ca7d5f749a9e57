// vtm_sim_orbital_tests: the orbital view (sim/orbital.hpp) against the terrain's own
// queries and analytic scenes (georeference, footprint sub-samples, the dome's lit and
// shadowed sides), the thermal model's response to slope and albedo, thermal versus
// visible (not a monotonic remap), a descent frame located in the orbital image through
// its truth, determinism, the no-heap rule, refusals, and the scenario's [orbital] section.
// Expected values come from the documented formulas evaluated here, never from a render.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "sim/orbital.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "terrain_pool.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"

namespace vtm::sim {
namespace {

// Each world in its own pool slot (built once per process).
enum class World { kFlatAlbedo, kDome, kSmallMars };
const Terrain& buildTerrain(World world, const TerrainParams& params) {
    return terrainInPool(params, static_cast<int>(world));
}

// A flat plane with albedo patches of a few metres and no fine texture.
TerrainParams flatAlbedoParams() {
    TerrainParams p;
    p.kind = TerrainKind::kPlane;
    p.finest_cell_m = 0.1;
    p.samples_log2 = 8;
    p.levels = 4;
    p.base_elevation_m = 2.0;
    p.albedo_mean = 0.25;
    p.albedo_variation = 0.8;
    p.albedo_wavelength_m = 4.0;
    p.texture_contrast = 0.0;
    return p;
}

constexpr double kDomeRadius = 8.0;

// A dome of radius 8 m on a flat plane at elevation 0, uniform albedo 0.25.
TerrainParams domeParams() {
    TerrainParams p;
    p.kind = TerrainKind::kDome;
    p.finest_cell_m = 0.1;
    p.samples_log2 = 8;
    p.levels = 3;
    p.dome_radius_m = kDomeRadius;
    p.albedo_mean = 0.25;
    p.albedo_variation = 0.0;
    p.texture_contrast = 0.0;
    return p;
}

TerrainParams smallMarsParams() {
    TerrainParams p = defaultMarsTerrainParams();
    p.seed = 24U;
    p.finest_cell_m = 0.08;
    p.samples_log2 = 7;
    p.levels = 8;
    p.relief_amplitude_m = 3.0;
    p.relief_longest_wavelength_m = 40.0;
    p.albedo_wavelength_m = 10.0;
    p.rock_region_radius_m = 20.0;
    p.crater_min_diameter_m = 1.0;
    return p;
}

struct Image {
    std::vector<std::uint8_t> p8;
    std::vector<std::uint16_t> p16;
    std::vector<float> elevation;
    OrbitalStats stats;
};

OrbitalOutput views(const OrbitalParams& p, Image& img) {
    const auto n = static_cast<std::size_t>(p.width_px) * static_cast<std::size_t>(p.height_px);
    img.p8.resize(n);
    img.p16.resize(n);
    img.elevation.resize(n);
    OrbitalOutput out;
    out.image8 = ImageView<std::uint8_t>(img.p8.data(), p.width_px, p.height_px);
    out.image16 = ImageView<std::uint16_t>(img.p16.data(), p.width_px, p.height_px);
    out.elevation_m = ImageView<float>(img.elevation.data(), p.width_px, p.height_px);
    return out;
}

Image render(const Terrain& t, const OrbitalParams& p) {
    Image img;
    const OrbitalOutput out = views(p, img);
    const Status s = renderOrbital(t, p, out, &img.stats);
    EXPECT_TRUE(s.isOk()) << s.reason();
    return img;
}

// Noise-free 16-bit, 1 m/px-like settings shared by the model tests.
OrbitalParams exactParams(OrbitalModality modality, double cell_m, std::int32_t w, std::int32_t h) {
    OrbitalParams p;
    p.modality = modality;
    p.cell_m = cell_m;
    p.width_px = w;
    p.height_px = h;
    p.bit_depth = 16;
    p.noise_fs = 0.0;
    return p;
}

Vec3 sunFrom(double azimuth_deg, double elevation_deg) {
    const double az = azimuth_deg * M_PI / 180.0;
    const double el = elevation_deg * M_PI / 180.0;
    return Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
}

// The documented grid, computed here: pixel (c, r) -> site.
void siteOfPixel(const OrbitalParams& p, double c, double r, double& north, double& east) {
    north = p.centre_north_m + 0.5 * (p.height_px - 1) * p.cell_m - r * p.cell_m;
    east = p.centre_east_m - 0.5 * (p.width_px - 1) * p.cell_m + c * p.cell_m;
}

// Brightness temperature (K) of a 16-bit thermal DN under p's scale (offset included).
double kelvinOfDn(const OrbitalParams& p, std::uint16_t dn) {
    const double s = dn / 65535.0 - p.offset_fs;
    return p.thermal.scale_min_k + s * (p.thermal.scale_max_k - p.thermal.scale_min_k);
}

double rankCorrelation(const std::vector<double>& a, const std::vector<double>& b) {
    auto ranks = [](const std::vector<double>& v) {
        std::vector<std::size_t> idx(v.size());
        for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
        std::sort(idx.begin(), idx.end(), [&](std::size_t x, std::size_t y) { return v[x] < v[y]; });
        std::vector<double> r(v.size());
        std::size_t i = 0;
        while (i < idx.size()) {  // average ranks of ties
            std::size_t j = i;
            while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
            for (std::size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * static_cast<double>(i + j);
            i = j + 1;
        }
        return r;
    };
    const std::vector<double> ra = ranks(a);
    const std::vector<double> rb = ranks(b);
    double ma = 0.0, mb = 0.0;
    for (std::size_t i = 0; i < ra.size(); ++i) {
        ma += ra[i];
        mb += rb[i];
    }
    ma /= static_cast<double>(ra.size());
    mb /= static_cast<double>(rb.size());
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t i = 0; i < ra.size(); ++i) {
        sab += (ra[i] - ma) * (rb[i] - mb);
        saa += (ra[i] - ma) * (ra[i] - ma);
        sbb += (rb[i] - mb) * (rb[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

// ---- georeference -------------------------------------------------------------------

TEST(SimOrbital, GeoreferencePutsPixelZeroAtTheNorthWestCornerRowsSouthColumnsEast) {
    OrbitalParams p;
    p.centre_north_m = 100.0;
    p.centre_east_m = -40.0;
    p.cell_m = 2.0;
    p.width_px = 11;
    p.height_px = 7;
    const OrbitalGeoreference geo = orbitalGeoreference(p);
    // 11 columns of 2 m centred on -40: -50 .. -30 east; 7 rows centred on 100: 106 .. 94 north.
    EXPECT_DOUBLE_EQ(geo.north0_m, 106.0);
    EXPECT_DOUBLE_EQ(geo.east0_m, -50.0);
    const Vec2 se = orbitalSiteFromPixel(geo, 10.0, 6.0);
    EXPECT_DOUBLE_EQ(se.x(), 94.0);   // last row: south
    EXPECT_DOUBLE_EQ(se.y(), -30.0);  // last column: east
    const Vec2 centre = orbitalPixelFromSite(geo, 100.0, -40.0);
    EXPECT_DOUBLE_EQ(centre.x(), 5.0);
    EXPECT_DOUBLE_EQ(centre.y(), 3.0);
    const Vec2 back = orbitalPixelFromSite(geo, 101.3, -37.1);
    const Vec2 site = orbitalSiteFromPixel(geo, back.x(), back.y());
    EXPECT_NEAR(site.x(), 101.3, 1e-12);
    EXPECT_NEAR(site.y(), -37.1, 1e-12);
}

// Visible, sun at the zenith, no shadows, no noise: every pixel is the mean of
// a * (1 + ambient) / full_scale over its 2 x 2 sub-samples at +-cell/4, albedo queried here
// at the documented site with footprint cell/2. One pixel off would not match.
TEST(SimOrbital, VisiblePixelsAreTheAlbedoAtTheirGeoreferencedSubsamples) {
    const Terrain& t = buildTerrain(World::kFlatAlbedo, flatAlbedoParams());
    OrbitalParams p = exactParams(OrbitalModality::kVisible, 0.5, 48, 40);
    p.centre_north_m = 3.0;
    p.centre_east_m = -2.0;
    p.to_sun_site = Vec3(0.0, 0.0, -1.0);
    p.shadows = false;
    const Image img = render(t, p);
    const auto expected = [&](double c, double r) {
        double sum = 0.0;
        for (const double dr : {-0.25, 0.25}) {
            for (const double dc : {-0.25, 0.25}) {
                double north = 0.0, east = 0.0;
                siteOfPixel(p, c + dc, r + dr, north, east);
                sum += t.albedoAt(north, east, 0.5 * p.cell_m) * (1.0 + p.ambient) / p.full_scale_reflectance;
            }
        }
        return 65535.0 * (p.offset_fs + 0.25 * sum);
    };
    int worst = 0;
    int shifted_off = 0;
    for (int r = 0; r < p.height_px; ++r) {
        for (int c = 0; c < p.width_px; ++c) {
            const double dn = img.p16[static_cast<std::size_t>(r * p.width_px + c)];
            worst = std::max(worst, static_cast<int>(std::lround(std::fabs(dn - expected(c, r)))));
            shifted_off += std::fabs(dn - expected(c + 1, r)) > 20.0 ? 1 : 0;
        }
    }
    EXPECT_LE(worst, 1);
    EXPECT_GT(shifted_off, p.width_px * p.height_px / 2);  // the check can tell one pixel apart
    // The elevation truth is the plane's.
    EXPECT_FLOAT_EQ(img.elevation[0], 2.0F);
}

// ---- the thermal model on analytic scenes -------------------------------------------

// Thermal, sun in the east at 45 deg: on the dome (away from its rim) every pixel's
// brightness temperature is the model's with the sphere's analytic normal at the pixel's
// georeferenced site; the hottest pixel is where the normal points at the sun; the
// sunward (east) flank is warmer than the west flank; the plane in the dome's shadow sits
// at the floor, the lit plane east of it at the flat-ground temperature.
TEST(SimOrbital, ThermalDomeFollowsTheModelWithTheAnalyticNormal) {
    const Terrain& t = buildTerrain(World::kDome, domeParams());
    OrbitalParams p = exactParams(OrbitalModality::kThermal, 0.25, 96, 96);
    p.subsamples = 1;
    p.to_sun_site = sunFrom(90.0, 45.0);
    const Image img = render(t, p);
    const double a = 0.25;
    const double f4 = std::pow(p.thermal.floor_k, 4.0);
    const double s4 = std::pow(p.thermal.subsolar_k, 4.0);
    const auto model = [&](double cos_i) { return std::pow(f4 + s4 * (1.0 - a) * std::max(cos_i, 0.0), 0.25); };
    const auto domeT = [&](double north, double east) {
        const double r2 = north * north + east * east;
        const Vec3 n = Vec3(north, east, -std::sqrt(kDomeRadius * kDomeRadius - r2)) / kDomeRadius;
        return model(n.dot(p.to_sun_site));
    };
    std::vector<double> err;
    std::vector<double> err_shifted;
    double hottest = 0.0;
    int hot_c = -1, hot_r = -1;
    for (int r = 0; r < p.height_px; ++r) {
        for (int c = 0; c < p.width_px; ++c) {
            const double k = kelvinOfDn(p, img.p16[static_cast<std::size_t>(r * p.width_px + c)]);
            if (k > hottest) {
                hottest = k;
                hot_c = c;
                hot_r = r;
            }
            double north = 0.0, east = 0.0;
            siteOfPixel(p, c, r, north, east);
            double ns = 0.0, es = 0.0;
            siteOfPixel(p, c + 1, r, ns, es);
            if (std::hypot(north, east) < 0.8 * kDomeRadius && std::hypot(ns, es) < 0.8 * kDomeRadius) {
                err.push_back(std::fabs(k - domeT(north, east)));
                err_shifted.push_back(std::fabs(k - domeT(ns, es)));
            }
        }
    }
    ASSERT_GT(err.size(), 1000U);
    std::sort(err.begin(), err.end());
    std::sort(err_shifted.begin(), err_shifted.end());
    const double median = err[err.size() / 2];
    std::printf("dome: %zu pixels, |T - model| median %.4f K, p99 %.4f K; one pixel east: median %.4f K\n", err.size(),
                median, err[err.size() * 99 / 100], err_shifted[err_shifted.size() / 2]);
    EXPECT_LT(median, 0.1);  // kelvin
    EXPECT_LT(err[err.size() * 99 / 100], 0.5);
    EXPECT_GT(err_shifted[err_shifted.size() / 2], 5.0 * median);
    // Hottest pixel: the normal points at the sun, R cos(45 deg) east of the centre.
    const Vec2 expected_hot = orbitalPixelFromSite(orbitalGeoreference(p), 0.0, kDomeRadius * std::sqrt(0.5));
    EXPECT_LE(std::fabs(hot_c - expected_hot.x()), 1.5);
    EXPECT_LE(std::fabs(hot_r - expected_hot.y()), 1.5);
    const auto kelvinAt = [&](double north, double east) {
        const Vec2 px = orbitalPixelFromSite(orbitalGeoreference(p), north, east);
        const auto idx = static_cast<std::size_t>(std::lround(px.y()) * p.width_px + std::lround(px.x()));
        return kelvinOfDn(p, img.p16[idx]);
    };
    for (const double d : {2.0, 4.0, 6.0}) {
        EXPECT_GT(kelvinAt(0.0, d), kelvinAt(0.0, -d) + 10.0) << d;  // sunward flank warmer
    }
    // West of the dome, within its shadow (it reaches R / tan(45 deg) + R... on the plane):
    EXPECT_NEAR(kelvinAt(0.0, -1.2 * kDomeRadius), p.thermal.floor_k, 0.05);
    EXPECT_NEAR(kelvinAt(0.0, 1.2 * kDomeRadius), model(std::sin(45.0 * M_PI / 180.0)), 0.05);
    EXPECT_GT(img.stats.shadowed_subsamples, 100);
}

// Thermal on flat ground with albedo patches: darker is warmer, as the model says, so
// there the thermal image is the visible one turned upside down (rank correlation < -0.95);
// on a Mars world (relief, craters, rocks, texture) slope makes both brighter and
// albedo pulls them apart: correlated, but far from a monotonic remap.
TEST(SimOrbital, ThermalIsWarmerOnDarkGroundAndNotAMonotonicRemapOfVisible) {
    {
        const Terrain& t = buildTerrain(World::kFlatAlbedo, flatAlbedoParams());
        OrbitalParams p = exactParams(OrbitalModality::kThermal, 0.5, 48, 48);
        p.to_sun_site = sunFrom(200.0, 60.0);
        const Image th = render(t, p);
        p.modality = OrbitalModality::kVisible;
        const Image vis = render(t, p);
        std::vector<double> a, b;
        int model_off = 0;
        for (int r = 0; r < p.height_px; ++r) {
            for (int c = 0; c < p.width_px; ++c) {
                const std::size_t i = static_cast<std::size_t>(r * p.width_px + c);
                a.push_back(th.p16[i]);
                b.push_back(vis.p16[i]);
                // One sub-sample's worth of check: the pixel's mean albedo from the visible
                // model, then T from the thermal model (flat: cos i = sin 60 deg).
                const double albedo = (vis.p16[i] / 65535.0 - p.offset_fs) * p.full_scale_reflectance /
                                      (std::sin(60.0 * M_PI / 180.0) + p.ambient);
                const double t_model = std::pow(std::pow(p.thermal.floor_k, 4.0) +
                                                    std::pow(p.thermal.subsolar_k, 4.0) * (1.0 - albedo) *
                                                        std::sin(60.0 * M_PI / 180.0),
                                                0.25);
                model_off += std::fabs(kelvinOfDn(p, th.p16[i]) - t_model) > 0.05 ? 1 : 0;
            }
        }
        std::printf("flat ground: rank correlation thermal/visible %.4f\n", rankCorrelation(a, b));
        EXPECT_LT(rankCorrelation(a, b), -0.95);
        EXPECT_EQ(model_off, 0);
    }
    {
        const Terrain& t = buildTerrain(World::kSmallMars, smallMarsParams());
        OrbitalParams p = exactParams(OrbitalModality::kThermal, 0.25, 64, 64);
        p.to_sun_site = sunFrom(250.0, 40.0);
        const Image th = render(t, p);
        p.modality = OrbitalModality::kVisible;
        const Image vis = render(t, p);
        std::vector<double> a(th.p16.begin(), th.p16.end());
        std::vector<double> b(vis.p16.begin(), vis.p16.end());
        const double rho = rankCorrelation(a, b);
        EXPECT_LT(rho, 0.85);
        EXPECT_GT(rho, -0.5);
        // Pairs of pixels whose order flips between the two views: many.
        int flips = 0;
        int pairs = 0;
        for (std::size_t i = 0; i + 37 < a.size(); i += 3) {
            const double da = a[i] - a[i + 37];
            const double db = b[i] - b[i + 37];
            pairs += 1;
            flips += (da * db < 0.0) ? 1 : 0;
        }
        std::printf("mars world: rank correlation thermal/visible %.4f, order flips %d of %d pairs\n", rho, flips,
                    pairs);
        EXPECT_GT(flips, pairs / 10);
    }
}

// ---- a descent frame in the orbital image -------------------------------------------

double ncc(const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0.0, mb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ma += a[i];
        mb += b[i];
    }
    ma /= static_cast<double>(a.size());
    mb /= static_cast<double>(b.size());
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

// A nadir camera frame (the camera renderer) and a visible orbital view under the same
// sun: each camera pixel's true site point, through the orbital georeference, lands on
// orbital pixels that look the same (bilinear NCC > 0.9); moved by 2 orbital pixels in
// any direction the agreement drops.
TEST(SimOrbital, DescentFramePixelsLandOnTheirOrbitalPixelsThroughTheTruth) {
    const Terrain& t = buildTerrain(World::kSmallMars, smallMarsParams());
    constexpr std::int32_t kCam = 96;
    const Vec3 sun = sunFrom(120.0, 35.0);
    const double ground = t.elevationAt(1.0, -2.0);
    FrameRequest r;
    r.terrain = &t;
    r.model = makePinhole(kCam, kCam, 45.0);
    // 60 m up: 50 m of ground, ~0.52 m per pixel.
    r.pose = poseLookingAt(Vec3(1.0, -2.0, -(ground + 60.0)), Vec3(1.0, -2.0, -ground));
    r.lighting.to_sun_site = sun;
    r.lighting.shadows = true;
    r.sensor.bit_depth = 12;
    r.sensor.shot_noise = false;
    r.sensor.read_noise_e = 0.0;
    r.sensor.vignetting = 0.0;
    std::vector<std::uint16_t> cam(kCam * kCam);
    std::vector<float> points(3 * kCam * kCam);
    FrameOutput fo;
    fo.image16 = ImageView<std::uint16_t>(cam.data(), kCam, kCam);
    fo.truth.point_site_m = ImageView<float>(points.data(), 3 * kCam, kCam);
    ASSERT_TRUE(renderFrame(r, fo, nullptr).isOk());

    OrbitalParams p = exactParams(OrbitalModality::kVisible, 0.5, 128, 128);
    p.centre_north_m = 3.0;  // not centred on the camera: the georeference does the work
    p.centre_east_m = 1.0;
    p.to_sun_site = sun;
    const Image orb = render(t, p);
    const OrbitalGeoreference geo = orbitalGeoreference(p);
    const auto sample = [&](double x, double y) {
        const int x0 = static_cast<int>(std::floor(x));
        const int y0 = static_cast<int>(std::floor(y));
        const double fx = x - x0, fy = y - y0;
        const auto at = [&](int xx, int yy) { return static_cast<double>(orb.p16[static_cast<std::size_t>(yy * p.width_px + xx)]); };
        return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
    };
    const auto score = [&](double dx, double dy) {
        std::vector<double> a, b;
        for (int i = 0; i < kCam * kCam; ++i) {
            const Vec2 px = orbitalPixelFromSite(geo, points[3 * i], points[3 * i + 1]);
            a.push_back(cam[static_cast<std::size_t>(i)]);
            b.push_back(sample(px.x() + dx, px.y() + dy));
        }
        return ncc(a, b);
    };
    const double at_truth = score(0.0, 0.0);
    std::printf("descent->orbital NCC at truth %.4f; shifted 2 px: %.4f %.4f %.4f %.4f\n", at_truth, score(2, 0),
                score(-2, 0), score(0, 2), score(0, -2));
    EXPECT_GT(at_truth, 0.9);
    for (const auto& d : {Vec2(2, 0), Vec2(-2, 0), Vec2(0, 2), Vec2(0, -2)}) {
        EXPECT_LT(score(d.x(), d.y()), at_truth - 0.1) << d.transpose();
    }
}

// ---- determinism, bands, heap, errors -----------------------------------------------

TEST(SimOrbital, SameInputsGiveSameBytesBandsMatchAndTheSeedOnlyChangesNoise) {
    const Terrain& t = buildTerrain(World::kSmallMars, smallMarsParams());
    OrbitalParams p;
    p.modality = OrbitalModality::kThermal;
    p.cell_m = 0.5;
    p.width_px = 40;
    p.height_px = 30;
    p.noise_fs = 0.01;
    const Image a = render(t, p);
    const Image b = render(t, p);
    EXPECT_EQ(a.p8, b.p8);
    Image bands;
    const OrbitalOutput out = views(p, bands);
    for (const auto& band : {std::pair<int, int>{20, -1}, {7, 13}, {0, 7}}) {
        p.first_row = band.first;
        p.row_count = band.second;
        ASSERT_TRUE(renderOrbital(t, p, out, nullptr).isOk());
    }
    EXPECT_EQ(a.p8, bands.p8);
    p.first_row = 0;
    p.row_count = -1;
    p.noise_seed = 2U;
    const Image c = render(t, p);
    EXPECT_NE(a.p8, c.p8);
    int far = 0;
    for (std::size_t i = 0; i < a.p8.size(); ++i) far += std::abs(a.p8[i] - c.p8[i]) > 20 ? 1 : 0;
    EXPECT_EQ(far, 0);  // noise sigma 2.55 DN, of a difference 3.6: > 5.5 sigma never in 1200
}

TEST(SimOrbital, RenderOrbitalTouchesNoHeap) {
    const Terrain& t = buildTerrain(World::kSmallMars, smallMarsParams());
    OrbitalParams p;
    p.modality = OrbitalModality::kThermal;
    p.cell_m = 0.5;
    p.width_px = 32;
    p.height_px = 24;
    static std::uint8_t image[32 * 24];
    static float elevation[32 * 24];
    OrbitalOutput out;
    out.image8 = ImageView<std::uint8_t>(image, 32, 24);
    out.elevation_m = ImageView<float>(elevation, 32, 24);
    test::NoHeapScope guard;
    EXPECT_TRUE(renderOrbital(t, p, out, nullptr).isOk());
    p.modality = OrbitalModality::kVisible;
    EXPECT_TRUE(renderOrbital(t, p, out, nullptr).isOk());
    EXPECT_EQ(guard.heapCalls(), 0U);
}

TEST(SimOrbital, BadParamsAreRejectedNamingTheField) {
    const Terrain& t = buildTerrain(World::kFlatAlbedo, flatAlbedoParams());
    OrbitalParams good;
    good.width_px = 8;
    good.height_px = 8;
    Image img;
    const OrbitalOutput out = views(good, img);
    ASSERT_TRUE(renderOrbital(t, good, out, nullptr).isOk());
    struct Case {
        void (*spoil)(OrbitalParams&);
        const char* field;
    };
    const Case cases[] = {
        {[](OrbitalParams& p) { p.cell_m = 0.0; }, "orbital.cell_m"},
        {[](OrbitalParams& p) { p.cell_m = std::nan(""); }, "orbital.cell_m"},
        {[](OrbitalParams& p) { p.centre_east_m = INFINITY; }, "orbital.centre_north_m/centre_east_m"},
        {[](OrbitalParams& p) { p.width_px = 0; }, "orbital.width_px"},
        {[](OrbitalParams& p) { p.height_px = 5000; }, "orbital.height_px"},
        {[](OrbitalParams& p) { p.subsamples = 5; }, "orbital.subsamples"},
        {[](OrbitalParams& p) { p.first_row = 8; }, "orbital.first_row/row_count"},
        {[](OrbitalParams& p) { p.row_count = 9; }, "orbital.first_row/row_count"},
        {[](OrbitalParams& p) { p.to_sun_site = Vec3(0.0, 0.0, 1.0); }, "orbital.to_sun_site"},
        {[](OrbitalParams& p) { p.to_sun_site = Vec3(0.0, 0.0, -2.0); }, "orbital.to_sun_site"},
        {[](OrbitalParams& p) { p.max_shadow_range_m = -1.0; }, "orbital.max_shadow_range_m"},
        {[](OrbitalParams& p) { p.ambient = -0.1; }, "orbital.ambient"},
        {[](OrbitalParams& p) { p.full_scale_reflectance = 0.0; }, "orbital.full_scale_reflectance"},
        {[](OrbitalParams& p) { p.modality = static_cast<OrbitalModality>(7); }, "orbital.modality"},
        {[](OrbitalParams& p) { p.thermal.floor_k = 0.0; }, "orbital.thermal.floor_k"},
        {[](OrbitalParams& p) { p.thermal.subsolar_k = 150.0; }, "orbital.thermal.subsolar_k"},
        {[](OrbitalParams& p) { p.thermal.scale_min_k = -1.0; }, "orbital.thermal.scale_min_k"},
        {[](OrbitalParams& p) { p.thermal.scale_max_k = 100.0; }, "orbital.thermal.scale_max_k"},
        {[](OrbitalParams& p) { p.bit_depth = 12; }, "orbital.bit_depth"},
        {[](OrbitalParams& p) { p.offset_fs = 1.5; }, "orbital.offset_fs"},
        {[](OrbitalParams& p) { p.noise_fs = -0.1; }, "orbital.noise_fs"},
    };
    for (const Case& c : cases) {
        OrbitalParams p = good;
        c.spoil(p);
        const Status s = renderOrbital(t, p, out, nullptr);
        EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << c.field;
        EXPECT_EQ(std::string(s.reason()).rfind(std::string(c.field) + ":", 0), 0U) << c.field << " -> " << s.reason();
        EXPECT_FALSE(validateOrbitalParams(p).isOk()) << c.field;
    }
    OrbitalOutput wrong = out;
    wrong.image8 = ImageView<std::uint8_t>(img.p8.data(), 7, 8);
    EXPECT_EQ(renderOrbital(t, good, wrong, nullptr).code(), StatusCode::kSizeMismatch);
    wrong = out;
    wrong.elevation_m = ImageView<float>(img.elevation.data(), 8, 7);
    EXPECT_EQ(renderOrbital(t, good, wrong, nullptr).code(), StatusCode::kSizeMismatch);
    OrbitalParams sixteen = good;
    sixteen.bit_depth = 16;
    wrong = out;
    wrong.image16 = ImageView<std::uint16_t>();
    EXPECT_EQ(renderOrbital(t, sixteen, wrong, nullptr).code(), StatusCode::kSizeMismatch);
    const Terrain unbuilt;
    EXPECT_EQ(renderOrbital(unbuilt, good, out, nullptr).code(), StatusCode::kInvalidArgument);
}

// ---- the scenario's [orbital] section ------------------------------------------------

constexpr const char* kDescent =
    "name d\nkind descent\nseed 9\n"               // lines 1-3
    "[camera]\nmodel pinhole\nwidth_px 64\nheight_px 64\nhfov_deg 45\n"  // 4-8
    "[motion]\nstart_m 10 -20\n";                  // 9-10

TEST(ScenarioOrbital, EveryKeySetsItsFieldAndTheImageFollowsTheScenario) {
    const std::string text = std::string(kDescent) +
                             "[orbital]\nmodality visible\ncell_m 0.75\nwidth_px 300\nheight_px 200\nsubsamples 3\n"
                             "centre_offset_m 5 -7\nsun_azimuth_deg 270\nsun_elevation_deg 20\nbit_depth 16\n"
                             "shadows false\nnoise_fs 0.01\nnoise_seed 77\nambient 0.2\nthermal_floor_k 150\n"
                             "thermal_subsolar_k 320\n";
    Scenario s;
    const Status st = parseScenario(text, s);
    ASSERT_TRUE(st.isOk()) << st.reason() << " line " << st.detail();
    ASSERT_TRUE(s.orbital.enabled);
    const OrbitalParams p = scenarioOrbitalParams(s);
    EXPECT_EQ(p.modality, OrbitalModality::kVisible);
    EXPECT_DOUBLE_EQ(p.cell_m, 0.75);
    EXPECT_EQ(p.width_px, 300);
    EXPECT_EQ(p.height_px, 200);
    EXPECT_EQ(p.subsamples, 3);
    EXPECT_DOUBLE_EQ(p.centre_north_m, 15.0);  // motion.start_m + centre_offset_m
    EXPECT_DOUBLE_EQ(p.centre_east_m, -27.0);
    EXPECT_NEAR(p.to_sun_site.x(), 0.0, 1e-12);  // azimuth 270: towards the west
    EXPECT_NEAR(p.to_sun_site.y(), -std::cos(20.0 * M_PI / 180.0), 1e-12);
    EXPECT_NEAR(p.to_sun_site.z(), -std::sin(20.0 * M_PI / 180.0), 1e-12);
    EXPECT_EQ(p.bit_depth, 16);
    EXPECT_FALSE(p.shadows);
    EXPECT_DOUBLE_EQ(p.noise_fs, 0.01);
    EXPECT_EQ(p.noise_seed, 77U);
    EXPECT_DOUBLE_EQ(p.ambient, 0.2);
    EXPECT_DOUBLE_EQ(p.thermal.floor_k, 150.0);
    EXPECT_DOUBLE_EQ(p.thermal.subsolar_k, 320.0);
    EXPECT_DOUBLE_EQ(p.thermal.scale_min_k, 140.0);
    EXPECT_DOUBLE_EQ(p.thermal.scale_max_k, 320.0);
    // No [orbital]: off. An empty [orbital]: the documented defaults, seed derived.
    Scenario none;
    ASSERT_TRUE(parseScenario(kDescent, none).isOk());
    EXPECT_FALSE(none.orbital.enabled);
    Scenario empty;
    ASSERT_TRUE(parseScenario(std::string(kDescent) + "[orbital]\n", empty).isOk());
    EXPECT_TRUE(empty.orbital.enabled);
    const OrbitalParams d = scenarioOrbitalParams(empty);
    EXPECT_EQ(d.modality, OrbitalModality::kThermal);
    EXPECT_DOUBLE_EQ(d.cell_m, 1.0);
    EXPECT_EQ(d.width_px, 512);
    EXPECT_EQ(d.bit_depth, 8);
    EXPECT_NE(d.noise_seed, empty.sensor.noise_seed);
    EXPECT_NE(d.noise_seed, empty.terrain.seed);
}

TEST(ScenarioOrbital, EveryBadValueIsNamedWithItsLine) {
    struct Case {
        const char* appended;  // after kDescent + "[orbital]\n" (line 11); the key is line 12
        StatusCode code;
        const char* reason_part;
        std::int32_t line;
    };
    const Case cases[] = {
        {"cell_m 0\n", StatusCode::kInvalidConfig, "orbital.cell_m is out of range", 12},
        {"cell_m one\n", StatusCode::kCorruptData, "orbital.cell_m has a bad value", 12},
        {"width_px 8\n", StatusCode::kInvalidConfig, "orbital.width_px is out of range", 12},
        {"width_px 1.5\n", StatusCode::kCorruptData, "orbital.width_px has a bad value", 12},
        {"height_px 5000\n", StatusCode::kInvalidConfig, "orbital.height_px is out of range", 12},
        {"subsamples 0\n", StatusCode::kInvalidConfig, "orbital.subsamples is out of range", 12},
        {"centre_offset_m 3\n", StatusCode::kCorruptData, "orbital.centre_offset_m has a bad value", 12},
        {"centre_offset_m 0 2e6\n", StatusCode::kInvalidConfig, "orbital.centre_offset_m is out of range", 12},
        {"sun_azimuth_deg 400\n", StatusCode::kInvalidConfig, "orbital.sun_azimuth_deg is out of range", 12},
        {"sun_elevation_deg 0\n", StatusCode::kInvalidConfig, "orbital.sun_elevation_deg is out of range", 12},
        {"sun_elevation_deg inf\n", StatusCode::kCorruptData, "orbital.sun_elevation_deg has a bad value", 12},
        {"modality infrared\n", StatusCode::kCorruptData, "orbital.modality has a bad value", 12},
        {"bit_depth 32\n", StatusCode::kInvalidConfig, "orbital.bit_depth is out of range", 12},
        {"bit_depth 12\n", StatusCode::kInvalidConfig, "orbital.bit_depth must be 8 or 16", 0},
        {"shadows yes\n", StatusCode::kCorruptData, "orbital.shadows has a bad value", 12},
        {"noise_fs 0.9\n", StatusCode::kInvalidConfig, "orbital.noise_fs is out of range", 12},
        {"noise_seed -3\n", StatusCode::kCorruptData, "orbital.noise_seed has a bad value", 12},
        {"ambient -1\n", StatusCode::kInvalidConfig, "orbital.ambient is out of range", 12},
        {"thermal_floor_k 0\n", StatusCode::kInvalidConfig, "orbital.thermal_floor_k is out of range", 12},
        {"thermal_subsolar_k 3000\n", StatusCode::kInvalidConfig, "orbital.thermal_subsolar_k is out of range", 12},
        {"thermal_subsolar_k 170\n", StatusCode::kInvalidConfig,
         "orbital.thermal_subsolar_k must exceed orbital.thermal_floor_k", 0},
        {"cell_m 1\ncell_m 2\n", StatusCode::kCorruptData, "orbital.cell_m given twice", 13},
        {"colour red\n", StatusCode::kCorruptData, "unknown key in [orbital]", 12},
        {"[orbital]\n", StatusCode::kCorruptData, "[orbital] given twice", 12},
    };
    for (const Case& c : cases) {
        Scenario s;
        const Status st = parseScenario(std::string(kDescent) + "[orbital]\n" + c.appended, s);
        EXPECT_EQ(st.code(), c.code) << c.appended << " -> " << st.reason();
        EXPECT_NE(std::string(st.reason()).find(c.reason_part), std::string::npos) << c.appended << " -> " << st.reason();
        EXPECT_EQ(st.detail(), c.line) << c.appended;
    }
    // [orbital] in a rover scenario: named, at the section's line.
    const char* rover = "name r\nkind rover_pair\nseed 1\n[camera]\nmodel pinhole\nwidth_px 64\nheight_px 64\nhfov_deg 45\n"
                        "[orbital]\n";
    Scenario s;
    const Status st = parseScenario(rover, s);
    EXPECT_EQ(st.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::string(st.reason()).find("[orbital] belongs to descent scenarios only"), std::string::npos)
        << st.reason();
    EXPECT_EQ(st.detail(), 9);
    // A code-built scenario is checked the same way.
    Scenario built;
    ASSERT_TRUE(parseScenario(std::string(kDescent) + "[orbital]\n", built).isOk());
    built.orbital.bit_depth = 10;
    EXPECT_EQ(validateScenario(built).code(), StatusCode::kInvalidConfig);
    built.orbital.bit_depth = 8;
    built.orbital.cell_m = -1.0;
    EXPECT_NE(std::string(validateScenario(built).reason()).find("orbital.cell_m"), std::string::npos);
}

}  // namespace
}  // namespace vtm::sim
