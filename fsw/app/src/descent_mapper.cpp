#include "vtm/core/config_check.hpp"
#include "vtm/app/descent_mapper.hpp"

#include <cmath>

#include "vtm/core/math.hpp"
#include "request_support.hpp"

namespace vtm::app {
namespace {

// Element counts of the mapper's own buffers (the sweep and the height map plan their own).
struct Buffers {
    std::size_t pixels;  // one frame
};

Buffers buffersOf(const DescentMapperConfig& c) noexcept {
    Buffers b{};
    b.pixels = static_cast<std::size_t>(c.sweep.max_width) * static_cast<std::size_t>(c.sweep.max_height);
    return b;
}

// The height map's configuration: grid_cells x grid_cells; the origin and the cell are
// set per request (runGrid), so these are placeholders that validate.
terrain::HeightMapConfig heightMapOf(const DescentMapperConfig& c) noexcept {
    terrain::HeightMapConfig m;
    m.grid.north_edge_m = 0.0;
    m.grid.west_edge_m = 0.0;
    m.grid.cell_m = 1.0;
    m.grid.cols = c.grid_cells;
    m.grid.rows = c.grid_cells;
    m.reducer = c.grid_reducer;
    return m;
}

// The refinement's configuration with its capacity from the sweep's (the camera's frame
// size, stated once in sweep.max_width/max_height).
refine::Config refineConfigOf(const DescentMapperConfig& c) noexcept {
    refine::Config r = c.refine;
    r.max_width = c.sweep.max_width;
    r.max_height = c.sweep.max_height;
    return r;
}

using detail::carve;
using detail::toGrey8;

}  // namespace

refine::Config descentRefineConfig() noexcept {
    refine::Config r;
    r.match_margin_px = 16.0;
    r.visibility_margin_px = 16.0;
    r.detector.per_cell = 1;
    return r;
}

descent::Config descentSweepConfig() noexcept {
    descent::Config c;
    c.max_plane_step_px = 2.0;
    return c;
}

Status DescentMapperConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(sweep.validate());
    VTM_RETURN_IF_ERROR(validateMount(mount));
    if (!isInRange(relief_fraction, 0.01, 0.9)) {
        return invalidConfig("relief_fraction: must be 0.01..0.9");
    }
    if (!isInRange(parallax_factor, 0.0, 1000.0)) {
        return invalidConfig("parallax_factor: must be 0..1000");
    }
    if (refine_pose) {
        VTM_RETURN_IF_ERROR(refineConfigOf(*this).validate());
        if (!isInRange(attitude_sigma_rad, 0.0, math::kPi)) {
            return invalidConfig("attitude_sigma_rad: must be 0..pi");
        }
        if (!isInRange(feature_depth_margin, 0.0, 0.9)) {
            return invalidConfig("feature_depth_margin: must be 0..0.9");
        }
    }
    if (orbital.enabled) {
        if (!refine_pose) {
            return invalidConfig("orbital.enabled: needs refine_pose (locate places the refined features)");
        }
        VTM_RETURN_IF_ERROR(orbital.validate());
    }
    if (grid_cells < 16 || grid_cells > kMaxGridCells) {
        return invalidConfig("grid_cells: must be 16..4096", grid_cells);
    }
    if (!isInRange(grid_cell_m, 0.0, 1.0e4)) {
        return invalidConfig("grid_cell_m: must be 0 (one pixel at the camera height) or a cell in metres up to 1e4");
    }
    if (!heightMapOf(*this).validate().isOk()) {
        return invalidConfig("grid_reducer: must be kHighest, kMean or kLowest", static_cast<std::int64_t>(grid_reducer));
    }
    return Status::ok();
}

std::size_t DescentMapper::workspaceBytes(const DescentMapperConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const Buffers b = buffersOf(config);
    const std::size_t refine = config.refine_pose
                                   ? refine::PairRefiner::workspaceBytes(refineConfigOf(config))  // its own plan
                                         + 2U * Arena::arrayBytes<std::uint8_t>(b.pixels)  // 8-bit frames
                                   : 0U;
    const std::size_t locate = config.orbital.enabled  // the registration and its cut-outs
                                   ? OrbitalLocator::workspaceBytes(config.orbital, config.sweep.max_width,
                                                                    config.sweep.max_height)
                                   : 0U;
    return refine + locate + descent::PlaneSweep::workspaceBytes(config.sweep)  // the sweep's own plan
           + 2U * Arena::arrayBytes<std::uint16_t>(b.pixels)            // image 1, image 2
           + Arena::arrayBytes<float>(b.pixels)                         // depth of image 1
           + Arena::arrayBytes<std::uint8_t>(b.pixels)                  // reason per pixel
           + terrain::HeightMap::workspaceBytes(heightMapOf(config));   // the height map's own plan
}

