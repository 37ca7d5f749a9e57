// Evaluation harness of the wide-baseline front end (issue 5 item 5, docs/wide-baseline-evaluation.md).
// Ground/test code (host only, links OpenCV): heap, std::vector and printing are fine here.
//
// What it provides:
//  - a simulated world per seed (sim/scenarios/rover_wide_baseline.scn with overrides) and
//    rendered mast-camera pairs (frame 0 = A, frame 1 = B) with per-pixel truth;
//  - the true relative pose and an odometry pose with controlled, seeded errors;
//  - true correspondences (A pixel with a truth 3-D point, visible and not occluded in B);
//  - the VTM front end (refine::PairRefiner, the flight module: visibility -> Förstner ->
//    guided NCC matching -> MotionRefiner), the VTM
//    rectification (Rectifier) and the OpenCV peers (findEssentialMat + recoverPose,
//    stereoRectify + undistortPoints) on the same inputs;
//  - the full chain (refine, rectify, remap, ML stereo, triangulate) against true range.
//
// Relative pose convention (shared with fsw/features, fsw/motion, fsw/rectify):
//   X_b = R_b_from_a * X_a + t_b_from_a_m, X_a / X_b in the camera reference frames of A / B.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "vtm/features/template_matcher.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"

namespace vtm::eval {

struct RelativePose {
    Mat3 R_b_from_a = Mat3::Identity();
    Vec3 t_b_from_a_m = Vec3::Zero();
};

// X_b = R_b_from_a X_a + t from T_site_from_a and T_site_from_b.
[[nodiscard]] RelativePose relativePose(const RigidPose& a, const RigidPose& b);

// Angle between two rotations and between two translation directions, degrees (ground
// side: std::acos; the flight helpers live in vtm/motion).
[[nodiscard]] double rotationErrorDeg(const Mat3& estimate, const Mat3& truth);
[[nodiscard]] double directionErrorDeg(const Vec3& estimate, const Vec3& truth);

// ---- world and pairs --------------------------------------------------------------

// Terrain of a world. The defaults are the scenario's own (samples_log2 10, levels 12,
// 1 cm finest cell), which the sweep uses.
struct WorldSpec {
    std::uint64_t seed = 20240601U;
    int samples_log2 = 10;  // the scenario's own terrain (rover_wide_baseline.scn)
    int levels = 12;
    double finest_cell_m = 0.01;
    // Terrain rising in front of the rover, so that the overlap of a 5-20 m pair holds
    // slopes (the matches lie 30-90 m away) instead of level ground seen at 1.4-5 deg: the
    // scenario's far hills (300-3,000 m from the terrain centre, 150 m high) brought in to
    // kHillside* (docs/wide-baseline-evaluation.md, "Hillside world").
    bool hillside = false;
};
// The hillside world's hills: they begin 15 m from the terrain centre, reach full height
// at 100 m, are 40 m high at full height and 200 m long (sim/include/sim/terrain.hpp).
inline constexpr double kHillsideStart_m = 15.0;
inline constexpr double kHillsideFull_m = 100.0;
inline constexpr double kHillsideAmplitude_m = 40.0;
inline constexpr double kHillsideWavelength_m = 200.0;

// One terrain per seed, reused for every baseline / convergence / size of that seed.
struct World {
    std::string base_text;  // the scenario file with the seed / terrain overrides
    sim::Scenario scenario{};
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain{};
    double build_seconds = 0.0;
};

// Reads `scn_path`, applies the WorldSpec and builds the terrain. false + error on failure.
[[nodiscard]] bool buildWorld(const std::string& scn_path, const WorldSpec& spec, World& world,
                              std::string& error);

struct PairSpec {
    double baseline_m = 5.0;
    double convergence_deg = 10.0;
    int size_px = 512;      // square images, pinhole with the scenario's 45 deg hfov
    bool shadows = true;    // the scenario's cast shadows
    // Aim both cameras at the ground where their axes converge (as wide-baseline pairs are
    // planned: the same terrain at the centre of both images, paper §2): the mast tilt is
    // set so that the optical axis meets level ground at the convergence distance
    // D = (b / 2) / tan(conv / 2) (4 b for parallel axes), D clamped to 5..80 m.
    // false: the scenario's fixed tilt (-18 deg).
    bool aim_at_convergence = true;
};
// The mast tilt (degrees, negative = down) aim_at_convergence gives for a pair.
double aimedTiltDeg(const PairSpec& spec);

// A rendered pair with truth. Pixel arrays are row-major, width * height (x3 for points).
struct RenderedPair {
    PairSpec spec{};
    CameraModel model{};  // A and B (same mast camera)
    RigidPose pose_a{}, pose_b{};
    RelativePose truth{};
    int width = 0, height = 0;
    std::vector<std::uint8_t> image_a, image_b;
    std::vector<float> range_a_m, range_b_m;
    std::vector<float> point_a_site_m;  // 3 floats per pixel
    double render_seconds = 0.0;
};

[[nodiscard]] bool renderPair(const World& world, const PairSpec& spec, RenderedPair& pair, std::string& error);

// ---- odometry ---------------------------------------------------------------------

// Errors applied to B's true pose (site frame, z down): the projection centre moves by
// translation_fraction * |c_b - c_a| in a random direction; B's attitude turns by a
// heading error about the site vertical and by a tilt about a random horizontal axis.
// Each magnitude is max * u, u uniform in [min_scale, 1], with a random sign.
struct OdometryErrorSpec {
    double translation_fraction = 0.05;
    double heading_deg = 2.0;
    double tilt_deg = 0.3;
    double min_scale = 0.5;
};
struct OdometryCase {
    RelativePose pose{};
    double translation_error_fraction = 0.0;  // |dc| / |c_b - c_a| actually applied
    double heading_error_deg = 0.0;           // signed
    double tilt_error_deg = 0.0;
};
[[nodiscard]] OdometryCase perturbedOdometry(const RenderedPair& pair, const OdometryErrorSpec& spec,
                                             std::uint64_t seed);

// ---- truth correspondences ----------------------------------------------------------

struct Correspondence {
    Vec2 pixel_a = Vec2::Zero();
    Vec2 pixel_b = Vec2::Zero();  // exact projection of A's truth point into B
    double range_a_m = 0.0;
};
// A grid (step_px) of A pixels with a truth point, projecting into B's image (1 px
// inside), whose distance from B agrees with B's truth range there within
// occlusion_tolerance (relative): not hidden from B.
[[nodiscard]] std::vector<Correspondence> trueCorrespondences(const RenderedPair& pair, int step_px,
                                                              double occlusion_tolerance = 0.01);

// ---- VTM front end --------------------------------------------------------------------

struct FrontEndResult {
    bool ok = false;
    std::string error;
    std::int32_t features = 0;
    std::vector<Vec2> feature_pixels;  // A's Förstner features
    std::int32_t matches = 0;
    std::int32_t inliers = 0;
    features::MatchStats match_stats{};
    // Against the truth (A's pixel's true point visible in B): median |matched B pixel -
    // true B pixel| and the number of matches within 2 px of the truth.
    double match_error_median_px = 0.0;
    std::int32_t correct_matches = 0;
    std::vector<Vec2> pixels_a, pixels_b;  // the matches (input to VTM refine and OpenCV)
    // Per match: 1 if it is one of correct_matches, and then its true B pixel (else NaN).
    std::vector<std::uint8_t> correct;
    std::vector<Vec2> truth_b;
    RelativePose refined{};
    double refine_rms_px = 0.0;
    double refine_epipolar_sigma_px = 0.0;  // MotionResult::epipolar_sigma_px
    double seconds = 0.0;  // PairRefiner::refine: detect + match + refine
};
struct FrontEndSpec {
    double range_min_m = 1.5;
    double range_max_m = 1000.0;
    double margin_px = 0.0;  // 0: derived from the odometry error bound and the image size
    float min_score = 0.8f;          // MatcherConfig::min_score
    std::int32_t template_window = 11;  // MatcherConfig::template_window
    std::int32_t pyramid_levels = 2;    // MatcherConfig::pyramid_levels
    // > 0: the ground scene (refine::Scene::kGround): features only where B sees A by the
    // odometry and a ground plane this far below the camera, templates warped for that
    // plane (site up in A). 0: the general scene (features everywhere, fronto-parallel).
    double camera_height_m = 1.9;
};
// The spec as the flight module's configuration (default refine::Config at the image's
// size, the spec's matcher fields and margin) and request (odometry prior, no rotation
// prior, the spec's range interval for the matching and the refiner).
[[nodiscard]] refine::Config frontEndConfig(const RenderedPair& pair, const FrontEndSpec& spec);
[[nodiscard]] refine::Request frontEndRequest(const RenderedPair& pair, const RelativePose& odometry,
                                              const FrontEndSpec& spec);
// refine::PairRefiner on the pair, each match scored against the truth.
[[nodiscard]] FrontEndResult runVtmFrontEnd(const RenderedPair& pair, const RelativePose& odometry,
                                            const FrontEndSpec& spec);

// MotionRefiner (default motion::Config) from the odometry pose on given matches.
struct RefineResult {
    bool ok = false;
    std::string error;
    RelativePose pose{};
    std::int32_t inliers = 0;
    double rms_px = 0.0;
    double epipolar_sigma_px = 0.0;  // MotionResult::epipolar_sigma_px
};
[[nodiscard]] RefineResult refinePose(const RenderedPair& pair, const RelativePose& odometry,
                                      const std::vector<Vec2>& pixels_a, const std::vector<Vec2>& pixels_b);

// "Oracle" matches that isolate refinement and rectification from the matcher: `count`
// true correspondences drawn at random (seeded), B pixel plus N(0, sigma_px^2) per axis.
void noisyTrueMatches(const std::vector<Correspondence>& corr, std::size_t count, double sigma_px,
                      std::uint64_t seed, std::vector<Vec2>& pixels_a, std::vector<Vec2>& pixels_b);

// Normalised correlation of the square window (side `window`) around A's pixel with the
// window around B's pixel (bilinear at B's subpixel position); NaN near the border.
[[nodiscard]] double nccAt(const RenderedPair& pair, const Vec2& pixel_a, const Vec2& pixel_b, int window);

// What any matcher that scores 11 x 11 NCC windows can reach, with the pose KNOWN: for
// each A pixel (rounded) whose true point B sees, the B pixels that A's ray crosses
// between range_min_m and range_max_m under the TRUE pose (rounded, and one row above and
// below), and the one with the highest NCC (nccAt). `visible` counts the pixels with a
// true match, `correct` those whose best position lies within 2 px of it (the
// "correct matches" criterion). Fewer than motion::Config::min_inliers correct means the
// images, not the search region, limit the front end.
struct TrueLineCeiling {
    int visible = 0;
    int correct = 0;
};
[[nodiscard]] TrueLineCeiling bestNccOnTrueLine(const RenderedPair& pair, const std::vector<Vec2>& pixels_a,
                                                double range_min_m, double range_max_m);

// True B pixel of an A pixel (bilinear truth point of A, projected into B), false where
// the truth is missing (sky, depth edge) and, if require_visible, where the point is
// outside B's image or hidden from B (B's truth range disagrees by more than 1 %).
[[nodiscard]] bool truthMatch(const RenderedPair& pair, const Vec2& pixel_a, Vec2& pixel_b, bool require_visible);

// ---- OpenCV peers ---------------------------------------------------------------------

struct PeerPoseResult {
    bool ok = false;
    RelativePose pose{};  // t is a unit vector (scale unknown)
    int inliers = 0;
};
// cv::findEssentialMat (RANSAC, prob 0.999, threshold 1 px, camera matrix K) +
// cv::recoverPose on the same matches.
[[nodiscard]] PeerPoseResult opencvRelativePose(const CameraModel& pinhole, const std::vector<Vec2>& pixels_a,
                                                const std::vector<Vec2>& pixels_b);

// Vertical disparity of rectified true correspondences: RMS of y_a - y_b.
struct VerticalDisparity {
    bool ok = false;
    std::string error;
    double rms_px = 0.0;
    double max_abs_px = 0.0;
    int count = 0;
};
// With VTM's Rectifier built from `pose`.
[[nodiscard]] VerticalDisparity vtmVerticalDisparity(const RenderedPair& pair, const RelativePose& pose,
                                                     const std::vector<Correspondence>& corr);
// With cv::stereoRectify (same K, zero distortion, CALIB_ZERO_DISPARITY, alpha -1) and
// cv::undistortPoints(R1/P1, R2/P2).
[[nodiscard]] VerticalDisparity opencvVerticalDisparity(const RenderedPair& pair, const RelativePose& pose,
                                                        const std::vector<Correspondence>& corr);

// ---- full chain -----------------------------------------------------------------------

struct ChainResult {
    bool ok = false;
    std::string error;
    int d_min = 0, d_max = 0;
    double evaluated_fraction = 0.0;   // rectified A pixels whose true point is visible in B
    double valid_fraction = 0.0;       // of those: ML stereo gave a disparity
    double median_disparity_error_px = 0.0;  // |d - true d| over valid pixels with a true d
    double within1px_fraction = 0.0;         // of those: |d - true d| <= 1 px
    double median_rel_error = 0.0;     // |range - true| / true over valid pixels
    double within5_fraction = 0.0;     // of valid pixels: relative error <= 5 %
    double median_rel_error_true_scale = 0.0;  // same with the true baseline length
    double within5_fraction_true_scale = 0.0;
    double baseline_scale_error = 0.0;  // |t_odometry| / |t_true| - 1
    double seconds_rectify = 0.0, seconds_stereo = 0.0;
};
[[nodiscard]] ChainResult runFullChain(const RenderedPair& pair, const RelativePose& refined,
                                       double range_min_m, double range_max_m);

}  // namespace vtm::eval
