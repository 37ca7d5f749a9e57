#include "vtm/core/config_check.hpp"
#include "vtm/app/wide_baseline_mapper.hpp"

#include <cmath>

#include "request_support.hpp"
#include "vtm/core/math.hpp"
#include "vtm/terrain/ground_bound.hpp"
#include "vtm/terrain/rectified_geometry.hpp"

namespace vtm::app {
namespace {

using detail::carve;
using detail::toGrey8;

constexpr double kDegPerRad = 180.0 / math::kPi;

struct Sizes {
    std::size_t frame;      // pixels of one frame
    std::size_t rectified;  // pixels of one rectified image
};

std::int32_t rectifiedWidth(const WideBaselineMapperConfig& c) noexcept {
    return c.rectify.out_width > 0 ? c.rectify.out_width : c.frame_width;
}
std::int32_t rectifiedHeight(const WideBaselineMapperConfig& c) noexcept {
    return c.rectify.out_height > 0 ? c.rectify.out_height : c.frame_height;
}

Sizes sizesOf(const WideBaselineMapperConfig& c) noexcept {
    Sizes s{};
    s.frame = static_cast<std::size_t>(c.frame_width) * static_cast<std::size_t>(c.frame_height);
    s.rectified = static_cast<std::size_t>(rectifiedWidth(c)) * static_cast<std::size_t>(rectifiedHeight(c));
    return s;
}

// The sub-configurations with what the mapper states once in them: the capacities from
// the frame size (the stereo's from the rectified size) and the range interval.
refine::Config refineConfigOf(const WideBaselineMapperConfig& c) noexcept {
    refine::Config r = c.refine;
    r.max_width = c.frame_width;
    r.max_height = c.frame_height;
    return r;
}
rectify::Config rectifyConfigOf(const WideBaselineMapperConfig& c) noexcept {
    rectify::Config r = c.rectify;
    r.max_width = c.frame_width;
    r.max_height = c.frame_height;
    r.range_min_m = c.range_min_m;
    r.range_max_m = c.range_max_m;
    return r;
}
terrain::TriangulationLimits limitsOf(const WideBaselineMapperConfig& c) noexcept {
    terrain::TriangulationLimits l = c.limits;
    l.min_range_m = c.range_min_m;
    l.max_range_m = c.range_max_m;
    return l;
}

stereo::PyramidConfig stereoConfigOf(const WideBaselineMapperConfig& c) noexcept {
    stereo::PyramidConfig s = c.stereo;
    s.max_width = rectifiedWidth(c);
    s.max_height = rectifiedHeight(c);
    return s;
}
stereo::SpeckleConfig speckleConfigOf(const WideBaselineMapperConfig& c) noexcept {
    stereo::SpeckleConfig s = c.speckle;
    s.max_width = rectifiedWidth(c);
    s.max_height = rectifiedHeight(c);
    return s;
}

}  // namespace

stereo::PyramidConfig wideBaselineStereoConfig() noexcept {
    stereo::PyramidConfig s;
    s.matcher = stereo::Config::conservative();
    s.matcher.lr_max_diff_px = 2;
    return s;
}

refine::Config wideBaselineRefineConfig() noexcept {
    refine::Config r;
    r.matcher.max_verified = kWideBaselineMaxVerified;
    return r;
}

Status WideBaselineMapperConfig::validate() const noexcept {
    if (frame_width < 16 || frame_width > rectify::kMaxImageSide || frame_height < 16 ||
        frame_height > rectify::kMaxImageSide) {
        return invalidConfig("frame_width/frame_height: must be 16..4094", frame_width);
    }
    VTM_RETURN_IF_ERROR(validateMount(mount));
    VTM_RETURN_IF_ERROR(refineConfigOf(*this).validate());
    if (!math::isFinite(range_min_m) || !math::isFinite(range_max_m) || !(range_min_m > 0.0) ||
        !(range_max_m > range_min_m)) {
        return invalidConfig("range_min_m/range_max_m: need 0 < range_min_m < range_max_m, finite");
    }
    VTM_RETURN_IF_ERROR(rectifyConfigOf(*this).validate());
    VTM_RETURN_IF_ERROR(stereoConfigOf(*this).validate());
    VTM_RETURN_IF_ERROR(limitsOf(*this).validate());
    VTM_RETURN_IF_ERROR(height_map.validate());
    if (!isInRange(attitude_sigma_rad, 0.0, math::kPi)) {
        return invalidConfig("attitude_sigma_rad: must be 0..pi");
    }
    if (!(max_refined_sigma_ratio == 0.0 || isInRange(max_refined_sigma_ratio, 0.5, 100.0))) {
        return invalidConfig("max_refined_sigma_ratio: must be 0 (off) or 0.5..100");
    }
    if (!isInRange(relief_below_m, 0.0, 1000.0)) {
        return invalidConfig("relief_below_m: must be 0..1000");
    }
    if (!isInRange(min_baseline_m, 0.01, 100.0)) {
        return invalidConfig("min_baseline_m: must be 0.01..100");
    }
    if (exposure_tolerance_percent < 1 || exposure_tolerance_percent > 100) {
        return invalidConfig("exposure_tolerance_percent: must be 1..100");
    }
    VTM_RETURN_IF_ERROR(speckleConfigOf(*this).validate());
    return Status::ok();
}

std::size_t WideBaselineMapper::workspaceBytes(const WideBaselineMapperConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const Sizes s = sizesOf(config);
    return refine::PairRefiner::workspaceBytes(refineConfigOf(config))  // each module's own plan
           + rectify::Rectifier::workspaceBytes(rectifyConfigOf(config)) +
           stereo::PyramidStereo::workspaceBytes(stereoConfigOf(config)) +
           stereo::SpeckleFilter::workspaceBytes(speckleConfigOf(config)) +
           terrain::HeightMap::workspaceBytes(config.height_map) +
           Arena::arrayBytes<std::uint16_t>(s.frame)              // staging frame of a > 8-bit camera
           + 2U * Arena::arrayBytes<std::uint8_t>(s.frame)        // the two frames (8-bit)
           + 2U * Arena::arrayBytes<std::uint8_t>(s.rectified)    // rectified pair
           + 2U * Arena::arrayBytes<std::int16_t>(s.rectified)    // inlier plane's disparity, disparity
           + Arena::arrayBytes<float>(s.rectified)                // its sigma
           + Arena::arrayBytes<terrain::TerrainPoint>(s.rectified);  // one point per rectified pixel
}

Status WideBaselineMapper::init(const WideBaselineMapperConfig& config, Arena& arena, hal::Camera& camera,
                                hal::Odometry& odometry, const hal::Clock& clock, hal::EventLog& events) noexcept {
    initialized_ = false;
    published_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    hal::CameraDescription description;
    VTM_RETURN_IF_ERROR(camera.describe(description));
    if (description.width_px != config.frame_width || description.height_px != config.frame_height) {
        return Status(StatusCode::kSizeMismatch, "camera: frame size differs from frame_width/frame_height",
                      description.width_px);
    }
    const Status model_ok = validateCameraModel(description.model);
    if (!model_ok.isOk()) {
        return Status(StatusCode::kInvalidArgument, model_ok.reason(), model_ok.detail());
    }
    const std::size_t before = arena.usedBytes();
    VTM_RETURN_IF_ERROR(refiner_.init(refineConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(rectifier_.init(rectifyConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(stereo_.init(stereoConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(speckle_.init(speckleConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(map_.init(config.height_map, arena));
    const std::int32_t w = config.frame_width;
    const std::int32_t h = config.frame_height;
    const std::int32_t rw = rectifiedWidth(config);
    const std::int32_t rh = rectifiedHeight(config);
    frame16_ = carve<std::uint16_t>(arena, w, h);
    grey1_ = carve<std::uint8_t>(arena, w, h);
    grey2_ = carve<std::uint8_t>(arena, w, h);
    rect1_ = carve<std::uint8_t>(arena, rw, rh);
    rect2_ = carve<std::uint8_t>(arena, rw, rh);
    surface_ = carve<std::int16_t>(arena, rw, rh);
    disparity_ = carve<std::int16_t>(arena, rw, rh);
    sigma_ = carve<float>(arena, rw, rh);
    points_ = arena.allocateArray<terrain::TerrainPoint>(sizesOf(config).rectified);
    if (frame16_.data() == nullptr || grey1_.data() == nullptr ||
        grey2_.data() == nullptr || rect1_.data() == nullptr ||
        rect2_.data() == nullptr || surface_.data() == nullptr || disparity_.data() == nullptr ||
        sigma_.data() == nullptr || points_.empty()) {
        return Status(StatusCode::kOutOfMemory, "WideBaselineMapper::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    memory_bytes_ = arena.usedBytes() - before;
    config_ = config;
    model_ = description.model;
    bit_depth_ = description.bit_depth;
    camera_ = &camera;
    odometry_ = &odometry;
    clock_ = &clock;
    events_ = &events;
    initialized_ = true;
    return Status::ok();
}

Status WideBaselineMapper::finish(Stage stage, const Status& status, std::int64_t quality,
                                  std::uint64_t t0_ns) noexcept {
    return detail::recordStage(stages_, *events_, *clock_, stage, status, quality, t0_ns);
}

Status WideBaselineMapper::capture(Stage stage, const ImageView<std::uint8_t>& image, hal::FrameInfo& info) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    // 8-bit cameras straight into the 8-bit frame; deeper ones through the 16-bit staging
    // frame, keeping their top 8 bits.
    Status st = bit_depth_ > 8U ? camera_->capture16(frame16_, info) : camera_->capture(image, info);
    if (st.isOk() && (info.width_px != image.width() || info.height_px != image.height())) {
        st = Status(StatusCode::kSizeMismatch, "capture: the frame's size differs from the camera's description",
                    info.width_px);
    }
    if (st.isOk() && bit_depth_ > 8U) {
        toGrey8(frame16_, info.bit_depth, image);
    }
    return finish(stage, st, st.isOk() ? static_cast<std::int64_t>(info.sequence) : 0, t0);
}

Status WideBaselineMapper::poseOf(Stage stage, const hal::FrameInfo& info, hal::PoseEstimate& pose) noexcept {
    return detail::poseStage(*odometry_, stages_, *events_, *clock_, stage, info, pose);
}

Status WideBaselineMapper::planGeometry() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    Status st = cameraPoseInSite(pose1_, config_.mount, p.site_from_cam1);
    if (st.isOk()) {
        st = cameraPoseInSite(pose2_, config_.mount, p.site_from_cam2);
    }
    double baseline = 0.0;
    if (st.isOk()) {
        p.odometry_2_from_1 = relativePose(p.site_from_cam1, p.site_from_cam2);  // X2 = R X1 + t
        baseline = math::sqrt(p.odometry_2_from_1.t_m.squaredNorm());
        if (!(baseline >= config_.min_baseline_m)) {
            st = Status(StatusCode::kDegenerate, "geometry: the rover moved less than min_baseline_m between the frames",
                        static_cast<std::int64_t>(std::floor(1000.0 * baseline + 0.5)));
        }
    }
    return finish(Stage::kGeometry, st, st.isOk() ? static_cast<std::int64_t>(std::floor(1000.0 * baseline + 0.5)) : 0,
                  t0);
}

// The refine stage: refine::PairRefiner on the ground scene, prior = the odometry's pose.
Status WideBaselineMapper::refinePose() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    refine::Request rq;
    rq.prior.model_a = model_;
    rq.prior.model_b = model_;
    rq.prior.b_from_a = p.odometry_2_from_1;
    rq.rotation_sigma_rad = config_.attitude_sigma_rad;
    rq.image_a = grey1_;
    rq.image_b = grey2_;
    rq.range_min_m = config_.range_min_m;
    rq.range_max_m = config_.range_max_m;
    rq.scene = refine::Scene::kGround;
    rq.up_a = p.site_from_cam1.R.transpose() * Vec3(0.0, 0.0, -1.0);  // level ground, up
    // The mast camera's height above the ground the rover stands on (site z is down; the
    // vehicle frame's origin is on the ground).
    const double height = pose1_.position_m[2] - p.site_from_cam1.t_m.z();
    rq.camera_height_m = height > 0.05 ? height : 0.05;
    Status st = refiner_.refine(rq, p.refine);
    if (st.isOk() && !detail::refinementIsCertainEnough(p.refine.motion.rotation_sigma_rad,
                                                        detail::relativeRotationSigmaRad(pose1_, pose2_),
                                                        config_.max_refined_sigma_ratio)) {
        st = Status(StatusCode::kDegenerate,
                    "refine: the refined rotation is less certain than max_refined_sigma_ratio x the odometry's "
                    "(detail: its 1-sigma, millidegrees)",
                    static_cast<std::int64_t>(std::floor(1000.0 * kDegPerRad * p.refine.motion.rotation_sigma_rad + 0.5)));
    }
    if (st.isOk()) {
        p.site_from_cam2 = poseOfB(p.site_from_cam1, p.refine.refined.b_from_a);  // camera 2 refined
    }
    return finish(Stage::kRefine, st, st.isOk() ? p.refine.motion.inliers : p.refine.matching.matched, t0);
}

Status WideBaselineMapper::runRectify() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    rectify::RectifyInput in;
    in.pair = p.refine.refined;  // the camera's model twice and the refined b_from_a
    Status st = rectifier_.compute(in, p.rectified);
    if (st.isOk()) {
        st = rectifier_.remap(rectify::Rectifier::Side::kA, grey1_, rect1_);
    }
    if (st.isOk()) {
        st = rectifier_.remap(rectify::Rectifier::Side::kB, grey2_, rect2_);
    }
    if (st.isOk()) {
        // The rectified left camera in the site frame, for the triangulation.
        st = terrain::rectifiedGeometry(p.rectified, p.site_from_cam1, p.triangulation_geometry);
    }
    return finish(Stage::kRectify, st,
                  st.isOk() ? static_cast<std::int64_t>(std::floor(100.0 * p.rectified.convergence_deg + 0.5)) : 0, t0);
}

// The coarse search's surface: the plane in disparity space through the refined inliers'
// rectified disparities (stereo::fitDisparityPlane), within the rectifier's bounds.
Status WideBaselineMapper::searchSurface() noexcept {
    WideBaselineProducts& p = products_;
    std::size_t n = 0U;
    const refine::Result& r = p.refine;
    for (std::size_t i = 0U; i < r.pixels_a.size() && n < features::kMaxFeatures; ++i) {
        Vec2 ra;
        Vec2 rb;
        if (r.inliers[i] == 0U || !rectifier_.rectifyPixel(rectify::Rectifier::Side::kA, r.pixels_a[i], ra).isOk() ||
            !rectifier_.rectifyPixel(rectify::Rectifier::Side::kB, r.pixels_b[i], rb).isOk()) {
            continue;
        }
        samples_[n] = Vec3(ra.x(), ra.y(), ra.x() - rb.x());
        ++n;
    }
    if (n < 3U) {
        return Status(StatusCode::kDegenerate, "stereo: fewer than 3 refined inliers map into the rectified pair",
                      static_cast<std::int64_t>(n));
    }
    VTM_RETURN_IF_ERROR(stereo::fitDisparityPlane(Span<const Vec3>(samples_, n),
                                                  Span<double>(residuals_, features::kMaxFeatures), p.inlier_plane));
    // Inside the disparities MlStereo can represent (a 3 m range at a 5 m baseline is beyond).
    constexpr std::int32_t kLimit = 2000;
    return stereo::fillDisparityPlane(p.inlier_plane, p.disparity_min > -kLimit ? p.disparity_min : -kLimit,
                                      p.disparity_max < kLimit ? p.disparity_max : kLimit, surface_);
}

// PyramidStereo around the inlier plane; the speckle filter; then the ground bound (terrain::boundByGround) drops
// disparities that a plane relief_below_m under that ground puts beyond the bounds.
Status WideBaselineMapper::runStereo() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    p.disparity_min = p.rectified.d_min;
    p.disparity_max = p.rectified.d_max;
    const double ground_z = pose1_.position_m[2];  // site z is down; the vehicle's origin is on the ground
    p.exposure_gain_q16 = detail::equalizeExposure(rect1_, rect2_, config_.exposure_tolerance_percent);
    Status st = searchSurface();
    const stereo::DisparityOutput out{disparity_, sigma_, {}};
    if (st.isOk()) {
        st = stereo_.compute(rect1_, rect2_, surface_, p.disparity_min, p.disparity_max, out, &p.pyramid);
        p.stereo = p.pyramid.fine;
    }
    if (st.isOk()) {
        st = speckle_.apply(out, &p.stereo, &p.speckles);
    }
    if (st.isOk()) {
        const double plane_z = ground_z + config_.relief_below_m;
        st = terrain::boundByGround(p.triangulation_geometry, plane_z, p.disparity_min, p.disparity_max, disparity_,
                                    p.outside_window);
    }
    if (st.isOk() && p.stereo.valid_pixels == p.outside_window) {
        st = Status(StatusCode::kNoData, "stereo: no pixel of the rectified pair got a disparity");
    }
    return finish(Stage::kStereo, st, st.isOk() ? p.stereo.valid_pixels - p.outside_window : 0, t0);
}

Status WideBaselineMapper::runTriangulate() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    p.triangulation = terrain::TriangulationStats{};
    Status st = terrain::triangulate(p.triangulation_geometry, limitsOf(config_), disparity_, sigma_, points_,
                                     p.triangulation);
    if (st.isOk() && p.triangulation.points == 0) {
        st = Status(StatusCode::kNoData, "triangulate: no disparity gave a point within the range interval");
    }
    return finish(Stage::kTriangulate, st, st.isOk() ? p.triangulation.points : 0, t0);
}

Status WideBaselineMapper::runGrid() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    WideBaselineProducts& p = products_;
    map_.clear();
    p.map = terrain::HeightMapStats{};
    const Span<const terrain::TerrainPoint> points(points_.data(), static_cast<std::size_t>(p.triangulation.points));
    Status st = map_.add(points, &p.map);
    if (st.isOk() && map_.filledCells() == 0) {
        st = Status(StatusCode::kNoData,
                    "grid: no point fell inside the site grid (height_map.grid: edges, cell_m, cols/rows?)");
    }
    return finish(Stage::kGrid, st, st.isOk() ? map_.filledCells() : 0, t0);
}

Status WideBaselineMapper::map() noexcept {
    published_ = false;
    stages_.clear();
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "WideBaselineMapper::map: init() has not succeeded");
    }
    products_.refine = refine::Result{};
    products_.stereo = stereo::StereoStats{};
    products_.pyramid = stereo::PyramidStats{};
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture1, grey1_, products_.frame1));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose1, products_.frame1, pose1_));
    VTM_RETURN_IF_ERROR(capture(Stage::kCapture2, grey2_, products_.frame2));
    VTM_RETURN_IF_ERROR(poseOf(Stage::kPose2, products_.frame2, pose2_));
    VTM_RETURN_IF_ERROR(planGeometry());
    VTM_RETURN_IF_ERROR(refinePose());
    VTM_RETURN_IF_ERROR(runRectify());
    VTM_RETURN_IF_ERROR(runStereo());
    VTM_RETURN_IF_ERROR(runTriangulate());
    VTM_RETURN_IF_ERROR(runGrid());
    products_.image1 = grey1_;
    products_.image2 = grey2_;
    products_.rectified1 = rect1_;
    products_.rectified2 = rect2_;
    products_.disparity_px16 = disparity_;
    products_.sigma_px = sigma_;
    products_.surface_px = surface_;
    products_.prior_px = stereo_.prior();
    products_.points = Span<const terrain::TerrainPoint>(points_.data(),
                                                         static_cast<std::size_t>(products_.triangulation.points));
    products_.height_map = &map_;
    products_.camera = model_;
    published_ = true;
    return Status::ok();
}

}  // namespace vtm::app