Status DescentMapper::init(const DescentMapperConfig& config, Arena& arena, hal::Camera& camera,
                           hal::Odometry& odometry, const hal::Clock& clock, hal::EventLog& events) noexcept {
    initialized_ = false;
    published_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    hal::CameraDescription description;
    VTM_RETURN_IF_ERROR(camera.describe(description));
    if (description.width_px != config.sweep.max_width || description.height_px != config.sweep.max_height) {
        return Status(StatusCode::kSizeMismatch, "camera: frame size differs from sweep.max_width/max_height",
                      description.width_px);
    }
    VTM_RETURN_IF_ERROR(descent::checkCamera(description.model));
    const std::size_t before = arena.usedBytes();
    VTM_RETURN_IF_ERROR(sweep_.init(config.sweep, arena));
    const std::int32_t w = config.sweep.max_width;
    const std::int32_t h = config.sweep.max_height;
    image1_ = carve<std::uint16_t>(arena, w, h);
    image2_ = carve<std::uint16_t>(arena, w, h);
    depth_ = carve<float>(arena, w, h);
    reason_ = carve<std::uint8_t>(arena, w, h);
    VTM_RETURN_IF_ERROR(map_.init(heightMapOf(config), arena));
    if (config.refine_pose) {
        VTM_RETURN_IF_ERROR(refiner_.init(refineConfigOf(config), arena));
        grey1_ = carve<std::uint8_t>(arena, w, h);
        grey2_ = carve<std::uint8_t>(arena, w, h);
        if (grey1_.data() == nullptr || grey2_.data() == nullptr) {
            return Status(StatusCode::kOutOfMemory, "DescentMapper::init: arena smaller than workspaceBytes(config)",
                          static_cast<std::int64_t>(workspaceBytes(config)));
        }
    }
    if (config.orbital.enabled) {
        VTM_RETURN_IF_ERROR(locator_.init(config.orbital, w, h, arena));
    }
    if (image1_.data() == nullptr || image2_.data() == nullptr || depth_.data() == nullptr ||
        reason_.data() == nullptr) {
        return Status(StatusCode::kOutOfMemory, "DescentMapper::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    memory_bytes_ = arena.usedBytes() - before;
    config_ = config;
    model_ = description.model;
    camera_ = &camera;
    odometry_ = &odometry;
    clock_ = &clock;
    events_ = &events;
    initialized_ = true;
    return Status::ok();
}

Status DescentMapper::setOrbitalMap(const OrbitalMap& map) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "DescentMapper::setOrbitalMap: init() has not succeeded");
    }
    if (!config_.orbital.enabled) {
        return Status(StatusCode::kInvalidArgument, "setOrbitalMap: orbital.enabled is false (no memory planned for the fix)");
    }
    return locator_.setMap(map);
}

Status DescentMapper::finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept {
    return detail::recordStage(stages_, *events_, *clock_, stage, status, quality, t0_ns);
}

Status DescentMapper::capture(Stage stage, const ImageView<std::uint16_t>& image, hal::FrameInfo& info) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    Status st = camera_->capture16(image, info);
    if (st.isOk() && (info.width_px != image.width() || info.height_px != image.height())) {
        st = Status(StatusCode::kSizeMismatch, "capture: the frame's size differs from the camera's description",
                    info.width_px);
    }
    return finish(stage, st, st.isOk() ? static_cast<std::int64_t>(info.sequence) : 0, t0);
}

Status DescentMapper::poseOf(Stage stage, const hal::FrameInfo& info, hal::PoseEstimate& pose) noexcept {
    return detail::poseStage(*odometry_, stages_, *events_, *clock_, stage, info, pose);
}

Status DescentMapper::setSweepRange(double zmin, double zmax) noexcept {
    const double parallax = config_.parallax_factor * (1.0 / zmin - 1.0 / zmax) * 0.5 * (zmin + zmax);
    VTM_RETURN_IF_ERROR(sweep_.setDepthRange(zmin, zmax, parallax < 1000.0 ? parallax : 1000.0));
    products_.depth_min_m = zmin;
    products_.depth_max_m = zmax;
    return Status::ok();
}

Status DescentMapper::planGeometry() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    descent::PairGeometry& g = products_.geometry;
    g.camera = model_;
    Status st = cameraPoseInSite(pose1_, config_.mount, g.site_from_cam1);
    if (st.isOk()) {
        st = cameraPoseInSite(pose2_, config_.mount, g.site_from_cam2);
    }
    const double h1 = -g.site_from_cam1.t_m.z();  // site z is down
    const double h2 = -g.site_from_cam2.t_m.z();
    if (st.isOk() && !(h1 > 0.0)) {
        st = Status(StatusCode::kDegenerate, "geometry: camera 1 is not above the site datum");
    }
    if (st.isOk() && !(h2 < h1)) {
        st = Status(StatusCode::kDegenerate, "geometry: image 2 is not closer than image 1 (no descent between them)");
    }
    if (st.isOk()) {
        st = setSweepRange(h1 * (1.0 - config_.relief_fraction), h1 * (1.0 + config_.relief_fraction));
    }
    return finish(Stage::kGeometry, st, st.isOk() ? static_cast<std::int64_t>(std::floor(100.0 * h1 + 0.5)) : 0, t0);
}

