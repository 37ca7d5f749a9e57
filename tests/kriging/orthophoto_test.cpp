// The orthophoto of the simulator's Mars terrain from three rendered nadir images: grey
// values against the radiometric truth at each node, the grey and height steps across the
// borders between source images against the steps within one source, refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "kriging_fixtures.hpp"
#include "no_heap_guard.hpp"
#include "sim/render.hpp"
#include "sim_scene.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/kriging/orthophoto.hpp"

namespace vtm::kriging {
namespace {

constexpr double kEyeUpM = 4.0;
constexpr double kHfovDeg = 70.0;
constexpr std::int32_t kWidth = 128;
constexpr std::int32_t kHeight = 96;
const double kStationEastM[3] = {-1.6, 0.0, 1.6};

terrain::GridConfig orthoGrid() {
    terrain::GridConfig g;
    g.north_edge_m = 1.6;
    g.west_edge_m = -2.56;
    g.cell_m = 0.08;
    g.cols = 64;
    g.rows = 40;
    return g;
}

struct Scene {
    std::vector<NetworkStation> stations;
    std::vector<std::vector<std::uint8_t>> pixels;
    std::vector<StationImages> images;
};

// Three nadir stations 1.6 m apart along east, 4 m up; left eyes rendered, right eyes empty.
const Scene& scene() {
    static const Scene s = [] {
        Scene q;
        const sim::Terrain& terrain = test::smallMarsTerrain();
        const CameraModel model = makePinhole(kWidth, kHeight, kHfovDeg);
        q.pixels.resize(3);
        for (int i = 0; i < 3; ++i) {
            NetworkStation st;
            st.rig.model_a = model;
            st.rig.model_b = model;
            st.rig.b_from_a.t_m = Vec3(-0.3, 0.0, 0.0);
            const Vec3 eye(0.0, kStationEastM[i], -kEyeUpM);
            st.site_from_a = sim::poseLookingAt(eye, eye + Vec3(0.0, 0.0, 100.0));
            q.stations.push_back(st);
            q.pixels[static_cast<std::size_t>(i)].assign(static_cast<std::size_t>(kWidth * kHeight), 0U);
            sim::FrameRequest r;
            r.terrain = &terrain;
            r.model = model;
            r.pose = st.site_from_a;
            r.lighting = test::plainLighting();
            r.sensor = test::plainSensor();
            r.frame_index = static_cast<std::uint32_t>(i);
            sim::FrameOutput out;
            out.image8 = ImageView<std::uint8_t>(q.pixels[static_cast<std::size_t>(i)].data(), kWidth, kHeight);
            const Status rendered = sim::renderFrame(r, out, nullptr);
            EXPECT_TRUE(rendered.isOk()) << rendered.reason();
        }
        for (int i = 0; i < 3; ++i) {
            StationImages im;
            im.left = ImageView<const std::uint8_t>(q.pixels[static_cast<std::size_t>(i)].data(), kWidth, kHeight);
            q.images.push_back(im);
        }
        return q;
    }();
    return s;
}

// The grey a nadir pixel centred on the node records (the renderer's Lambertian model,
// no noise, no vignetting, no shadows), at the images' pixel footprint.
double trueGrey(const sim::Terrain& terrain, double n, double e) {
    const double footprint_m = kEyeUpM * (kHfovDeg * 3.141592653589793 / 180.0) / kWidth;
    const sim::Lighting l = test::plainLighting();
    const sim::SensorParams s = test::plainSensor();
    const double albedo = terrain.albedoAt(n, e, footprint_m);
    const Vec3 normal = terrain.shadingNormal(n, e, footprint_m);
    const double cos_sun = std::max(0.0, normal.dot(l.to_sun_site));
    const double radiance = albedo / 3.141592653589793 * (l.sun_irradiance * cos_sun + l.sky_irradiance);
    return std::min(255.0, std::floor(s.dark_offset_dn + s.gain_dn_per_e * radiance * s.exposure_s + 0.5));
}

struct Ortho {
    std::vector<std::uint8_t> grey;
    std::vector<std::uint16_t> source;
    OrthophotoStats stats;
};

// The orthophoto of the scene's images over an elevation grid; `stations` replaces the
// scene's poses when given (a planted misregistration).
Ortho ortho(const std::vector<float>& elevation, const std::vector<NetworkStation>* stations = nullptr) {
    const terrain::GridConfig g = orthoGrid();
    Ortho o;
    o.grey.assign(static_cast<std::size_t>(g.cols * g.rows), 0U);
    o.source.assign(o.grey.size(), 0U);
    const Scene& s = scene();
    const std::vector<NetworkStation>& used = stations != nullptr ? *stations : s.stations;
    vtm::test::NoHeapScope guard;
    const Status st = buildOrthophoto(OrthophotoConfig{}, g, Span<const float>(elevation.data(), elevation.size()),
                                      Span<const NetworkStation>(used.data(), used.size()),
                                      Span<const StationImages>(s.images.data(), s.images.size()),
                                      ImageView<std::uint8_t>(o.grey.data(), g.cols, g.rows),
                                      ImageView<std::uint16_t>(o.source.data(), g.cols, g.rows), &o.stats);
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_TRUE(st.isOk()) << st.reason();
    return o;
}

template <typename Elevation>
std::vector<float> elevationGrid(const Elevation& elevation) {
    const terrain::GridConfig g = orthoGrid();
    std::vector<float> z;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            z.push_back(static_cast<float>(elevation(g.north_edge_m - (row + 0.5) * g.cell_m,
                                                     g.west_edge_m + (col + 0.5) * g.cell_m)));
        }
    }
    return z;
}

