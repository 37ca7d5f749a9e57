// A descent_orbital.scn-like world for the DescentMapper's orbital fix (tests/app): the
// scenario with its frame size, terrain grid, seed, suns and altitude profile replaced,
// its terrain, frames and orbital image, and a helper that flies a mapper over it through
// the in-process simulated drivers. Errors are measured against the simulator's truth
// (rendered depth, true camera poses, the orbital image's georeference).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "no_heap_guard.hpp"
#include "scenario_text.hpp"
#include "sim/orbital.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/app/descent_mapper.hpp"

namespace vtm::app::orbital_test {

struct WorldSpec {
    std::uint64_t seed = 24U;
    std::int32_t size_px = 256;        // descent frames
    std::int32_t samples_log2 = 9;     // terrain grid
    double sun_azimuth_deg = 100.0;    // the descent camera's sun
    double sun_elevation_deg = 30.0;
    double orbital_sun_azimuth_deg = 250.0;
    double orbital_sun_elevation_deg = 50.0;
    double start_altitude_m = 400.0;
    double end_altitude_m = 40.0;
    std::int32_t frames = 6;
    std::string modality = "thermal";
};

struct World {
    sim::Scenario scenario;
    std::vector<std::byte> storage;
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain;
    sim::ScenarioFrames frames;
    std::vector<std::uint8_t> orbital;
    sim::OrbitalGeoreference geo{};
    bool ok = false;
};

inline std::string num(double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

inline std::unique_ptr<World> buildWorld(const WorldSpec& spec) {
    auto w = std::make_unique<World>();
    std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/descent_orbital.scn", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    std::string t = s.str();
    const std::size_t seed_at = t.find("\nseed ");
    t.replace(seed_at + 1, t.find('\n', seed_at + 1) - seed_at - 1, "seed " + std::to_string(spec.seed));
    bool ok = test::setScenarioValueInSection(t, "camera", "width_px", std::to_string(spec.size_px)) &&
              test::setScenarioValueInSection(t, "camera", "height_px", std::to_string(spec.size_px)) &&
              test::setScenarioValueInSection(t, "terrain", "samples_log2", std::to_string(spec.samples_log2)) &&
              test::setScenarioValueInSection(t, "lighting", "sun_azimuth_deg", num(spec.sun_azimuth_deg)) &&
              test::setScenarioValueInSection(t, "lighting", "sun_elevation_deg", num(spec.sun_elevation_deg)) &&
              test::setScenarioValueInSection(t, "orbital", "sun_azimuth_deg", num(spec.orbital_sun_azimuth_deg)) &&
              test::setScenarioValueInSection(t, "orbital", "sun_elevation_deg", num(spec.orbital_sun_elevation_deg)) &&
              test::setScenarioValueInSection(t, "orbital", "modality", spec.modality) &&
              test::setScenarioValueInSection(t, "motion", "start_altitude_m", num(spec.start_altitude_m)) &&
              test::setScenarioValueInSection(t, "motion", "end_altitude_m", num(spec.end_altitude_m)) &&
              test::setScenarioValueInSection(t, "motion", "frames", std::to_string(spec.frames));
    if (!ok || !sim::parseScenario(t, w->scenario).isOk()) {
        return w;
    }
    w->storage.resize(sim::scenarioTerrainBytes(w->scenario) + 64U);
    w->arena = std::make_unique<Arena>(w->storage.data(), w->storage.size());
    if (!sim::buildScenarioTerrain(w->scenario, *w->arena, w->terrain).isOk() ||
        !sim::buildScenarioFrames(w->scenario, w->terrain, w->frames).isOk()) {
        return w;
    }
    const sim::OrbitalParams p = sim::scenarioOrbitalParams(w->scenario);
    w->orbital.assign(static_cast<std::size_t>(p.width_px) * static_cast<std::size_t>(p.height_px), 0U);
    sim::OrbitalOutput o;
    o.image8 = ImageView<std::uint8_t>(w->orbital.data(), p.width_px, p.height_px);
    w->geo = sim::orbitalGeoreference(p);
    w->ok = p.bit_depth == 8 && sim::renderOrbital(w->terrain, p, o, nullptr).isOk();
    return w;
}

// The mapper's view of the world's orbital image: the simulator's georeference.
inline OrbitalMap orbitalMapOf(const World& w) {
    OrbitalMap m;
    m.image8 = ImageView<const std::uint8_t>(w.orbital.data(), w.geo.width_px, w.geo.height_px);
    m.geo.north0_m = w.geo.north0_m;
    m.geo.east0_m = w.geo.east0_m;
    m.geo.cell_m = w.geo.cell_m;
    return m;
}

inline CameraMount mountOf(const sim::ScenarioFrame& f) {
    const RigidPose vehicle_from_camera = sim::vehicleFromCamera(f);
    CameraMount m;
    m.R_vehicle_from_camera = vehicle_from_camera.R;
    m.position_vehicle_m = vehicle_from_camera.t_m;
    return m;
}

// The small descent configuration of descent_mapper_test.cpp, with the orbital fix.
inline DescentMapperConfig orbitalConfig(const World& w, bool fix) {
    DescentMapperConfig c;
    const std::int32_t size = w.scenario.camera.width_px;
    c.sweep.max_width = size;
    c.sweep.max_height = size;
    c.sweep.planes = 32;
    c.sweep.window = 7;
    c.mount = mountOf(w.frames.frames[0]);
    c.grid_cells = size / 2;
    c.refine.detector.grid_cols = 8;
    c.refine.detector.grid_rows = 8;
    c.refine.detector.per_cell = 4;
    c.refine.matcher.pyramid_levels = 1;
    c.refine.match_margin_px = c.refine.visibility_margin_px = 8.0;
    c.orbital.enabled = fix;
    if (const char* e = std::getenv("VTM_ORB_ROUNDS")) c.orbital.registration.refine_rounds = std::atoi(e);
    if (const char* e = std::getenv("VTM_ORB_WINDOW")) c.orbital.registration.entropy.window = std::atoi(e);
    if (const char* e = std::getenv("VTM_ORB_BINS")) c.orbital.registration.entropy.bins = std::atoi(e);
    if (const char* e = std::getenv("VTM_ORB_MINNCC")) c.orbital.min_ncc = std::atof(e);
    if (const char* e = std::getenv("VTM_ORB_PIXEL")) c.orbital.min_pixel_cells = std::atof(e);
    if (const char* e = std::getenv("VTM_ORB_RADIUS")) c.orbital.registration.equalise_radius_px = std::atoi(e);
    if (const char* e = std::getenv("VTM_ORB_REG_MINNCC")) c.orbital.registration.min_ncc = std::atof(e);
    if (const char* e = std::getenv("VTM_ORB_PEAK")) {
        c.orbital.max_peak_ratio = std::atof(e);
        c.orbital.registration.max_peak_ratio = std::atof(e);
    }
    return c;
}

inline const sim::ScenarioFrame* frameAt(const World& w, std::uint64_t timestamp_ns) {
    for (std::int32_t i = 0; i < w.frames.count; ++i) {
        if (w.frames.frames[i].timestamp_ns == timestamp_ns) return &w.frames.frames[i];
    }
    return nullptr;
}

// Median |depth - true depth| / true depth over image 1's valid pixels (-1: none).
inline double medianDepthError(const World& w, const DescentProducts& p) {
    const sim::ScenarioFrame* f = frameAt(w, p.frame1.timestamp_ns);
    if (f == nullptr) return -1.0;
    const std::int32_t n = p.depth_m.width();
    std::vector<float> truth(static_cast<std::size_t>(n) * n);
    std::vector<std::uint16_t> pixels(truth.size());
    sim::FrameOutput o;
    o.image16 = ImageView<std::uint16_t>(pixels.data(), n, n);
    o.truth.depth_m = ImageView<float>(truth.data(), n, n);
    if (!sim::renderFrame(sim::scenarioFrameRequest(w.scenario, w.terrain, *f), o, nullptr).isOk()) return -1.0;
    std::vector<double> rel;
    for (std::int32_t y = 0; y < n; ++y) {
        for (std::int32_t x = 0; x < n; ++x) {
            const float d = p.depth_m.row(y)[x];
            const float t = truth[static_cast<std::size_t>(y * n + x)];
            if (std::isfinite(d) && std::isfinite(t)) rel.push_back(std::fabs(static_cast<double>(d - t)) / t);
        }
    }
    if (rel.empty()) return -1.0;
    std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(rel.size() / 2), rel.end());
    return rel[rel.size() / 2];
}

// One request's outcome, measured against the truth.
struct Outcome {
    bool mapped = false;
    bool applied = false;
    double depth_error = -1.0;             // median, relative
    double frame_error_px[2] = {-1.0, -1.0};  // located camera vs true, orbital px (-1: not located)
    double placement_error_px = -1.0;      // camera 1 as the map is placed (fixed or navigation) vs true
    double navigation_error_px = -1.0;     // camera 1 as the navigation said vs true
    std::int64_t locate_quality = -1;
    double scale = 1.0;                    // applied to the navigation's baseline
    bool scale_applied = false;
    double true_scale = 1.0;               // true baseline / the navigation's (refined) baseline
    double frame_scale[2] = {0.0, 0.0};
    double frame_ncc[2] = {-1.0, -1.0};     // the registration's peak and second peak
    double frame_second[2] = {-1.0, -1.0};
    double frame_residual_px[2] = {-1.0, -1.0};
    const char* frame_reason[2] = {"", ""};
    const char* reason = "";
};

// Flies `requests` requests (frames 0+1, 2+3, ...) with SimOdometry's poses.
inline std::vector<Outcome> fly(const World& w, const DescentMapperConfig& c, int requests) {
    std::vector<Outcome> out;
    hal::FaultPlan plan;
    hal::SimCamera camera;
    hal::SimOdometry odometry;
    hal::ManualClock clock;
    hal::EventLog events;
    hal::SimCamera::Config cc;
    cc.scenario = &w.scenario;
    cc.terrain = &w.terrain;
    cc.frames = &w.frames;
    cc.faults = &plan;
    EXPECT_TRUE(camera.init(cc).isOk());
    EXPECT_TRUE(odometry.init({&w.frames, &plan}).isOk());
    std::vector<std::byte> pool(DescentMapper::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<DescentMapper>();
    const Status init = mapper->init(c, arena, camera, odometry, clock, events);
    EXPECT_TRUE(init.isOk()) << init.reason();
    if (c.orbital.enabled) {
        const Status set = mapper->setOrbitalMap(orbitalMapOf(w));
        EXPECT_TRUE(set.isOk()) << set.reason();
    }
    const double cell = w.geo.cell_m;
    for (int r = 0; r < requests; ++r) {
        Outcome o;
        Status st;
        {
            test::NoHeapScope guard;
            st = mapper->map();
            EXPECT_EQ(guard.heapCalls(), 0U) << "map() used the heap";
        }
        const DescentProducts* p = mapper->products();
        EXPECT_TRUE(st.isOk()) << "request " << r << ": " << st.reason();
        if (!st.isOk() || p == nullptr) {
            out.push_back(o);
            continue;
        }
        o.mapped = true;
        o.applied = p->orbital.applied;
        o.reason = p->orbital.status.reason();
        o.depth_error = medianDepthError(w, *p);
        const sim::ScenarioFrame* f[2] = {frameAt(w, p->frame1.timestamp_ns), frameAt(w, p->frame2.timestamp_ns)};
        for (int i = 0; i < 2; ++i) {
            const LocatedFrame& lf = p->orbital.frames[i];
            o.frame_ncc[i] = lf.registration.ncc;
            o.frame_second[i] = lf.registration.second_ncc;
            o.frame_residual_px[i] = lf.residual_px;
            o.frame_reason[i] = lf.status.reason();
            if (lf.used && f[i] != nullptr) {
                const Vec2 truth(f[i]->camera_pose.t_m.x(), f[i]->camera_pose.t_m.y());
                o.frame_error_px[i] = (lf.position_ne_m - truth).norm() / cell;
            }
        }
        if (f[0] != nullptr) {
            const Vec2 truth(f[0]->camera_pose.t_m.x(), f[0]->camera_pose.t_m.y());
            const Vec3& placed = p->geometry.site_from_cam1.t_m;
            o.placement_error_px = (Vec2(placed.x(), placed.y()) - truth).norm() / cell;
            const Vec2 nav = Vec2(placed.x(), placed.y()) - (o.applied ? p->orbital.correction_ne_m : Vec2::Zero());
            o.navigation_error_px = (nav - truth).norm() / cell;
        }
        if (f[0] != nullptr && f[1] != nullptr) {
            const double used = (p->geometry.site_from_cam2.t_m - p->geometry.site_from_cam1.t_m).norm();
            const double k = o.applied && p->orbital.scale_applied ? p->orbital.scale : 1.0;
            o.scale_applied = o.applied && p->orbital.scale_applied;
            o.scale = k;
            o.true_scale = (f[1]->camera_pose.t_m - f[0]->camera_pose.t_m).norm() / (used / k);
            o.frame_scale[0] = p->orbital.frames[0].scale;
            o.frame_scale[1] = p->orbital.frames[1].scale;
        }
        if (std::getenv("VTM_ORBITAL_DEBUG") != nullptr) {
            for (int i = 0; i < 2; ++i) {
                const LocatedFrame& lf = p->orbital.frames[i];
                if (!lf.used || f[i] == nullptr) continue;
                const std::int32_t n = p->depth_m.width();
                std::vector<float> pts(3U * n * n);
                std::vector<std::uint16_t> px(static_cast<std::size_t>(n) * n);
                sim::FrameOutput fo;
                fo.image16 = ImageView<std::uint16_t>(px.data(), n, n);
                fo.truth.point_site_m = ImageView<float>(pts.data(), 3 * n, n);
                (void)sim::renderFrame(sim::scenarioFrameRequest(w.scenario, w.terrain, *f[i]), fo, nullptr);
                // similarity full pixel -> orbital px over all pixels, LSQ (complex)
                double sx = 0, sy = 0, tx = 0, ty = 0, m = 0;
                for (int k = 0; k < n * n; ++k) {
                    if (!std::isfinite(pts[3 * k])) continue;
                    const Vec2 o = sim::orbitalPixelFromSite(w.geo, pts[3 * k], pts[3 * k + 1]);
                    sx += k % n; sy += k / n; tx += o.x(); ty += o.y(); m += 1;
                }
                sx /= m; sy /= m; tx /= m; ty /= m;
                double re = 0, im = 0, nn = 0;
                for (int k = 0; k < n * n; ++k) {
                    if (!std::isfinite(pts[3 * k])) continue;
                    const Vec2 o = sim::orbitalPixelFromSite(w.geo, pts[3 * k], pts[3 * k + 1]);
                    const double zx = k % n - sx, zy = k / n - sy, wx = o.x() - tx, wy = o.y() - ty;
                    re += wx * zx + wy * zy; im += wy * zx - wx * zy; nn += zx * zx + zy * zy;
                }
                const double true_s = std::sqrt(re * re + im * im) / nn * (1 << lf.reduction);
                std::printf("    frame %d: registration scale %.5f, true similarity scale %.5f (ratio %.4f), ncc %.3f second %.3f, reduction %d\n", i,
                            lf.registration.scale, true_s, lf.registration.scale / true_s, lf.registration.ncc, lf.registration.second_ncc, lf.reduction);
            }
        }
        for (std::size_t i = 0; i < mapper->stages().size(); ++i) {
            if (mapper->stages().at(i).stage == Stage::kLocate) o.locate_quality = mapper->stages().at(i).quality;
        }
        out.push_back(o);
    }
    return out;
}

}  // namespace vtm::app::orbital_test
