// DescentMapper: the lander's mapping executive (issue 7, paper §4). Initialised once from
// a validated configuration, it owns all its memory (planned by workspaceBytes and taken
// from the caller's Arena at init). Each map() request:
//   capture1  image 1 through hal::Camera (capture16: 8- or 12-bit frames)
//   pose1     hal::Odometry at image 1's timestamp
//   capture2  image 2 (the next frame: later, closer)
//   pose2     the pose at image 2's timestamp
//   geometry  camera poses from the vehicle poses and the mount; the depth range from
//             camera 1's height above the site datum, +-relief_fraction; image 2 must be
//             the closer one
//   refine    (refine_pose) the relative pose from the images, as the paper does before
//             the sweep: refine::PairRefiner on the ground scene (docs/refine.md):
//             Förstner features of image 1 where image 2 sees it, guided template
//             matching into image 2 (templates warped for the ground plane, so the scale
//             change between the frames is in the warp), MotionRefiner (LM over rotation
//             and translation direction, with the attitude prior; the baseline length stays
//             the odometry's); camera 2's pose is replaced by the refined one, and the
//             sweep's depth range becomes the inliers' depth range
//   locate    (orbital.enabled, with an orbital map set) both frames registered to the
//             orbital map around the navigation's prediction (orbital_fix.hpp); when the
//             fix is confident, camera 1's horizontal position and the baseline length
//             (the depth scale) come from it, and the map lands in orbital coordinates.
//             A fix that fails keeps the navigation's answer (quality 0) unless
//             orbital.required
//   sweep     descent::PlaneSweep: depth of every pixel of image 1 (or a reason)
//   grid      terrain::HeightMap (grid_reducer: the mean by default) on a grid of
//             grid_cells^2 centred under camera 1: descent::addDepthToHeightMap
// Every stage leaves a StageRecord (Status, quality figure, time from hal::Clock) in
// stages() and one event in hal::EventLog. The first stage that fails ends the request
// with its Status (stages().failed() names the stage) and nothing is published:
// products() is nullptr until a request succeeds, and again from the start of the next
// one. A published product stays valid until the next map().
//
// No heap, no exceptions; deterministic for the same frames and poses (the sweep's bits
// are the same on every target). docs/app.md has the memory figures.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/camera.hpp"
#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "hal/odometry.hpp"
#include "vtm/app/camera_mount.hpp"
#include "vtm/app/orbital_fix.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/descent/plane_sweep.hpp"
#include "vtm/features/features.hpp"
#include "vtm/motion/motion_refiner.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::app {

constexpr std::int32_t kMaxGridCells = 4096;  // elevation grid side

// The refinement's defaults with the lander's matching window: 16 px around the
// odometry's prediction (its position and attitude error seen in image 2), and the same
// 16 px as the visibility margin; one feature per cell of the detector's 16 x 16 grid
// (docs/app.md "Cost": the same depths as two at 0.56x the refine stage's instructions).
[[nodiscard]] refine::Config descentRefineConfig() noexcept;

// The sweep's defaults with a plane step of at most 2 image-2 pixels over the largest
// parallax (descent::Config::max_plane_step_px): the 64 planes are the capacity, a pair
// whose parallax is smaller sweeps fewer (docs/app.md "Cost").
[[nodiscard]] descent::Config descentSweepConfig() noexcept;

struct DescentMapperConfig {
    // The plane sweep. max_width x max_height must be the camera's frame size; depth_min_m,
    // depth_max_m and min_parallax_px are replaced per pair (see below).
    descent::Config sweep = descentSweepConfig();
    CameraMount mount{};  // the nadir camera on the lander
    // Depth range of each pair before refinement (the matching's prediction; the sweep's
    // range without refine_pose): camera 1's height h above the site datum times
    // (1 - relief_fraction) .. (1 + relief_fraction). 0.01..0.9. Wide by default: near the
    // ground the navigation's height may be off by more than 10 %.
    double relief_fraction = 0.3;
    // Focus-of-expansion mask: min_parallax_px = parallax_factor * (1/zmin - 1/zmax) * zmid.
    // A pixel whose image-2 position moves P px over the range knows its depth to about
    // (0.25 px / P) of the range width: 20 keeps pixels known to ~1.25 % of the range
    // (docs/app.md has the measured trade-off). 0..1000.
    double parallax_factor = 20.0;
    // Relative-pose refinement from the images (stage refine). Its capacity is set from
    // sweep.max_width/max_height (the camera's frame size, stated once there); the motion's
    // range limits are replaced per pair by the depth range (widened to the image corners).
    bool refine_pose = true;
    refine::Config refine = descentRefineConfig();
    // The refiner's rotation prior: 0.003 rad (0.17 deg) per axis, 0..pi (0 = none). A
    // lander knows its attitude from its IMU far better than its position, and without the
    // prior a narrow view of near-planar ground along the optical axis cannot tell a small
    // rotation from a change of translation direction (docs/app.md "Accuracy").
    double attitude_sigma_rad = 0.003;
    // After refinement the sweep's depth range is the inlier features' depth range
    // widened by this fraction of their median depth on each side (the odometry's height
    // above the datum may be off by far more than the relief near the ground). 0..0.9.
    double feature_depth_margin = 0.05;
    std::int32_t grid_cells = 512;  // elevation grid side, 16..kMaxGridCells
    // Grid cell, metres: > 0, or 0 for two image-1 pixels at camera 1's height (2 h / fx:
    // with one pixel per cell the pixels' footprints leave empty seams between cells).
    double grid_cell_m = 0.0;
    // How a cell's points become its elevation. The mean: a descent cell holds the points
    // of a few pixels of one surface, and their mean averages the depth noise.
    terrain::Reducer grid_reducer = terrain::Reducer::kMean;
    // The absolute fix from an orbital map (stage locate; needs refine_pose). Off by
    // default: enabling it plans the registration's memory; the map is given by
    // DescentMapper::setOrbitalMap.
    OrbitalFixConfig orbital{};

