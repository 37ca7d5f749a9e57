// The panorama chain on rendered images against the truth (issue 23 item 5): the simulated
// Navcam panorama (sim/scenarios/panorama.scn, its images rendered at 512 x 512 here to keep
// CI short; VTM_EVAL_FULL=1 adds other seeds and sun angles), tie points from the images
// (fsw/tiepoints, each tier a closed ring), the bundle adjustment of all stations with their
// pointing priors (fsw/bundle). Measured against the simulator's truth: image RMS before and
// after, the tie points' ground positions before and after by distance band, the stations'
// relative rotations between neighbours, and how many tie points were wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "panorama_world.hpp"
#include "scenario_text.hpp"
#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"
#include "vtm/core/rotation.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"
#include "vtm/kriging/orthophoto.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

using World = test::PanoramaWorld;

std::string scenarioText() {
    std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/panorama.scn", std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

bool buildWorld(const std::string& text, World& w) { return test::buildPanoramaWorld(text, w, -1, true); }

// The true ground point of a left-eye pixel from the rendered range (nearest pixel; none on
// sky or at a depth edge, where the four neighbours differ by more than 2 %).
bool trueGround(const World& w, std::int32_t station, const Vec2& pixel, Vec3& site_m) {
    const auto x = static_cast<std::int32_t>(std::lround(pixel.x()));
    const auto y = static_cast<std::int32_t>(std::lround(pixel.y()));
    if (x < 1 || y < 1 || x + 1 >= w.side || y + 1 >= w.side) return false;
    const std::vector<float>& r = w.range[static_cast<std::size_t>(2 * station)];
    const auto at = [&](std::int32_t xx, std::int32_t yy) { return static_cast<double>(r[static_cast<std::size_t>(yy * w.side + xx)]); };
    const double c = at(x, y);
    if (!std::isfinite(c)) return false;
    for (const double n : {at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)}) {
        if (!std::isfinite(n) || std::fabs(n - c) > 0.02 * c) return false;
    }
    const NetworkStation& truth = w.panorama.stations[station].truth;
    CameraRay ray;
    if (!backProjectPixel(truth.rig.model_a, pixel, ray).isOk()) return false;
    site_m = transformPoint(truth.site_from_a, ray.origin_m + c * ray.direction);
    return true;
}

struct Chain {
    std::vector<NetworkStation> approx, truth;
    std::vector<TieObservation> obs;
    std::uint32_t points = 0;
    std::int32_t tiepoint_failures = 0;
    bundle::BundleResult result;
    Status bundle_status;
    std::vector<bundle::StationSolution> stations;
    std::vector<bundle::PointSolution> solved;
};

// Tie points per tier (a closed ring of `columns` stations), gathered into one network.
void tiePoints(const World& w, Chain& c) {
    const std::int32_t columns = w.scenario.motion.columns;
    const std::int32_t tiers = w.panorama.count / columns;
    tiepoints::Config tc;
    tc.max_width = w.side;
    tc.max_height = w.side;
    tc.max_stations = columns;
    tc.max_observations = 1 << 15;
    tc.closed_panorama = true;
    tc.range_min_m = 1.0;
    tc.range_max_m = 80.0;
    std::vector<std::byte> pool(tiepoints::TiePointExtractor::workspaceBytes(tc));
    Arena arena(pool.data(), pool.size());
    auto extractor = std::make_unique<tiepoints::TiePointExtractor>();
    ASSERT_TRUE(extractor->init(tc, arena).isOk());
    for (std::int32_t t = 0; t < tiers; ++t) {
        const auto first = static_cast<std::size_t>(t * columns);
        const Status st = extractor->run(Span<const NetworkStation>(w.approx.data() + first, static_cast<std::size_t>(columns)),
                                         Span<const StationImages>(w.images.data() + first, static_cast<std::size_t>(columns)));
        if (!st.isOk()) {
            std::printf("[ chain ] tier %d: tie points refused: %s\n", t, st.reason());
            ++c.tiepoint_failures;
            continue;
        }
        for (const TieObservation& o : extractor->observations()) {
            TieObservation g = o;
            g.image.station = static_cast<std::uint16_t>(t * columns + o.image.station);
            g.point = c.points + o.point;
            c.obs.push_back(g);
        }
        c.points += extractor->pointCount();
    }
}

