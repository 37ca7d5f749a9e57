// Builds the world of the traverse-and-descent fusion (traverse_world.hpp).
#include "traverse_world.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "sim/render.hpp"
#include "vtm/app/descent_mapper.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#include "vtm/stereo/speckle_filter.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::traverse {
namespace {

using ground::setScenarioValue;
using tools::secondsSince;

// The descent over the traverse's terrain: the traverse file up to its [camera] section
// (name, seed, [terrain]) and a nadir camera that sinks from 60 m to 40 m while drifting
// 12 m east, so that the direction of motion (31 deg off nadir) lies outside the 45 deg
// view and every pixel has parallax. Zero odometry model: the descent's frames are placed
// with their true poses; its navigation error is applied afterwards as a rigid motion.
std::string descentText(const std::string& traverse_text, std::int32_t px) {
    std::string head = traverse_text.substr(0, traverse_text.find("[camera]"));
    setScenarioValue(head, "kind", "descent");
    setScenarioValue(head, "name", "traverse_descent");
    const std::string side = std::to_string(px);
    return head + "[camera]\nmodel pinhole\nwidth_px " + side + "\nheight_px " + side +
           "\nhfov_deg 45\nbit_depth 12\nmount_position_m 0 0 0\nmount_tilt_deg -90\n"
           "[sensor]\nexposure_s 0.004\ngain_dn_per_e 0.04\nfull_well_e 60000\nread_noise_e 12\nvignetting 0.15\n"
           "[lighting]\nsun_azimuth_deg 200\nsun_elevation_deg 45\n"
           "[motion]\nstart_m 4 -4\nheading_deg 0\nstart_altitude_m 45\nend_altitude_m 30\nframes 2\n"
           "drift_m 0 8\nattitude_noise_deg 0\nspeed_m_per_s 10\n";
}

// Rover stereo at one stop: two parallel pinholes `baseline_m` apart, centred on the mast
// camera's projection centre and parallel to it (as the rover_pair scenario's fixed pair),
// rendered from the stop's TRUE pose; MlStereo, the speckle filter, and triangulation in
// the vehicle frame (RectifiedGeometry with the rig's vehicle_from_left).

Status mapStop(const World& w, const sim::ScenarioFrame& mast, StopMap& out) {
    const std::int32_t n = w.sizes.stereo_px;
    const CameraModel model = makePinhole(static_cast<std::uint16_t>(n), static_cast<std::uint16_t>(n), 45.0);
    RigidPose site_from_left = mast.camera_pose;
    site_from_left.t_m -= mast.camera_pose.R * Vec3(0.5 * kStereoBaseline_m, 0.0, 0.0);
    const RigidPose site_from_right = sim::rightPoseOfRectifiedPair(site_from_left, kStereoBaseline_m);
    std::vector<std::uint8_t> left(static_cast<std::size_t>(n) * n), right(left.size());
    std::vector<float> depth(left.size());
    for (int side = 0; side < 2; ++side) {
        sim::ScenarioFrame f = mast;
        f.model = model;
        f.camera_pose = side == 0 ? site_from_left : site_from_right;
        sim::FrameRequest req = sim::scenarioFrameRequest(w.traverse.scenario, w.traverse.terrain, f);
        req.frame_index = 1000U + 2U * mast.index + static_cast<std::uint32_t>(side);
        sim::FrameOutput o;
        o.image8 = ImageView<std::uint8_t>(side == 0 ? left.data() : right.data(), n, n);
        o.truth.depth_m = ImageView<float>(depth.data(), n, n);
        VTM_RETURN_IF_ERROR(sim::renderFrame(req, o, nullptr));
    }
    stereo::Config sc = stereo::Config::conservative();  // left-right check (1 px), uniqueness 5 %
    sc.max_width = sc.max_height = n;
    sc.d_min = 0;
    sc.d_max = static_cast<std::int32_t>(std::ceil(model.fx_px * kStereoBaseline_m / 1.5));  // nearest 1.5 m
    std::vector<std::byte> pool(stereo::MlStereo::workspaceBytes(sc) + 64U);
    Arena arena(pool.data(), pool.size());
    auto ml = std::make_unique<stereo::MlStereo>();
    VTM_RETURN_IF_ERROR(ml->init(sc, arena));
    std::vector<std::int16_t> disp(left.size(), stereo::kNoDisparity);
    const stereo::DisparityOutput dout{ImageView<std::int16_t>(disp.data(), n, n), {}, {}};
    VTM_RETURN_IF_ERROR(ml->compute(ImageView<const std::uint8_t>(left.data(), n, n),
                                    ImageView<const std::uint8_t>(right.data(), n, n), dout));
    stereo::SpeckleConfig fc;  // as the rover mapper runs it: islands of <= 100 px, 3 px steps
    fc.max_width = fc.max_height = n;
    fc.max_diff_px16 = 3 * stereo::kDisparityScale;
    std::vector<std::byte> fpool(stereo::SpeckleFilter::workspaceBytes(fc) + 64U);
    Arena farena(fpool.data(), fpool.size());
    stereo::SpeckleFilter speckles;
    VTM_RETURN_IF_ERROR(speckles.init(fc, farena));
    VTM_RETURN_IF_ERROR(speckles.apply(dout));

    const RigidPose vehicle_from_mast = sim::vehicleFromCamera(mast);
    terrain::RectifiedGeometry g;
    g.fx_px = model.fx_px;
    g.fy_px = model.fy_px;
    g.cx_left_px = g.cx_right_px = model.cx_px;
    g.cy_px = model.cy_px;
    g.baseline_m = kStereoBaseline_m;
    g.R_site_from_rect = vehicle_from_mast.R;  // "site" = the vehicle frame here
    g.left_centre_site_m = vehicle_from_mast.t_m - vehicle_from_mast.R * Vec3(0.5 * kStereoBaseline_m, 0.0, 0.0);
    terrain::TriangulationLimits limits;
    limits.min_range_m = 1.0;
    limits.max_range_m = 12.0;
    std::vector<terrain::TerrainPoint> pts(left.size());
    terrain::TriangulationStats stats;
    VTM_RETURN_IF_ERROR(terrain::triangulate(g, limits, ImageView<const std::int16_t>(disp.data(), n, n), {},
                                             Span<terrain::TerrainPoint>(pts.data(), pts.size()), stats));
    out.truth = toRigidPose(mast.true_pose);
    out.odometry = toRigidPose(mast.odometry_pose);
    out.sensor_m = g.left_centre_site_m;
    out.pixel_angle_rad = 1.0 / model.fx_px;
    out.valid_disparities = static_cast<std::int64_t>(left.size()) - stats.no_disparity;
    out.points.clear();
    for (std::int32_t i = 0; i < stats.points; ++i) {
        out.points.emplace_back(pts[static_cast<std::size_t>(i)].x_m, pts[static_cast<std::size_t>(i)].y_m,
                                pts[static_cast<std::size_t>(i)].z_m);
    }
    std::vector<double> err;
    for (const Vec3& p : out.points) {
        const Vec3 q = out.truth.R * p + out.truth.t_m;
        err.push_back(std::fabs(-q.z() - w.traverse.terrain.elevationAt(q.x(), q.y())));
    }
    if (!err.empty()) {
        std::nth_element(err.begin(), err.begin() + static_cast<std::ptrdiff_t>(err.size() / 2), err.end());
        out.median_abs_vs_truth_m = err[err.size() / 2];
    }
    return Status::ok();
}

// DescentMapper on the descent pair (true poses, refine_pose off: the mapper's own chain is
// measured in tests/app/descent_mapper_test.cpp; here its map is an input).
Status mapDescent(World& w) {
    const std::int32_t n = w.sizes.descent_px;
    hal::FaultPlan plan;
    hal::SimCamera camera;
    hal::SimCamera::Config cc;
    cc.scenario = &w.descent;
    cc.terrain = &w.traverse.terrain;
    cc.frames = w.nadir_frames.get();
    cc.faults = &plan;
    VTM_RETURN_IF_ERROR(camera.init(cc));
    hal::SimOdometry odometry;  // zero odometry model: the true poses
    VTM_RETURN_IF_ERROR(odometry.init({w.nadir_frames.get(), &plan}));
    app::DescentMapperConfig c;
    c.sweep.max_width = c.sweep.max_height = n;
    c.sweep.planes = 48;
    c.sweep.window = 7;
    const RigidPose vehicle_from_camera = sim::vehicleFromCamera(w.nadir_frames->frames[0]);
    c.mount.R_vehicle_from_camera = vehicle_from_camera.R;
    c.mount.position_vehicle_m = vehicle_from_camera.t_m;
    c.refine_pose = false;
    c.relief_fraction = 0.1;
    c.grid_cells = 128;
    c.grid_cell_m = 0.25;
    hal::ManualClock clock;
    hal::EventLog events;
    std::vector<std::byte> pool(app::DescentMapper::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::DescentMapper>();
    VTM_RETURN_IF_ERROR(mapper->init(c, arena, camera, odometry, clock, events));
    VTM_RETURN_IF_ERROR(mapper->map());
    const app::DescentProducts* p = mapper->products();
    const terrain::HeightMap& map = *p->height_map;
    DescentMap& d = w.descent_map;
    d.cell_m = map.grid().cell_m;
    d.camera1_height_m = -p->geometry.site_from_cam1.t_m.z() - w.traverse.terrain.elevationAt(p->geometry.site_from_cam1.t_m.x(),
                                                                                       p->geometry.site_from_cam1.t_m.y());
    double sum = 0.0;
    for (std::int32_t row = 0; row < map.grid().rows; ++row) {
        for (std::int32_t col = 0; col < map.grid().cols; ++col) {
            const float e = map.elevation(col, row);
            if (terrain::isNoData(e)) continue;
            const double north = map.centreNorthM(row), east = map.centreEastM(col);
            d.points.emplace_back(north, east, -static_cast<double>(e));
            const double err = e - w.traverse.terrain.elevationAt(north, east);
            sum += err * err;
        }
    }
    d.rms_vs_truth_m = d.points.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(d.points.size()));
    return Status::ok();
}

}  // namespace