// Mean |difference of neighbouring nodes - the truth's difference| over neighbour pairs
// whose sources differ (across a border) and over pairs of one source (within).
struct Steps {
    double across = 0.0;
    double within = 0.0;
    int across_pairs = 0;
};

template <typename Value, typename Truth>
Steps steps(const std::vector<std::uint16_t>& source, const Value& value, const Truth& truth) {
    const terrain::GridConfig g = orthoGrid();
    Steps s;
    double sa = 0.0, sw = 0.0;
    int nw = 0;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col + 1 < g.cols; ++col) {
            const auto k = static_cast<std::size_t>(row * g.cols + col);
            const double d = std::fabs((value(k + 1) - value(k)) - (truth(k + 1) - truth(k)));
            if (source[k] != source[k + 1]) {
                sa += d;
                ++s.across_pairs;
            } else {
                sw += d;
                ++nw;
            }
        }
    }
    s.across = sa / std::max(1, s.across_pairs);
    s.within = sw / std::max(1, nw);
    return s;
}

TEST(Orthophoto, GreyValuesMatchTheTruthAndBordersShowNoSeam) {
    const sim::Terrain& terrain = test::smallMarsTerrain();
    const terrain::GridConfig g = orthoGrid();
    const auto true_z = elevationGrid([&terrain](double n, double e) { return terrain.elevationAt(n, e); });
    const Ortho o = ortho(true_z);
    EXPECT_EQ(o.stats.filled, g.cols * g.rows);
    const Ortho again = ortho(true_z);  // same bits twice
    EXPECT_EQ(again.grey, o.grey);
    EXPECT_EQ(again.source, o.source);
    std::vector<double> truth;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            truth.push_back(trueGrey(terrain, g.north_edge_m - (row + 0.5) * g.cell_m,
                                     g.west_edge_m + (col + 0.5) * g.cell_m));
        }
    }
    double err = 0.0;
    for (std::size_t k = 0; k < truth.size(); ++k) {
        err += std::fabs(o.grey[k] - truth[k]);
    }
    err /= static_cast<double>(truth.size());
    // The control: the same images draped on a level plane 0.4 m below the mean ground.
    double mean_z = 0.0;
    for (const float z : true_z) {
        mean_z += z;
    }
    mean_z /= static_cast<double>(true_z.size());
    const Ortho flat = ortho(std::vector<float>(true_z.size(), static_cast<float>(mean_z - 0.4)));
    double flat_err = 0.0;
    for (std::size_t k = 0; k < truth.size(); ++k) {
        flat_err += std::fabs(flat.grey[k] - truth[k]);
    }
    flat_err /= static_cast<double>(truth.size());
    // Sources: each node from the station nearest above it (nadir views of one height).
    for (std::int32_t col = 0; col < g.cols; ++col) {
        const double east = g.west_edge_m + (col + 0.5) * g.cell_m;
        const std::uint16_t expected = east < -1.0 ? 0U : (east > 1.0 ? 4U : (std::fabs(east) < 0.6 ? 2U : 0xFFFEU));
        if (expected != 0xFFFEU) {
            EXPECT_EQ(o.source[static_cast<std::size_t>(20 * g.cols + col)], expected) << col;
        }
    }
    const Steps grey_steps = steps(
        o.source, [&o](std::size_t k) { return static_cast<double>(o.grey[k]); },
        [&truth](std::size_t k) { return truth[k]; });
    std::printf("orthophoto from the true elevation: mean |grey - truth| %.2f DN (draped on a wrong plane: %.2f DN); "
                "grey step error across source borders %.2f DN (%d pairs), within one source %.2f DN\n",
                err, flat_err, grey_steps.across, grey_steps.across_pairs, grey_steps.within);
    EXPECT_GT(grey_steps.across_pairs, 2 * g.rows - 1);  // two borders cross every row
    EXPECT_LT(err, 0.5 * flat_err);
    // No seam: the step error across borders is the step error within one source (the
    // texture's own interpolation error) to 15 % and half a DN.
    const auto noSeam = [](const Steps& st) { return st.across <= 1.15 * st.within + 0.5; };
    EXPECT_TRUE(noSeam(grey_steps));
    // The measure sees a seam when there is one: the middle station's attitude 1 degree off
    // (about north) shifts its part of the orthophoto by 7 cm against its neighbours'.
    std::vector<NetworkStation> tilted = scene().stations;
    const double a = 1.0 * 3.141592653589793 / 180.0;
    Mat3 rx;
    rx << 1.0, 0.0, 0.0, 0.0, std::cos(a), -std::sin(a), 0.0, std::sin(a), std::cos(a);
    tilted[1].site_from_a.R = rx * tilted[1].site_from_a.R;
    const Ortho seam = ortho(true_z, &tilted);
    const Steps seam_steps = steps(
        seam.source, [&seam](std::size_t k) { return static_cast<double>(seam.grey[k]); },
        [&truth](std::size_t k) { return truth[k]; });
    std::printf("planted seam (middle station 1 deg off): grey step error across borders %.2f DN, within %.2f DN\n",
                seam_steps.across, seam_steps.within);
    EXPECT_FALSE(noSeam(seam_steps));
}