void adjust(Chain& c) {
    bundle::BundleConfig bc;
    bc.max_stations = static_cast<std::int32_t>(c.approx.size());
    bc.max_points = static_cast<std::int32_t>(c.points) + 1;
    bc.max_observations = static_cast<std::int32_t>(c.obs.size()) + 1;
    std::vector<std::byte> pool(bundle::BundleAdjuster::workspaceBytes(bc));
    Arena arena(pool.data(), pool.size());
    auto adjuster = std::make_unique<bundle::BundleAdjuster>();
    ASSERT_TRUE(adjuster->init(bc, arena).isOk());
    c.bundle_status = adjuster->adjust(Span<const NetworkStation>(c.approx.data(), c.approx.size()),
                                       Span<const TieObservation>(c.obs.data(), c.obs.size()), c.points, c.result);
    if (!c.bundle_status.isOk()) return;
    c.stations.assign(adjuster->stations().begin(), adjuster->stations().end());
    c.solved.assign(adjuster->points().begin(), adjuster->points().end());
}

// Least-squares triangulation of a point from its sightings at given stations.
bool triangulate(const std::vector<NetworkStation>& stations, const std::vector<const TieObservation*>& seen, Vec3& x) {
    Mat3 a = Mat3::Zero();
    Vec3 b = Vec3::Zero();
    for (const TieObservation* o : seen) {
        const NetworkStation& s = stations[o->image.station];
        CameraRay ray;
        if (!backProjectPixel(modelOfEye(s, o->image.eye), o->pixel_px, ray).isOk()) return false;
        const RigidPose p = siteFromEye(s, o->image.eye);
        const Vec3 d = p.R * ray.direction;
        const Vec3 o_site = transformPoint(p, ray.origin_m);
        const Mat3 m = Mat3::Identity() - d * d.transpose();
        a += m;
        b += m * o_site;
    }
    if (std::fabs(a.determinant()) < 1e-12) return false;
    x = a.inverse() * b;
    return true;
}

struct Band {
    double lo, hi;
    std::vector<double> before, after;
};