namespace {

// Longest ray length (metres) to a plane at depth z seen anywhere in the image: the
// corner rays of a pinhole are the longest.
double cornerRange(const CameraModel& m, double z) noexcept {
    const double dx = (m.cx_px + 0.5 > 0.5 * m.width_px) ? m.cx_px + 0.5 : m.width_px - 0.5 - m.cx_px;
    const double dy = (m.cy_px + 0.5 > 0.5 * m.height_px) ? m.cy_px + 0.5 : m.height_px - 0.5 - m.cy_px;
    const double ux = dx / m.fx_px;
    const double uy = dy / m.fy_px;
    return z * math::sqrt(1.0 + ux * ux + uy * uy);
}

}  // namespace

// The sweep's depth range from the refined features: their depths along camera 1's axis
// (range times the ray's axial component), min .. max widened on each side by
// feature_depth_margin times the middle of that range. One pass over the matches.
Status DescentMapper::depthRangeFromFeatures() noexcept {
    double lo = 0.0;
    double hi = 0.0;
    std::int32_t n = 0;
    const refine::Result& r = products_.refine;
    for (std::size_t i = 0U; i < r.pixels_a.size(); ++i) {
        if (r.inliers[i] == 0U || !math::isFinite(r.ranges_m[i])) {
            continue;
        }
        CameraRay ray;
        if (!backProjectPixel(model_, r.pixels_a[i], ray).isOk()) {
            continue;
        }
        const double depth = ray.origin_m.z() + r.ranges_m[i] * ray.direction.z();
        lo = (n == 0 || depth < lo) ? depth : lo;
        hi = (n == 0 || depth > hi) ? depth : hi;
        ++n;
    }
    if (n == 0 || !(lo > 0.0)) {
        return Status(StatusCode::kDegenerate, "refine: no inlier with a depth in front of camera 1");
    }
    const double margin = config_.feature_depth_margin * 0.5 * (lo + hi);
    const double zmin = lo - margin > 0.05 * lo ? lo - margin : 0.05 * lo;
    return setSweepRange(zmin, hi + margin);
}

// The refine stage: refine::PairRefiner on the ground scene, prior = the odometry's pose
// with the attitude prior; then the sweep's depth range from the inliers.
Status DescentMapper::refinePose() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    RigidPose& p1 = products_.geometry.site_from_cam1;
    RigidPose& p2 = products_.geometry.site_from_cam2;
    toGrey8(image1_, products_.frame1.bit_depth, grey1_);
    toGrey8(image2_, products_.frame2.bit_depth, grey2_);
    refine::Request rq;
    rq.prior.model_a = model_;
    rq.prior.model_b = model_;
    // Camera frames: X2 = R X1 + t.
    rq.prior.b_from_a = relativePose(p1, p2);
    rq.rotation_sigma_rad = config_.attitude_sigma_rad;
    rq.image_a = grey1_;
    rq.image_b = grey2_;
    rq.range_min_m = sweep_.config().depth_min_m;
    rq.range_max_m = cornerRange(model_, sweep_.config().depth_max_m);
    rq.scene = refine::Scene::kGround;
    rq.up_a = p1.R.transpose() * Vec3(0.0, 0.0, -1.0);  // level ground, up
    rq.camera_height_m = -p1.t_m.z();                   // site z is down
    refine::Result& r = products_.refine;
    Status st = refiner_.refine(rq, r);
    if (st.isOk()) {
        p2 = poseOfB(p1, r.refined.b_from_a);  // camera 2 refined
        st = depthRangeFromFeatures();
    }
    return finish(Stage::kRefine, st, st.isOk() ? r.motion.inliers : r.matching.matched, t0);
}

namespace {

// Horizontal 1-sigma of a pose (the larger of north and east), metres.
double horizontalSigmaM(const hal::PoseEstimate& pose) noexcept {
    const double v = pose.covariance[0] > pose.covariance[7] ? pose.covariance[0] : pose.covariance[7];
    return v > 0.0 ? math::sqrt(v) : 0.0;
}

}  // namespace