// Elevation samples as three stereo stations would give them: each station's footprint,
// each with its own bias (0, +1 cm, -1 cm); kriged together; the height step across the
// orthophoto's source borders against the truth.
TEST(Orthophoto, KrigedElevationFromBiasedStationsShowsNoHeightSeamAtTheBorders) {
    const sim::Terrain& terrain = test::smallMarsTerrain();
    const terrain::GridConfig g = orthoGrid();
    const double bias_m[3] = {0.0, 0.01, -0.01};
    std::vector<Vec3> samples;
    for (int i = 0; i < 3; ++i) {
        Random r(100U + static_cast<std::uint64_t>(i));
        for (int k = 0; k < 700; ++k) {
            const double n = -2.0 + 4.0 * r.uniform01();
            const double e = kStationEastM[i] - 2.4 + 4.8 * r.uniform01();
            samples.emplace_back(n, e, -(terrain.elevationAt(n, e) + bias_m[i]));
        }
    }
    KrigingConfig config;
    config.grid = g;
    config.neighbours = 12;
    config.search_radius_m = 1.0;
    config.variogram_max_lag_m = 2.5;
    config.variogram_bins = 20;
    test::Kriger k(config);
    ASSERT_TRUE(k.kriging.setSamples(Span<const Vec3>(samples.data(), samples.size())).isOk());
    Variogram v;
    ASSERT_TRUE(k.kriging.fitVariogram(v).isOk());
    ASSERT_TRUE(k.kriging.krigeGrid(v).isOk());
    const Span<const float> kz = k.kriging.map().elevations();
    const std::vector<float> kriged(kz.begin(), kz.end());
    const auto true_z = elevationGrid([&terrain](double n, double e) { return terrain.elevationAt(n, e); });
    const Ortho o = ortho(kriged);
    EXPECT_EQ(o.stats.filled, g.cols * g.rows);
    const Steps h = steps(
        o.source, [&kriged](std::size_t i) { return static_cast<double>(kriged[i]); },
        [&true_z](std::size_t i) { return static_cast<double>(true_z[i]); });
    double rms = 0.0;
    for (std::size_t i = 0; i < kriged.size(); ++i) {
        rms += (kriged[i] - true_z[i]) * (kriged[i] - true_z[i]);
    }
    rms = std::sqrt(rms / static_cast<double>(kriged.size()));
    // The peer without blending: each node from its own source station's samples only.
    std::vector<float> unblended(kriged.size(), 0.0F);
    for (int i = 0; i < 3; ++i) {
        test::Kriger one(config);
        ASSERT_TRUE(one.kriging.setSamples(Span<const Vec3>(samples.data() + 700 * i, 700)).isOk());
        Variogram vi;
        ASSERT_TRUE(one.kriging.fitVariogram(vi).isOk());
        ASSERT_TRUE(one.kriging.krigeGrid(vi).isOk());
        for (std::size_t n = 0; n < kriged.size(); ++n) {
            if (o.source[n] == 2 * i) {
                unblended[n] = one.kriging.map().elevations()[n];
            }
        }
    }
    const Steps u = steps(
        o.source, [&unblended](std::size_t i) { return static_cast<double>(unblended[i]); },
        [&true_z](std::size_t i) { return static_cast<double>(true_z[i]); });
    std::printf("kriged from three biased stations: RMS %.4f m; height step error across source borders %.4f m "
                "(%d pairs), within one source %.4f m; each station kriged alone: across %.4f m, within %.4f m "
                "(bias jump between stations 0.01 m)\n",
                rms, h.across, h.across_pairs, h.within, u.across, u.within);
    // No seam: across borders as within one source to 25 % and 1 mm; the same measure sees
    // the jump where the stations are not kriged together.
    const auto noSeam = [](const Steps& st) { return st.across <= 1.25 * st.within + 0.001; };
    EXPECT_TRUE(noSeam(h));
    EXPECT_FALSE(noSeam(u));
}