double rms(const std::vector<double>& v) {
    double s = 0.0;
    for (const double x : v) s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct Figures {
    double rms_before = 0.0, rms_after = 0.0;
    double obj_before = 0.0, obj_after = 0.0;      // RMS tie point error against the truth, m (all bands)
    double rel_rot_before = 0.0, rel_rot_after = 0.0;  // median neighbour relative rotation error, deg
    double wrong_fraction = 0.0;                   // tie points whose truth is > 0.25 m from the adjusted point
    double map_rms_near = 0.0, map_rms_far = 0.0;  // kriged elevation vs the terrain, 0-4 m and 4-10 m from the mast, m
    double map_coverage_near = 0.0;                // fraction of 0-4 m nodes with an estimate
    double seam_ratio = 0.0;                       // orthophoto: grey step across source borders / within one source
    std::int32_t points = 0, observations = 0;
};

Figures measure(const World& w, const Chain& c) {
    Figures f;
    f.rms_before = c.result.rms_before_px;
    f.rms_after = c.result.rms_after_px;
    f.points = static_cast<std::int32_t>(c.points);
    f.observations = static_cast<std::int32_t>(c.obs.size());
    std::vector<std::vector<const TieObservation*>> of(c.points);
    for (const TieObservation& o : c.obs) of[o.point].push_back(&o);
    Band bands[] = {{0.0, 5.0, {}, {}}, {5.0, 10.0, {}, {}}, {10.0, 20.0, {}, {}}, {20.0, 1e9, {}, {}}};
    std::vector<double> all_before, all_after;
    std::int32_t wrong = 0, checked = 0;
    for (std::uint32_t p = 0; p < c.points; ++p) {
        if (c.solved[p].state != bundle::PointState::kAdjusted) continue;
        const TieObservation* first = of[p].front();
        Vec3 truth;
        if (first->image.eye != Eye::kLeft || !trueGround(w, first->image.station, first->pixel_px, truth)) continue;
        Vec3 before;
        if (!triangulate(c.approx, of[p], before)) continue;
        const double range = (truth - c.truth[first->image.station].site_from_a.t_m).norm();
        const double eb = (before - truth).norm();
        const double ea = (c.solved[p].position_m - truth).norm();
        ++checked;
        if (ea > 0.25 + 0.02 * range) {
            ++wrong;
            continue;
        }
        all_before.push_back(eb);
        all_after.push_back(ea);
        for (Band& b : bands) {
            if (range >= b.lo && range < b.hi) {
                b.before.push_back(eb);
                b.after.push_back(ea);
            }
        }
    }
    f.obj_before = rms(all_before);
    f.obj_after = rms(all_after);
    f.wrong_fraction = checked > 0 ? static_cast<double>(wrong) / checked : 1.0;
    for (const Band& b : bands) {
        std::printf("[ chain ]   tie points %5.0f-%-5.0f m: %4zu, RMS error vs truth %.4f -> %.4f m\n", b.lo,
                    std::min(b.hi, 999.0), b.after.size(), rms(b.before), rms(b.after));
    }
    // Neighbours in a tier: the relative rotation against the truth's.
    const std::int32_t columns = w.scenario.motion.columns;
    std::vector<double> rb, ra;
    for (std::size_t s = 0; s < c.approx.size(); ++s) {
        const std::size_t t = (s / columns) * columns + (s % columns + 1) % columns;
        const Mat3 tr = c.truth[s].site_from_a.R.transpose() * c.truth[t].site_from_a.R;
        rb.push_back(rotationAngleRad(c.approx[s].site_from_a.R.transpose() * c.approx[t].site_from_a.R, tr) / kDeg);
        ra.push_back(rotationAngleRad(c.stations[s].site_from_a.R.transpose() * c.stations[t].site_from_a.R, tr) / kDeg);
    }
    f.rel_rot_before = median(rb);
    f.rel_rot_after = median(ra);
    std::printf("[ chain ]   checked %d tie points against the truth, %d wrong (> 0.25 m + 2 %% of range)\n", checked,
                wrong);
    return f;
}

// Products of the adjusted network (item 4): the adjusted tie points kriged into a 0.25 m
// elevation grid around the mast, against the terrain by distance band; the orthophoto from
// the adjusted stations, its grey steps across source borders against those inside one image.
void products(const World& w, const Chain& c, Figures& f) {
    const Vec3 mast = c.truth[0].site_from_a.t_m;
    std::vector<Vec3> samples;
    for (const bundle::PointSolution& p : c.solved) {
        const Vec3 d = p.position_m - mast;
        if (p.state == bundle::PointState::kAdjusted && std::hypot(d.x(), d.y()) <= 12.0) samples.push_back(p.position_m);
    }
    kriging::KrigingConfig kc;
    kc.grid.cell_m = 0.25;
    kc.grid.cols = kc.grid.rows = 80;  // 20 m square
    kc.grid.north_edge_m = mast.x() + 10.0;
    kc.grid.west_edge_m = mast.y() - 10.0;
    kc.max_samples = static_cast<std::int32_t>(samples.size()) + 16;
    kc.search_radius_m = 2.0;
    std::vector<std::byte> pool(kriging::OrdinaryKriging::workspaceBytes(kc));
    Arena arena(pool.data(), pool.size());
    auto krig = std::make_unique<kriging::OrdinaryKriging>();
    ASSERT_TRUE(krig->init(kc, arena).isOk());
    ASSERT_TRUE(krig->setSamples(Span<const Vec3>(samples.data(), samples.size())).isOk());
    kriging::Variogram v;
    ASSERT_TRUE(krig->fitVariogram(v).isOk());
    ASSERT_TRUE(krig->krigeGrid(v).isOk());
    const kriging::KrigedMap& map = krig->map();
    std::vector<double> near, far;
    std::int32_t near_nodes = 0;
    for (std::int32_t r = 0; r < kc.grid.rows; ++r) {
        for (std::int32_t col = 0; col < kc.grid.cols; ++col) {
            const double n = map.centreNorthM(r), e = map.centreEastM(col);
            const double dist = std::hypot(n - mast.x(), e - mast.y());
            if (dist < 1.0 || dist > 10.0) continue;  // under the rover: no tie point sees it
            near_nodes += dist <= 4.0 ? 1 : 0;
            if (map.reason(col, r) != kriging::NodeReason::kEstimated) continue;
            const double err = static_cast<double>(map.elevation(col, r)) - w.terrain.elevationAt(n, e);
            (dist <= 4.0 ? near : far).push_back(err);
        }
    }
    f.map_rms_near = rms(near);
    f.map_rms_far = rms(far);
    f.map_coverage_near = near_nodes > 0 ? static_cast<double>(near.size()) / near_nodes : 0.0;
    // The orthophoto from the adjusted stations.
    std::vector<NetworkStation> adjusted = c.approx;
    for (std::size_t s = 0; s < adjusted.size(); ++s) {
        adjusted[s].site_from_a = c.stations[s].site_from_a;
    }
    const std::vector<StationImages>& images = w.images;
    std::vector<std::uint8_t> grey(static_cast<std::size_t>(kc.grid.cols * kc.grid.rows), 0U);
    std::vector<std::uint16_t> source(grey.size(), 0U);
    kriging::OrthophotoConfig oc;
    ASSERT_TRUE(kriging::buildOrthophoto(oc, kc.grid, map.elevations(), Span<const NetworkStation>(adjusted.data(), adjusted.size()),
                                         Span<const StationImages>(images.data(), images.size()),
                                         ImageView<std::uint8_t>(grey.data(), kc.grid.cols, kc.grid.rows),
                                         ImageView<std::uint16_t>(source.data(), kc.grid.cols, kc.grid.rows))
                    .isOk());
    const kriging::SeamSteps seams =
        kriging::measureSeamSteps(ImageView<const std::uint8_t>(grey.data(), kc.grid.cols, kc.grid.rows),
                                  ImageView<const std::uint16_t>(source.data(), kc.grid.cols, kc.grid.rows));
    f.seam_ratio = seams.ratio();
    std::printf("[ chain ]   kriged map from %zu adjusted tie points (variogram: sill %.4f m2, range %.2f m): elevation "
                "RMS vs terrain %.4f m at 1-4 m (%.0f %% of nodes), %.4f m at 4-10 m (%zu nodes); orthophoto grey step "
                "across source borders %.2f DN (%d) vs within one image %.2f DN (%d)\n",
                samples.size(), v.partial_sill_m2 + v.nugget_m2, v.range_m, f.map_rms_near, 100.0 * f.map_coverage_near,
                f.map_rms_far, far.size(), seams.across_dn, seams.across_pairs, seams.within_dn, seams.within_pairs);
}

Figures runChain(const std::string& text, const char* label) {
    auto w = std::make_unique<World>();
    Figures f;
    EXPECT_TRUE(buildWorld(text, *w)) << label;
    if (::testing::Test::HasFailure()) return f;
    Chain c;
    for (std::int32_t s = 0; s < w->panorama.count; ++s) {
        c.approx.push_back(w->panorama.stations[s].approx);
        c.truth.push_back(w->panorama.stations[s].truth);
    }
    tiePoints(*w, c);
    adjust(c);
    EXPECT_TRUE(c.bundle_status.isOk()) << label << ": " << c.bundle_status.reason();
    if (!c.bundle_status.isOk()) return f;
    f = measure(*w, c);
    products(*w, c, f);
    std::printf("[ chain ] %s: %d stations, %d tie points, %d observations (%d outliers); image RMS %.3f -> %.3f px; "
                "tie points vs truth RMS %.4f -> %.4f m; neighbour relative rotation %.4f -> %.4f deg; wrong %.2f %%\n",
                label, w->panorama.count, f.points, f.observations, c.result.outliers, f.rms_before, f.rms_after,
                f.obj_before, f.obj_after, f.rel_rot_before, f.rel_rot_after, 100.0 * f.wrong_fraction);
    EXPECT_EQ(c.tiepoint_failures, 0) << label;
    return f;
}

std::string variant(std::uint64_t seed, double sun_azimuth, double sun_elevation) {
    std::string text = scenarioText();
    test::setScenarioValue(text, "seed", std::to_string(seed));
    test::setScenarioValueInSection(text, "camera", "width_px", "512");
    test::setScenarioValueInSection(text, "camera", "height_px", "512");
    test::setScenarioValueInSection(text, "lighting", "sun_azimuth_deg", std::to_string(sun_azimuth));
    test::setScenarioValueInSection(text, "lighting", "sun_elevation_deg", std::to_string(sun_elevation));
    return text;
}

// Issue 23 item 5: image RMS after adjustment <= 0.5 px; the tie points' object-space error
// against the truth reported by distance band (the 0.05 m target is the paper's precision
// of a tie point; here it is measured as accuracy against the truth); almost no wrong tie
// point; the neighbours' relative rotation better after than before.
TEST(PanoramaChain, RenderedNavcamPanoramaTiePointsAndBundleAgainstTheTruth) {
    struct Case {
        std::uint64_t seed;
        double az, el;
    };
    std::vector<Case> cases = {{20261205U, 250.0, 35.0}};
    if (std::getenv("VTM_EVAL_FULL") != nullptr) {
        cases.push_back({7U, 90.0, 55.0});
        cases.push_back({31U, 180.0, 20.0});
    }
    for (const Case& k : cases) {
        char label[64];
        std::snprintf(label, sizeof label, "seed %llu sun %.0f/%.0f", static_cast<unsigned long long>(k.seed), k.az, k.el);
        const Figures f = runChain(variant(k.seed, k.az, k.el), label);
        EXPECT_LE(f.rms_after, 0.5) << label;
        EXPECT_LT(f.rms_after, f.rms_before) << label;
        EXPECT_LT(f.rel_rot_after, f.rel_rot_before) << label;
        EXPECT_LE(f.wrong_fraction, 0.02) << label;
        EXPECT_GE(f.points, 500) << label;
        // The kriged elevation near the mast within 5 cm of the terrain; no seam in the
        // orthophoto (its grey steps across source borders within 1.5x those inside one image).
        EXPECT_LE(f.map_rms_near, 0.05) << label;
        EXPECT_GE(f.map_coverage_near, 0.5) << label;
        EXPECT_LE(f.seam_ratio, 1.5) << label;
    }
}

}  // namespace
}  // namespace vtm