RigidPose toRigidPose(const sim::VehiclePose& v) {
    RigidPose p;
    p.R = Quat(v.attitude_wxyz[0], v.attitude_wxyz[1], v.attitude_wxyz[2], v.attitude_wxyz[3]).normalized().toRotationMatrix();
    p.t_m = Vec3(v.position_m[0], v.position_m[1], v.position_m[2]);
    return p;
}

std::unique_ptr<World> buildWorld(const std::string& traverse_text, const Sizes& sizes) {
    auto w = std::make_unique<World>();
    w->sizes = sizes;
    std::string text = traverse_text;
    if (!setScenarioValue(text, "samples_log2", std::to_string(sizes.samples_log2))) {
        w->error = "the traverse scenario has no samples_log2";
        return w;
    }
    auto t0 = std::chrono::steady_clock::now();
    const std::string built = ground::buildSimWorld(text, w->traverse);
    if (!built.empty()) {
        w->error = built;
        return w;
    }
    if (w->traverse.scenario.kind != sim::ScenarioKind::kTraverse) {
        w->error = "not a traverse scenario (kind traverse)";
        return w;
    }
    Status st = sim::parseScenario(descentText(text, sizes.descent_px), w->descent);
    if (st.isOk()) st = sim::buildScenarioFrames(w->descent, w->traverse.terrain, *w->nadir_frames);
    w->build_s = secondsSince(t0);
    t0 = std::chrono::steady_clock::now();
    const sim::ScenarioFrames& stops = *w->traverse.frames;
    for (std::int32_t k = 0; st.isOk() && k < stops.count; ++k) {
        w->stops.emplace_back();
        st = mapStop(*w, stops.frames[k], w->stops.back());
    }
    w->stereo_s = secondsSince(t0);
    t0 = std::chrono::steady_clock::now();
    if (st.isOk()) st = mapDescent(*w);
    w->descent_s = secondsSince(t0);
    if (!st.isOk()) {
        w->error = std::string(st.reason()) + " (" + std::to_string(st.detail()) + ")";
    }
    return w;
}

}  // namespace vtm::traverse