// The locate stage (orbital_fix.hpp): both frames in the orbital map; a usable fix
// replaces camera 1's horizontal position and the baseline length. Quality: frames used.
Status DescentMapper::locateInOrbitalMap() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    LocateInput in;
    in.model = model_;
    in.frame1 = image1_;
    in.frame2 = image2_;
    in.bit_depth1 = products_.frame1.bit_depth;
    in.bit_depth2 = products_.frame2.bit_depth;
    in.site_from_cam1 = products_.geometry.site_from_cam1;
    in.site_from_cam2 = products_.geometry.site_from_cam2;
    in.refine = &products_.refine;
    in.position_sigma_m[0] = horizontalSigmaM(pose1_);
    in.position_sigma_m[1] = horizontalSigmaM(pose2_);
    OrbitalFix& fix = products_.orbital;
    Status st = locator_.locate(in, fix);
    fix.status = st;
    if (st.isOk()) {
        st = applyOrbitalFix();
    }
    const std::int64_t used = (fix.frames[0].used ? 1 : 0) + (fix.frames[1].used ? 1 : 0);
    const bool ok = st.isOk();
    return finish(Stage::kLocate, ok || !config_.orbital.required ? Status::ok() : st, ok ? used : 0, t0);
}

// Camera 1 moves to its located horizontal position (its height stays the navigation's:
// an orthographic map does not show it); camera 2 follows at the located scale of the
// baseline when the two frames agree on it (scale_applied), and the sweep's depth range
// (from the features) scales with it.
Status DescentMapper::applyOrbitalFix() noexcept {
    OrbitalFix& fix = products_.orbital;
    RigidPose& p1 = products_.geometry.site_from_cam1;
    RigidPose& p2 = products_.geometry.site_from_cam2;
    const Vec3 baseline = p2.t_m - p1.t_m;
    const double k = fix.scale_applied ? fix.scale : 1.0;
    VTM_RETURN_IF_ERROR(setSweepRange(k * sweep_.config().depth_min_m, k * sweep_.config().depth_max_m));
    p1.t_m.x() = fix.camera1_ne_m.x();
    p1.t_m.y() = fix.camera1_ne_m.y();
    p2.t_m = p1.t_m + k * baseline;
    fix.applied = true;
    return Status::ok();
}

Status DescentMapper::runSweep() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    descent::SweepOutput out;
    out.depth_m = depth_;
    out.reason = reason_;
    Status st = sweep_.compute(image1_, image2_, products_.geometry, out, &products_.sweep);
    if (st.isOk() && products_.sweep.valid_pixels == 0) {
        st = Status(StatusCode::kNoData, "sweep: no pixel of image 1 got a depth");
    }
    return finish(Stage::kSweep, st, st.isOk() ? products_.sweep.valid_pixels : 0, t0);
}

Status DescentMapper::runGrid() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    const RigidPose& p1 = products_.geometry.site_from_cam1;
    const double h1 = -p1.t_m.z();
    const double cell = config_.grid_cell_m > 0.0 ? config_.grid_cell_m : 2.0 * h1 / model_.fx_px;
    const double half = 0.5 * static_cast<double>(config_.grid_cells) * cell;
    terrain::GridConfig grid;
    grid.cell_m = cell;
    grid.north_edge_m = p1.t_m.x() + half;  // centred under camera 1
    grid.west_edge_m = p1.t_m.y() - half;
    grid.cols = config_.grid_cells;
    grid.rows = config_.grid_cells;
    terrain::HeightMapStats stats;
    Status st = map_.setGrid(grid);
    if (st.isOk()) {
        st = descent::addDepthToHeightMap(depth_, model_, p1, map_, &stats);
    }
    products_.points_outside = stats.outside;
    const std::int64_t filled = st.isOk() ? map_.filledCells() : 0;
    if (st.isOk() && filled == 0) {
        st = Status(StatusCode::kNoData, "grid: no cell got an elevation (grid_cell_m, grid_cells?)");
    }
    products_.cells_filled = filled;
    return finish(Stage::kGrid, st, filled, t0);
}

Status DescentMapper::map() noexcept {
    published_ = false;
    stages_.clear();
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "DescentMapper::map: init() has not succeeded");
    }
    products_.refine = refine::Result{};
    products_.orbital = OrbitalFix{};
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture1, image1_, products_.frame1));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose1, products_.frame1, pose1_));
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture2, image2_, products_.frame2));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose2, products_.frame2, pose2_));
    VTM_RETURN_IF_ERROR(planGeometry());
    if (config_.refine_pose) {
        VTM_RETURN_IF_ERROR(refinePose());
    }
    if (config_.orbital.enabled) {
        VTM_RETURN_IF_ERROR(locateInOrbitalMap());
    }
    VTM_RETURN_IF_ERROR(runSweep());
    VTM_RETURN_IF_ERROR(runGrid());
    products_.depth_m = depth_;
    products_.reason = reason_;
    products_.height_map = &map_;
    products_.image1 = image1_;
    products_.image2 = image2_;
    published_ = true;
    return Status::ok();
}

}  // namespace vtm::app
