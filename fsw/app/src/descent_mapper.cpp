#include "vtm/app/descent_mapper.hpp"

#include "vtm/core/math.hpp"

namespace vtm::app {
namespace {

Status invalid(const char* reason, std::int64_t value = 0) noexcept {
    return Status(StatusCode::kInvalidConfig, reason, value);
}

// Element counts of the mapper's own buffers (the sweep plans its own).
struct Buffers {
    std::size_t pixels;  // one frame
    std::size_t cells;   // the grid
};

Buffers buffersOf(const DescentMapperConfig& c) noexcept {
    Buffers b{};
    b.pixels = static_cast<std::size_t>(c.sweep.max_width) * static_cast<std::size_t>(c.sweep.max_height);
    b.cells = static_cast<std::size_t>(c.grid_cells) * static_cast<std::size_t>(c.grid_cells);
    return b;
}

template <typename T>
std::size_t bytesOf(std::size_t count) noexcept {
    const std::size_t align = alignof(T) > Arena::kDefaultAlignment ? alignof(T) : Arena::kDefaultAlignment;
    return Arena::blockBytes(count * sizeof(T), align);
}

template <typename T>
ImageView<T> carve(Arena& arena, std::int32_t width, std::int32_t height) noexcept {
    const Span<T> s = arena.allocateArray<T>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    return s.empty() ? ImageView<T>() : ImageView<T>(s.data(), width, height);
}

bool isUndistortedPinhole(const CameraModel& m) noexcept {
    return m.kind == CameraModelKind::kPinholeBrown && m.k1 == 0.0 && m.k2 == 0.0 && m.k3 == 0.0 && m.p1 == 0.0 &&
           m.p2 == 0.0;
}

// Position sigma (mm) of a pose: sqrt of the trace of its position covariance.
std::int64_t positionSigmaMm(const hal::PoseEstimate& p) noexcept {
    const double trace = p.covariance[0] + p.covariance[7] + p.covariance[14];
    return static_cast<std::int64_t>(1000.0 * math::sqrt(trace > 0.0 ? trace : 0.0) + 0.5);
}

}  // namespace

Status DescentMapperConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(sweep.validate());
    VTM_RETURN_IF_ERROR(validateMount(mount));
    if (!math::isFinite(relief_fraction) || relief_fraction < 0.01 || relief_fraction > 0.9) {
        return invalid("relief_fraction: must be 0.01..0.9");
    }
    if (!math::isFinite(parallax_factor) || parallax_factor < 0.0 || parallax_factor > 1000.0) {
        return invalid("parallax_factor: must be 0..1000");
    }
    if (grid_cells < 16 || grid_cells > kMaxGridCells) {
        return invalid("grid_cells: must be 16..4096", grid_cells);
    }
    if (!math::isFinite(grid_cell_m) || grid_cell_m < 0.0 || grid_cell_m > 1.0e4) {
        return invalid("grid_cell_m: must be 0 (one pixel at the camera height) or a cell in metres up to 1e4");
    }
    return Status::ok();
}