    // kOk, or kInvalidConfig naming the field (the sweep's own fields as
    // descent::Config::validate names them, prefixed by nothing).
    [[nodiscard]] Status validate() const noexcept;
};

// What a successful request publishes. Views point into the mapper's memory.
struct DescentProducts {
    ImageView<const float> depth_m;          // image 1's size, along camera 1's axis; NaN = NO_DATA
    ImageView<const std::uint8_t> reason;    // descent::Reason per pixel of image 1
    // The elevation map: grid_cells^2 cells centred under camera 1 (terrain::HeightMap's
    // convention: row 0 north, column 0 west; kNoData, a NaN, where no point fell).
    const terrain::HeightMap* height_map = nullptr;
    ImageView<const std::uint16_t> image1;   // the frames the map came from
    ImageView<const std::uint16_t> image2;
    descent::PairGeometry geometry{};        // camera model and the two camera poses used
    hal::FrameInfo frame1{};
    hal::FrameInfo frame2{};
    descent::SweepStats sweep{};
    // refine: what the images said about the odometry's relative pose (empty when
    // refine_pose is off): refine::PairRefiner's result (counts per step, matches, inliers,
    // ranges, the motion, the change from the odometry in degrees).
    refine::Result refine{};
    // locate: what the orbital map said (attempted = false without the stage or a map).
    OrbitalFix orbital{};
    double depth_min_m = 0.0;            // the depth range swept (geometry, or refine's)
    double depth_max_m = 0.0;
    std::int64_t cells_filled = 0;
    std::int64_t points_outside = 0;         // valid depths that fell outside the grid
};

class DescentMapper {
public:
    // Arena bytes for this configuration (frames, depth, reasons, grid, the sweep), 0 if
    // the configuration is invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const DescentMapperConfig& config) noexcept;

    // Validates the config, asks the camera for its description and carves the memory.
    // The drivers are borrowed and must outlive the mapper. kInvalidConfig (config field),
    // kSizeMismatch ("camera: frame size differs from sweep.max_width/max_height"),
    // descent::checkCamera's kUnsupported / kInvalidArgument (not an undistorted, valid
    // pinhole), kOutOfMemory (arena), or
    // the camera's describe() Status.
    [[nodiscard]] Status init(const DescentMapperConfig& config, Arena& arena, hal::Camera& camera,
                              hal::Odometry& odometry, const hal::Clock& clock, hal::EventLog& events) noexcept;

    // The orbital reference for the locate stage, once after init() and before the
    // requests: a view of the caller's image (static, unchanged while used) and its
    // georeference. kNotInitialized before init(); kInvalidArgument when orbital.enabled
    // is false or the map is bad (validateOrbitalMap names the field).
    [[nodiscard]] Status setOrbitalMap(const OrbitalMap& map) noexcept;

    // One request (see the file comment). kNotInitialized before a successful init();
    // otherwise the failing stage's Status, e.g. kNoData from capture2 for a dropped frame,
    // kCorruptData from pose1 for a NaN pose, kDegenerate from geometry when image 2 is not
    // closer, kNoData from sweep / grid when no pixel got a depth / no cell an elevation.
    [[nodiscard]] Status map() noexcept;

    [[nodiscard]] const DescentProducts* products() const noexcept { return published_ ? &products_ : nullptr; }
    [[nodiscard]] const StageLog& stages() const noexcept { return stages_; }
    // Arena bytes init() took.
    [[nodiscard]] std::size_t memoryBytes() const noexcept { return memory_bytes_; }

private:
    [[nodiscard]] Status capture(Stage stage, const ImageView<std::uint16_t>& image, hal::FrameInfo& info) noexcept;
    [[nodiscard]] Status poseOf(Stage stage, const hal::FrameInfo& info, hal::PoseEstimate& pose) noexcept;
    [[nodiscard]] Status planGeometry() noexcept;
    [[nodiscard]] Status refinePose() noexcept;
    [[nodiscard]] Status depthRangeFromFeatures() noexcept;
    [[nodiscard]] Status setSweepRange(double zmin, double zmax) noexcept;
    [[nodiscard]] Status locateInOrbitalMap() noexcept;
    [[nodiscard]] Status applyOrbitalFix() noexcept;
    [[nodiscard]] Status runSweep() noexcept;
    [[nodiscard]] Status runGrid() noexcept;
    // Records a stage that began at t0_ns and returns its status.
    Status finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

    DescentMapperConfig config_{};
    hal::Camera* camera_ = nullptr;
    hal::Odometry* odometry_ = nullptr;
    const hal::Clock* clock_ = nullptr;
    hal::EventLog* events_ = nullptr;
    CameraModel model_{};
    descent::PlaneSweep sweep_{};
    refine::PairRefiner refiner_{};
    OrbitalLocator locator_{};
    ImageView<std::uint8_t> grey1_{};  // 8-bit copies for the feature modules
    ImageView<std::uint8_t> grey2_{};
    ImageView<std::uint16_t> image1_{};
    ImageView<std::uint16_t> image2_{};
    ImageView<float> depth_{};
    ImageView<std::uint8_t> reason_{};
    terrain::HeightMap map_{};
    hal::PoseEstimate pose1_{};
    hal::PoseEstimate pose2_{};
    DescentProducts products_{};
    StageLog stages_{};
    std::size_t memory_bytes_ = 0U;
    bool initialized_ = false;
    bool published_ = false;
};

}  // namespace vtm::app
