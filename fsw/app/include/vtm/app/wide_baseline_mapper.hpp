// WideBaselineMapper: the rover's wide-baseline mapping executive (issue 7, paper §2 and
// §6). The rover images the terrain ahead from one place, drives a few metres sideways
// and images it again; the two frames are one stereo pair with a baseline of metres.
// Initialised once from a validated configuration, it owns all its memory (planned by
// workspaceBytes and taken from the caller's Arena at init). Each map() request:
//   capture1     image 1 through hal::Camera (capture for 8-bit cameras; deeper ones
//                through capture16, their top 8 bits kept)
//   pose1        hal::Odometry at image 1's timestamp
//   capture2     image 2 (the next frame: after the drive)
//   pose2        the pose at image 2's timestamp
//   geometry     camera poses from the vehicle poses and the mount; the baseline must be
//                at least min_baseline_m
//   refine       refine::PairRefiner on the ground scene (docs/refine.md): Förstner
//                features of image 1 where image 2 sees it (visibility from the odometry and
//                the ground plane under the camera), guided template matching into image 2
//                inside the region that the odometry and the range interval predict,
//                MotionRefiner (LM over rotation and translation direction, one depth per
//                feature; the baseline length stays the odometry's); camera 2's pose is
//                replaced by the refined one
//   rectify      Fusiello rectification of the refined pair and both remapped images
//   stereo       coarse to fine (stereo::PyramidStereo): the coarse level (half size)
//                searches around the plane in disparity space through the refined
//                inliers' rectified disparities (stereo::fitDisparityPlane; its window
//                sheared along the plane), the full resolution searches around the
//                coarse result; speckles are dropped; disparities whose ray the ground
//                bound puts beyond the rectifier's bounds for the range interval are
//                dropped (terrain::boundByGround, relief_below_m)
//   triangulate  every disparity to a site point with its range sigma (fsw/terrain)
//   grid         terrain::HeightMap on the configured site grid (height_map: the highest
//                point per cell by default)
// Every stage leaves a StageRecord (Status, quality figure, time from hal::Clock) in
// stages() and one event in hal::EventLog (stage_log.hpp). The first stage that fails
// ends the request with its Status and nothing is published: products() is nullptr until
// a request succeeds, and again from the start of the next one. A published product stays
// valid until the next map().
//
// No heap, no exceptions; deterministic for the same frames and poses. docs/app.md.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/camera.hpp"
#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "hal/odometry.hpp"
#include "vtm/app/camera_mount.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/features/features.hpp"
#include "vtm/motion/motion_refiner.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/stereo/disparity_plane.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#include "vtm/stereo/pyramid_stereo.hpp"
#include "vtm/stereo/speckle_filter.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::app {

// The dense stereo of the default flight configuration: PyramidStereo's defaults (one
// level down, 128 coarse disparities around the inlier plane, +-12 px at full
// resolution) with the conservative matcher's left-right check at 2 px (uniqueness is
// off in PyramidStereo; docs/app.md has the measurements).
[[nodiscard]] stereo::PyramidConfig wideBaselineStereoConfig() noexcept;

// The pose refinement of the default flight configuration: refine::Config's defaults with
// the matcher's verification (affine refinement and backward search) for at most
// kWideBaselineMaxVerified features of a pair, those with the best forward scores: the
// refine stage's work then stays within 1.1x of the shipped scene's for any image content
// (issue 22 item 5; an image where every forward search passes costs 1.38x without it).
// The shipped scene passes 89 forward searches at 1024^2 (every one verified); of the 20
// worlds of docs/app.md, four pass more (101-192): docs/app.md "Cost of the refine stage by
// content" has their maps.
constexpr std::int32_t kWideBaselineMaxVerified = 96;
[[nodiscard]] refine::Config wideBaselineRefineConfig() noexcept;