TEST(Orthophoto, RefusalsAreNamedAndNothingIsWritten) {
    const Scene& s = scene();
    const terrain::GridConfig g = orthoGrid();
    std::vector<float> z(static_cast<std::size_t>(g.cols * g.rows), 0.0F);
    std::vector<std::uint8_t> grey(z.size(), 7U);
    std::vector<std::uint16_t> src(z.size(), 7U);
    const ImageView<std::uint8_t> gv(grey.data(), g.cols, g.rows);
    const ImageView<std::uint16_t> sv(src.data(), g.cols, g.rows);
    const Span<const NetworkStation> st(s.stations.data(), s.stations.size());
    const Span<const StationImages> im(s.images.data(), s.images.size());
    const Span<const float> zs(z.data(), z.size());
    EXPECT_EQ(buildOrthophoto(OrthophotoConfig{}, g, Span<const float>(z.data(), 10), st, im, gv, sv).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(buildOrthophoto(OrthophotoConfig{}, g, zs, st, Span<const StationImages>(im.data(), 2), gv, sv).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(buildOrthophoto(OrthophotoConfig{}, g, zs, st, im, ImageView<std::uint8_t>(grey.data(), g.cols - 1, g.rows), sv).code(),
              StatusCode::kSizeMismatch);
    std::vector<StationImages> wrong(s.images);
    wrong[1].right = ImageView<const std::uint8_t>(s.pixels[0].data(), kWidth / 2, kHeight);
    const Status ws = buildOrthophoto(OrthophotoConfig{}, g, zs, st, Span<const StationImages>(wrong.data(), wrong.size()), gv, sv);
    EXPECT_EQ(ws.code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(ws.detail(), 3);  // station 1, right eye
    OrthophotoConfig bad_config;
    bad_config.occlusion_margin_m = -1.0;
    const Status cs = buildOrthophoto(bad_config, g, zs, st, im, gv, sv);
    EXPECT_EQ(cs.code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::strstr(cs.reason(), "occlusion_margin_m"), nullptr);
    std::vector<NetworkStation> bent(s.stations);
    bent[2].site_from_a.R(0, 0) = 2.0;
    const Status bs = buildOrthophoto(OrthophotoConfig{}, g, zs, Span<const NetworkStation>(bent.data(), bent.size()), im, gv, sv);
    EXPECT_EQ(bs.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(bs.detail(), 2);
    EXPECT_NE(std::strstr(bs.reason(), "station"), nullptr);
    for (std::size_t k = 0; k < grey.size(); ++k) {
        ASSERT_EQ(grey[k], 7U);
        ASSERT_EQ(src[k], 7U);
    }
    // NO_DATA elevations give no grey and no source; a node beyond every image likewise.
    z[0] = terrain::kNoData;
    terrain::GridConfig far = g;
    far.west_edge_m = 40.0;
    OrthophotoStats stats;
    ASSERT_TRUE(buildOrthophoto(OrthophotoConfig{}, g, zs, st, im, gv, sv, &stats).isOk());
    EXPECT_EQ(stats.no_elevation, 1);
    EXPECT_EQ(src[0], kNoSource);
    EXPECT_EQ(grey[0], 0U);
    ASSERT_TRUE(buildOrthophoto(OrthophotoConfig{}, far, zs, st, im, gv, sv, &stats).isOk());
    EXPECT_EQ(stats.not_seen, g.cols * g.rows - 1);
}

}  // namespace
}  // namespace vtm::kriging

namespace vtm::kriging {
namespace {

// measureSeamSteps on a 4 x 2 orthophoto worked out by hand: row 0 sources 0 0 1 1 with
// grey 10 14 30 26 (within: |10-14| = 4 and |30-26| = 4; across: |14-30| = 16); row 1
// sources 0 NONE 1 1 with grey 50 0 50 53 (within |50-53| = 3; the pairs beside the node
// without a source are left out).
TEST(OrthophotoSeams, StepsAcrossBordersAndWithinOneSourceByHand) {
    std::uint8_t grey[8] = {10, 14, 30, 26, 50, 0, 50, 53};
    std::uint16_t source[8] = {0, 0, 1, 1, 0, kNoSource, 1, 1};
    const SeamSteps s = measureSeamSteps(ImageView<const std::uint8_t>(grey, 4, 2),
                                         ImageView<const std::uint16_t>(source, 4, 2));
    EXPECT_EQ(s.within_pairs, 3);
    EXPECT_EQ(s.across_pairs, 1);
    EXPECT_DOUBLE_EQ(s.within_dn, 11.0 / 3.0);
    EXPECT_DOUBLE_EQ(s.across_dn, 16.0);
    EXPECT_DOUBLE_EQ(s.ratio(), 16.0 / (11.0 / 3.0));
    // Views of different sizes: no pairs, ratio 0.
    const SeamSteps none = measureSeamSteps(ImageView<const std::uint8_t>(grey, 4, 2),
                                            ImageView<const std::uint16_t>(source, 2, 4));
    EXPECT_EQ(none.within_pairs + none.across_pairs, 0);
    EXPECT_EQ(none.ratio(), 0.0);
}

}  // namespace
}  // namespace vtm::kriging