std::size_t DescentMapper::workspaceBytes(const DescentMapperConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const Buffers b = buffersOf(config);
    return descent::PlaneSweep::workspaceBytes(config.sweep)  // the sweep's own plan
           + 2U * bytesOf<std::uint16_t>(b.pixels)            // image 1, image 2
           + bytesOf<float>(b.pixels)                         // depth of image 1
           + bytesOf<std::uint8_t>(b.pixels)                  // reason per pixel
           + bytesOf<float>(b.cells)                          // elevation grid
           + bytesOf<std::uint16_t>(b.cells);                 // points per cell
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
    if (!isUndistortedPinhole(description.model)) {
        return Status(StatusCode::kUnsupported, "camera: model is not an undistorted pinhole (undistort first)");
    }
    const std::size_t before = arena.usedBytes();
    VTM_RETURN_IF_ERROR(sweep_.init(config.sweep, arena));
    const std::int32_t w = config.sweep.max_width;
    const std::int32_t h = config.sweep.max_height;
    image1_ = carve<std::uint16_t>(arena, w, h);
    image2_ = carve<std::uint16_t>(arena, w, h);
    depth_ = carve<float>(arena, w, h);
    reason_ = carve<std::uint8_t>(arena, w, h);
    elevation_ = carve<float>(arena, config.grid_cells, config.grid_cells);
    count_ = carve<std::uint16_t>(arena, config.grid_cells, config.grid_cells);
    if (image1_.data() == nullptr || image2_.data() == nullptr || depth_.data() == nullptr ||
        reason_.data() == nullptr || elevation_.data() == nullptr || count_.data() == nullptr) {
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

Status DescentMapper::finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept {
    const std::uint64_t now = clock_->monotonicNs();
    StageRecord r;
    r.stage = stage;
    r.status = status;
    r.quality = quality;
    r.duration_ns = now >= t0_ns ? now - t0_ns : 0U;
    stages_.add(r);
    hal::Event e;
    e.timestamp_ns = now;
    e.id = static_cast<std::uint16_t>(kEventStageBase + static_cast<std::uint16_t>(stage));
    e.severity = status.isOk() ? hal::Severity::kInfo : hal::Severity::kError;
    e.args[0] = static_cast<std::int64_t>(status.code());
    e.args[1] = status.detail();
    e.args[2] = quality;
    e.args[3] = static_cast<std::int64_t>(r.duration_ns / 1000U);
    events_->record(e);
    return status;
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
    const std::uint64_t t0 = clock_->monotonicNs();
    const Status st = odometry_->poseAt(info.timestamp_ns, pose);
    return finish(stage, st, st.isOk() ? positionSigmaMm(pose) : 0, t0);
}

Status DescentMapper::planGeometry() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    descent::PairGeometry& g = products_.geometry;
    g.camera = model_;
    Status st = cameraPoseInSite(pose1_, config_.mount, g.pose1.R_site_from_cam, g.pose1.position_site_m);
    if (st.isOk()) {
        st = cameraPoseInSite(pose2_, config_.mount, g.pose2.R_site_from_cam, g.pose2.position_site_m);
    }
    const double h1 = -g.pose1.position_site_m.z();  // site z is down
    const double h2 = -g.pose2.position_site_m.z();
    if (st.isOk() && !(h1 > 0.0)) {
        st = Status(StatusCode::kDegenerate, "geometry: camera 1 is not above the site datum");
    }
    if (st.isOk() && !(h2 < h1)) {
        st = Status(StatusCode::kDegenerate, "geometry: image 2 is not closer than image 1 (no descent between them)");
    }
    if (st.isOk()) {
        const double zmin = h1 * (1.0 - config_.relief_fraction);
        const double zmax = h1 * (1.0 + config_.relief_fraction);
        const double parallax = config_.parallax_factor * (1.0 / zmin - 1.0 / zmax) * 0.5 * (zmin + zmax);
        st = sweep_.setDepthRange(zmin, zmax, parallax < 1000.0 ? parallax : 1000.0);
    }
    return finish(Stage::kGeometry, st, st.isOk() ? static_cast<std::int64_t>(100.0 * h1 + 0.5) : 0, t0);
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
    const descent::CameraPose& p1 = products_.geometry.pose1;
    const double h1 = -p1.position_site_m.z();
    const double cell = config_.grid_cell_m > 0.0 ? config_.grid_cell_m : h1 / model_.fx_px;
    const double half = 0.5 * static_cast<double>(config_.grid_cells) * cell;
    descent::GridSpec& grid = products_.grid;
    grid.cell_m = cell;
    grid.origin_north_m = p1.position_site_m.x() + half;
    grid.origin_east_m = p1.position_site_m.y() - half;
    products_.points_outside = 0;
    Status st = descent::elevationGrid(depth_, model_, p1, grid, elevation_, count_, &products_.points_outside);
    std::int64_t filled = 0;
    if (st.isOk()) {
        for (std::int32_t y = 0; y < count_.height(); ++y) {
            const std::uint16_t* row = count_.row(y);
            for (std::int32_t x = 0; x < count_.width(); ++x) {
                filled += row[x] != 0U ? 1 : 0;
            }
        }
        if (filled == 0) {
            st = Status(StatusCode::kNoData, "grid: no cell got an elevation (grid_cell_m, grid_cells?)");
        }
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
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture1, image1_, products_.frame1));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose1, products_.frame1, pose1_));
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture2, image2_, products_.frame2));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose2, products_.frame2, pose2_));
    VTM_RETURN_IF_ERROR(planGeometry());
    VTM_RETURN_IF_ERROR(runSweep());
    VTM_RETURN_IF_ERROR(runGrid());
    products_.depth_m = depth_;
    products_.reason = reason_;
    products_.elevation_m = elevation_;
    products_.count = count_;
    products_.image1 = image1_;
    products_.image2 = image2_;
    published_ = true;
    return Status::ok();
}

}  // namespace vtm::app