struct WideBaselineMapperConfig {
    // Capacities, stated once: the camera's frame size. The mapper sets refine's and
    // rectify's max_width/max_height from it, and stereo's and speckle's from the rectified
    // size (rectify.out_* or the frame size); those fields of the sub-configurations are
    // not read.
    std::int32_t frame_width = 1024;
    std::int32_t frame_height = 1024;
    CameraMount mount{};  // the mast camera on the rover
    // The pose refinement (stage refine): detector, matcher, motion, the matching window
    // around the odometry's prediction (refine.match_margin_px, image-2 pixels: a heading
    // error of ~2.3 deg at fx ~1236 px with half again as margin, 75 px by default) and the
    // visibility margin. The motion's range limits are replaced by range_*_m.
    refine::Config refine = wideBaselineRefineConfig();
    // 1-sigma per axis of the odometry's relative rotation between the frames, radians,
    // 0..pi: the refiner's rotation prior. 0 = none (the rover's heading error is large).
    double attitude_sigma_rad = 0.0;
    // The refinement's own rotation 1-sigma may exceed the odometry's (from the two poses'
    // covariances, request_support.hpp) by at most this factor, else the request ends at
    // refine (kDegenerate): a pose less certain than its prior is not published.
    // 0 = off; 0.5..100. Not applied when the odometry states no rotation covariance.
    double max_refined_sigma_ratio = 2.0;
    rectify::Config rectify{};       // its range limits are replaced by range_*_m
    stereo::PyramidConfig stereo = wideBaselineStereoConfig();
    terrain::TriangulationLimits limits{};  // its range limits are replaced by range_*_m
    // The terrain's range along camera 1's rays: the matching's search segment, the
    // refiner's clamp, the rectifier's disparity bounds, the triangulation's limits.
    double range_min_m = 3.0;
    double range_max_m = 300.0;  // the far end of the band the map is for (issue 21)
    double min_baseline_m = 0.2;  // shorter drives are refused (kDegenerate), 0.01..100
    // The ML stereo compares grey levels, so frames taken with other exposures (an auto
    // exposure, a gain fault) would not match: when the median grey levels of the
    // rectified pair differ by more than this, percent, 1..100, rectified 2 is scaled to
    // rectified 1's (docs/app.md "Faults": a gain of 2 on frame 2 gave a 10 % median range
    // error before).
    std::int32_t exposure_tolerance_percent = 15;
    // How far the terrain may lie below the ground the rover stands on (craters, down
    // slopes), metres, 0..1000: along a ray that points down the terrain is hit no farther
    // than this plane, which bounds the ray's disparity; a disparity found in the window
    // when that bound lies beyond it is a wrong match and is dropped (stereo stage).
    double relief_below_m = 3.0;
    // Speckle filter after the stereo (stereo::SpeckleFilter; its capacity is replaced by
    // stereo's): islands of at most speckle.max_region_px disparities (100 at 1024²; scale
    // with the image area) are dropped. Isolated wrong disparities on far rays put points
    // high over the ground, and a height-map cell keeps its highest point (docs/app.md).
    stereo::SpeckleConfig speckle = defaultSpeckle();

    // Neighbours within 3 px are one region: level ground changes by about baseline /
    // camera height px per row (1.5 px on the mission pair), which splits it into rows at
    // the filter's 1 px default (measured: docs/app.md).
    [[nodiscard]] static stereo::SpeckleConfig defaultSpeckle() noexcept {
        stereo::SpeckleConfig s;
        s.max_diff_px16 = 3 * stereo::kDisparityScale;
        return s;
    }
    // The height map: its site grid (north-west corner, cell, size; terrain::GridConfig)
    // and reducer (the highest point per cell, paper §6). Every request maps into the same
    // grid, so successive maps merge (terrain::HeightMap::merge).
    terrain::HeightMapConfig height_map = defaultHeightMap();

    [[nodiscard]] static terrain::HeightMapConfig defaultHeightMap() noexcept {
        terrain::HeightMapConfig m;
        m.grid.cell_m = 0.25;
        m.grid.cols = 512;
        m.grid.rows = 512;
        m.grid.north_edge_m = 64.0;  // 128 m x 128 m centred on the site origin
        m.grid.west_edge_m = -64.0;
        m.reducer = terrain::Reducer::kHighest;
        return m;
    }
    // kOk, or kInvalidConfig naming the field (sub-configurations as their validate()
    // names them).
    [[nodiscard]] Status validate() const noexcept;
};

// What a successful request publishes. Views point into the mapper's memory.
struct WideBaselineProducts {
    ImageView<const std::uint8_t> image1;       // the captured frames (8-bit)
    ImageView<const std::uint8_t> image2;
    ImageView<const std::uint8_t> rectified1;   // the rectified pair (8-bit)
    ImageView<const std::uint8_t> rectified2;  // after the exposure equalisation (exposure_gain_q16)
    ImageView<const std::int16_t> disparity_px16;  // rectified 1's size, 1/16 px, d = x1 - x2; kNoDisparity
    ImageView<const float> sigma_px;               // 1-sigma of each disparity, px
    ImageView<const std::int16_t> surface_px;      // the inlier plane's disparity, whole px (the coarse search's centre)
    ImageView<const std::int16_t> prior_px;        // the full-resolution search's centre, whole px; kNoDisparity
    Span<const terrain::TerrainPoint> points;      // site frame, row-major over rectified 1
    const terrain::HeightMap* height_map = nullptr;
    CameraModel camera{};                   // the camera's model (both frames)
    RigidPose site_from_cam1{};
    RigidPose site_from_cam2{};     // refined
    RigidPose odometry_2_from_1{};  // the odometry's relative pose (X2 = R X1 + t_m)
    rectify::RectifiedPair rectified{};
    terrain::RectifiedGeometry triangulation_geometry{};
    hal::FrameInfo frame1{};
    hal::FrameInfo frame2{};
    // The refine stage's result (refine::PairRefiner): the refined pair, counts per step,
    // matches, inliers and their ranges, the motion and its covariance, the change from the
    // odometry in degrees (rotation_change_deg, direction_change_deg).
    refine::Result refine{};
    std::int32_t disparity_min = 0;     // the range searched, px (inclusive): the rectifier's
    std::int32_t disparity_max = 0;     // bounds for the range interval
    // The gain the stereo stage applied to rectified 2 (1/65536; 65536: none, the medians of
    // the pair agreed within exposure_tolerance_percent).
    std::uint32_t exposure_gain_q16 = 65536U;
    stereo::PyramidStats pyramid{};        // the coarse and the full-resolution search
    stereo::StereoStats stereo{};          // pyramid.fine after the speckle filter
    stereo::DisparityPlane inlier_plane{};  // the coarse search's surface (its fit to the inliers)
    std::int32_t speckles = 0;             // disparities dropped by the speckle filter
    std::int32_t outside_window = 0;       // disparities dropped by the ground bound (relief_below_m)
    terrain::TriangulationStats triangulation{};
    terrain::HeightMapStats map{};
};

