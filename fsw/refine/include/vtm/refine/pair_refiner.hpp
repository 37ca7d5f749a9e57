// PairRefiner: the relative pose of a camera pair refined from its two images, as one step
// (docs/refine.md). What the rover's and the lander's executives, `vtm refine` and the
// wide-baseline evaluation all run, in this order:
//   1. visibility  (ground scene only) the part of image A that B sees according to the
//                  prior pose and a level ground plane camera_height_m under A
//                  (features::predictVisibility, Config::visibility_margin_px inside B)
//   2. detect      Förstner features of image A (inside that part)
//   3. match       guided template matching into image B inside the region that the prior
//                  pose and the range interval predict, widened by Config::match_margin_px;
//                  templates warped for the ground plane (ground scene) or fronto-parallel
//                  (general scene)
//   4. motion      motion::MotionRefiner from the prior pose on the matches (LM over the
//                  rotation and the translation direction; the baseline length stays the
//                  prior's), its range limits the request's interval and its rotation prior
//                  the request's rotation sigma
// Conventions: vtm/core/pose.hpp (CameraPair, b_from_a: X_b = R X_a + t_m).
//
// Memory: every buffer (visibility mask, feature and match sets, the motion refiner, the
// per-match arrays, the detector's and the matcher's workspaces) comes from the Arena at
// init(); workspaceBytes(config) plans it. refine() never allocates. The PairRefiner object
// itself is small (pointers and the configuration).
// Deterministic: the modules it calls are, and it adds only copies and the two angles.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/forstner.hpp"
#include "vtm/features/template_matcher.hpp"
#include "vtm/motion/motion_refiner.hpp"

namespace vtm::refine {

struct Config {
    // Capacity: the largest image A and B, pixels, 1..4096, stated here once: the
    // detector's and the matcher's capacities are set from it (their max_width/max_height
    // fields are not read; detectorConfig(), matcherConfig()).
    std::int32_t max_width = 1024;
    std::int32_t max_height = 1024;
    features::DetectorConfig detector{};
    features::MatcherConfig matcher{};
    // The refiner's settings. range_min_m / range_max_m and rotation_prior_sigma_rad are
    // replaced per request (Request::range_*_m, Request::rotation_sigma_rad).
    motion::Config motion{};
    // The prior pose's uncertainty seen in image B: the matching window around the
    // segment that the prior pose and the range interval predict, pixels, 0..1000 (e.g. a
    // heading error of 2.3 deg at fx 1236 px with half again as margin: 75 px).
    double match_margin_px = 75.0;
    // Ground scene: a pixel of A is a feature candidate only when its predicted point lies
    // at least this far inside B's image, pixels, 0..1000.
    double visibility_margin_px = 16.0;
    // The certainty gate: a refinement whose own rotation 1-sigma (MotionResult::
    // rotation_sigma_rad) exceeds this is refused, degrees, 0 (off) or 0.01..10. Off by
    // default: the rover executive gates on the ratio to the odometry's sigma instead
    // (its far-terrain pairs legitimately reach 0.26 deg). For a general scene without a
    // prior covariance, kGeneralSceneMaxRotationSigmaDeg (docs/refine.md "Certainty gate").
    double max_rotation_sigma_deg = 0.0;
    // The detector's and the matcher's configurations with the capacity above.
    [[nodiscard]] features::DetectorConfig detectorConfig() const noexcept;
    [[nodiscard]] features::MatcherConfig matcherConfig() const noexcept;
    // kOk, or kInvalidConfig naming the field (sub-configurations as their validate()
    // names them).
    [[nodiscard]] Status validate() const noexcept;
};

// The gate `vtm refine` and the real-pair evaluations use for a general scene: a refined
// rotation 1 deg wrong would be a 4-sigma error. On the Strecha pairs the refinements that
// converged wrong (8-11 deg) report 0.50-1.41 deg, the right ones 0.011-0.055 deg.
constexpr double kGeneralSceneMaxRotationSigmaDeg = 0.25;

enum class Scene : std::uint8_t {
    // The cameras look at the ground they stand over (rover, descent): the visibility
    // mask restricts features to the part of A that B sees, and templates are warped for
    // the ground plane (site up_a, camera_height_m).
    kGround = 0,
    // No ground known: features anywhere in A, fronto-parallel templates (the plane
    // perpendicular to A's ray).
    kGeneral = 1,
};

struct Request {
    // The prior: both models and b_from_a (odometry, IMU). Its translation's length is
    // kept (pixels cannot observe it). The models must be the images' sizes.
    CameraPair prior{};
    // The prior's covariance, as far as it is used: the 1-sigma of its rotation per axis,
    // radians, [0, pi]; 0 = no rotation prior (the images alone decide). The position
    // and heading errors enter through Config::match_margin_px (pixels of image B).
    double rotation_sigma_rad = 0.0;
    ImageView<const std::uint8_t> image_a{};  // 8-bit, pair.model_a's size
    ImageView<const std::uint8_t> image_b{};  // 8-bit, pair.model_b's size
    // The scene's range along A's rays, metres, 0 < min < max, finite: the matching's
    // search segment and the refiner's clamp of each match's range.
    double range_min_m = 1.0;
    double range_max_m = 1000.0;
    Scene scene = Scene::kGround;
    // Ground scene only: the site's up direction in A's reference frame (unit within
    // 0.5..2, normalised) and A's projection centre above the ground plane, metres, > 0.
    Vec3 up_a = Vec3::Zero();
    double camera_height_m = 0.0;
};

struct Result {
    CameraPair refined{};          // the prior's models, the refined b_from_a
    motion::MotionResult motion{};  // covariance, RMS, inliers, iterations (motion_refiner.hpp)
    // Per match (matched pixels, 1 = inlier / 0 = outlier, refined range along A's ray in
    // metres, NaN for an outlier): views into the refiner's memory, valid until the next
    // refine().
    Span<const Vec2> pixels_a{};
    Span<const Vec2> pixels_b{};
    Span<const std::uint8_t> inliers{};
    Span<const double> ranges_m{};
    Span<const features::Feature> features{};  // A's features (detect)
    Span<const features::Match> matches{};     // the matches with their NCC (match), same order
    // Counts per step. visible_px: pixels of A that B sees (ground scene), or all of A's
    // pixels (general scene).
    std::int64_t visible_px = 0;
    features::DetectorStats detection{};
    features::MatchStats matching{};
    // The change from the prior: angle between the rotations and between the translation
    // directions, degrees.
    double rotation_change_deg = 0.0;
    double direction_change_deg = 0.0;
};

class PairRefiner {
public:
    // Arena bytes init() takes for this configuration, 0 if it is invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const Config& config) noexcept;

    // Validates the configuration (kInvalidConfig) and carves every buffer (kOutOfMemory:
    // the arena is smaller than workspaceBytes(config)).
    [[nodiscard]] Status init(const Config& config, Arena& arena) noexcept;

    // One pair (see the file comment). Every count of `result` that a step reached is
    // filled even when a later step fails (matching for a refinement that found too few
    // inliers). Errors:
    //  kNotInitialized   init() has not succeeded
    //  kInvalidArgument  "Request.prior.b_from_a: ..." (checkRigidPose, rotation within
    //                    1e-6, finite translation), zero baseline, rotation_sigma_rad,
    //                    range_min_m / range_max_m, empty image_a / image_b, a ground
    //                    scene's up_a or camera_height_m, an unknown scene
    //  kSizeMismatch     an image above the capacity, or not its model's size
    //  kDegenerate       the prior pose says B sees none of A (ground scene); fewer than
    //                    motion.min_inliers matches or inliers (the refiner's reason); the
    //                    refined rotation's 1-sigma above max_rotation_sigma_deg ("refine:
    //                    the refined rotation is too uncertain ...", detail: its 1-sigma in
    //                    millidegrees; result.motion and the matches are filled)
    //  or the detector's / matcher's / refiner's Status.
    [[nodiscard]] Status refine(const Request& request, Result& result) noexcept;

    [[nodiscard]] const Config& config() const noexcept { return config_; }

private:
    [[nodiscard]] Status checkRequest(const Request& request) const noexcept;
    [[nodiscard]] Status maskVisible(const Request& request, const features::MatchPrediction& prediction,
                                     Result& result, ImageView<const std::uint8_t>& mask) const noexcept;
    [[nodiscard]] Status refineMotion(const Request& request, Result& result) noexcept;

    Config config_{};
    features::ForstnerDetector detector_{};
    features::TemplateMatcher matcher_{};
    motion::MotionRefiner* refiner_ = nullptr;  // in the arena (about 200 KiB)
    features::FeatureSet* features_ = nullptr;
    features::MatchSet* matches_ = nullptr;
    ImageView<std::uint8_t> visible_{};  // max_width x max_height capacity
    Span<Vec2> pixels_a_{};
    Span<Vec2> pixels_b_{};
    Span<std::uint8_t> inliers_{};
    Span<double> ranges_{};
    bool initialized_ = false;
};

}  // namespace vtm::refine