class WideBaselineMapper {
public:
    // Arena bytes for this configuration, 0 if it is invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const WideBaselineMapperConfig& config) noexcept;

    // Validates the config, asks the camera for its description and carves the memory.
    // The drivers are borrowed and must outlive the mapper. kInvalidConfig (config field),
    // kSizeMismatch ("camera: frame size differs from frame_width/frame_height"),
    // kInvalidArgument (validateCameraModel's reason for the camera's model), kOutOfMemory
    // (arena), or the camera's describe() Status.
    [[nodiscard]] Status init(const WideBaselineMapperConfig& config, Arena& arena, hal::Camera& camera,
                              hal::Odometry& odometry, const hal::Clock& clock, hal::EventLog& events) noexcept;

    // One request (see the file comment). kNotInitialized before a successful init();
    // otherwise the failing stage's Status, e.g. kNoData from capture2 for a dropped frame,
    // kCorruptData from pose1 for a NaN pose, kDegenerate from geometry for a short drive
    // or from refine with too few inliers, kNoData from stereo / triangulate / grid when
    // nothing was left.
    [[nodiscard]] Status map() noexcept;

    [[nodiscard]] const WideBaselineProducts* products() const noexcept {
        return published_ ? &products_ : nullptr;
    }
    [[nodiscard]] const StageLog& stages() const noexcept { return stages_; }
    [[nodiscard]] std::size_t memoryBytes() const noexcept { return memory_bytes_; }

private:
    [[nodiscard]] Status capture(Stage stage, const ImageView<std::uint8_t>& image, hal::FrameInfo& info) noexcept;
    [[nodiscard]] Status poseOf(Stage stage, const hal::FrameInfo& info, hal::PoseEstimate& pose) noexcept;
    [[nodiscard]] Status planGeometry() noexcept;
    [[nodiscard]] Status refinePose() noexcept;
    [[nodiscard]] Status runRectify() noexcept;
    [[nodiscard]] Status searchSurface() noexcept;
    [[nodiscard]] Status runStereo() noexcept;
    [[nodiscard]] Status runTriangulate() noexcept;
    [[nodiscard]] Status runGrid() noexcept;
    Status finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

    WideBaselineMapperConfig config_{};
    hal::Camera* camera_ = nullptr;
    hal::Odometry* odometry_ = nullptr;
    const hal::Clock* clock_ = nullptr;
    hal::EventLog* events_ = nullptr;
    CameraModel model_{};
    refine::PairRefiner refiner_{};
    rectify::Rectifier rectifier_{};
    stereo::PyramidStereo stereo_{};
    stereo::SpeckleFilter speckle_{};
    terrain::HeightMap map_{};
    ImageView<std::uint16_t> frame16_{};  // staging frame of a camera of more than 8 bits
    ImageView<std::uint8_t> grey1_{};
    ImageView<std::uint8_t> grey2_{};
    ImageView<std::uint8_t> rect1_{};
    ImageView<std::uint8_t> rect2_{};
    Vec3 samples_[features::kMaxFeatures] = {};   // the inliers' rectified (x, y, disparity)
    double residuals_[features::kMaxFeatures] = {};
    ImageView<std::int16_t> surface_{};  // the inlier plane's disparity (the coarse search's centre)
    ImageView<std::int16_t> disparity_{};
    ImageView<float> sigma_{};
    Span<terrain::TerrainPoint> points_{};
    hal::PoseEstimate pose1_{};
    hal::PoseEstimate pose2_{};
    WideBaselineProducts products_{};
    StageLog stages_{};
    std::size_t memory_bytes_ = 0U;
    std::uint8_t bit_depth_ = 8U;
    bool initialized_ = false;
    bool published_ = false;
};

}  // namespace vtm::app
