#include "wide_baseline_command.hpp"
#include "command_support.hpp"
#include "option_pair.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include "vtm/ground/exit_codes.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/features/features.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/sim_output.hpp"
#include "vtm/motion/motion_refiner.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/refine/pair_refiner.hpp"

namespace vtm::tools {
namespace {

using ground::GreyImage;
using ground::SimCameraPose;

constexpr double kRadToDeg = 57.29577951308232;

// Everything both commands read: the pair, the models and the poses.
struct PairInputs {
    GreyImage image1;
    GreyImage image2;
    CameraModel model1{};
    CameraModel model2{};
    SimCameraPose pose1;
    SimCameraPose pose2;
    double range_min_m = 0.0;
    double range_max_m = 0.0;
    Mat3 R_2_from_1 = Mat3::Identity();  // X_2 = R X_1 + t (camera reference frames)
    Vec3 t_2_from_1_m = Vec3::Zero();
};


// --range MIN:MAX in metres, 0 < MIN < MAX; "" or the error.
std::string parseRange(const std::string& text, double& lo, double& hi) {
    return cli::parseOptionPair("--range", text, cli::PairRule::kPositiveIncreasing, "in metres", "1:1000", lo, hi);
}

std::string checkImageMatchesModel(const std::string& path, const GreyImage& img, const CameraModel& m,
                                   const std::string& camera_path) {
    if (img.width == m.width_px && img.height == m.height_px) return "";
    return path + " is " + sizeText(img) + " but its camera model " + camera_path + " is " +
           std::to_string(m.width_px) + "x" + std::to_string(m.height_px);
}

// Loads and checks every input; "" or the one-line error naming the input.
std::string loadPair(const WideBaselineOptions& o, PairInputs& in) {
    std::string e = parseRange(o.range, in.range_min_m, in.range_max_m);
    if (!e.empty()) return e;
    auto a = ground::loadGrey8(o.image1);
    if (!a.ok) return a.error;
    auto b = ground::loadGrey8(o.image2);
    if (!b.ok) return b.error;
    in.image1 = std::move(a.value);
    in.image2 = std::move(b.value);
    ground::Outcome m = ground::readCameraModelFile(o.camera, in.model1);
    if (!m.ok) return m.error;
    const std::string camera2 = o.camera2.empty() ? o.camera : o.camera2;
    m = ground::readCameraModelFile(camera2, in.model2);
    if (!m.ok) return m.error;
    e = checkImageMatchesModel(o.image1, in.image1, in.model1, o.camera);
    if (e.empty()) e = checkImageMatchesModel(o.image2, in.image2, in.model2, camera2);
    if (!e.empty()) return e;
    auto p1 = ground::readCameraPoseSpec(o.pose1);
    if (!p1.ok) return "--pose1 " + p1.error;
    auto p2 = ground::readCameraPoseSpec(o.pose2);
    if (!p2.ok) return "--pose2 " + p2.error;
    in.pose1 = p1.value;
    in.pose2 = p2.value;
    const RigidPose site_from_1 = ground::siteFromCam(in.pose1);
    const RigidPose site_from_2 = ground::siteFromCam(in.pose2);
    in.R_2_from_1 = site_from_2.R.transpose() * site_from_1.R;
    in.t_2_from_1_m = site_from_2.R.transpose() * (site_from_1.t_m - site_from_2.t_m);
    if (!(in.t_2_from_1_m.norm() > 1e-6)) {
        return "--pose1 and --pose2 put both cameras at the same place: no baseline";
    }
    return "";
}

std::string statusText(const char* what, const Status& s) {
    return std::string(what) + ": " + s.reason() + " (" + std::to_string(s.detail()) + ")";
}

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- vtm refine ----------------------------------------------------------------------

struct RefineRun {
    std::vector<std::byte> pool;  // the refiner's arena (the result's spans point into it)
    std::unique_ptr<Arena> arena;
    std::unique_ptr<refine::PairRefiner> refiner = std::make_unique<refine::PairRefiner>();
    refine::Result result;
    double seconds = 0.0;
};

// refine::PairRefiner, the flight module the executives run: the ground scene when
// --mast-height is given (> 0: visibility mask and templates warped for the ground plane
// under camera 1), the general scene otherwise (features anywhere, fronto-parallel
// templates). Default refine::Config at the images' size; the motion's range limits are
// the --range interval.
std::string refinePair(const WideBaselineOptions& o, const PairInputs& in, RefineRun& run) {
    refine::Config c;
    c.max_width = std::max(in.image1.width, in.image2.width);
    c.max_height = std::max(in.image1.height, in.image2.height);
    c.match_margin_px = o.margin_px;
    c.max_rotation_sigma_deg = o.max_rotation_sigma_deg >= 0.0 ? o.max_rotation_sigma_deg
                               : o.mast_height_m > 0.0     ? 0.0
                                                           : refine::kGeneralSceneMaxRotationSigmaDeg;
    run.pool.assign(refine::PairRefiner::workspaceBytes(c), std::byte{0});
    run.arena = std::make_unique<Arena>(run.pool.data(), run.pool.size());
    Status s = run.refiner->init(c, *run.arena);
    if (!s.isOk()) return statusText("PairRefiner::init", s);
    refine::Request rq;
    rq.prior.model_a = in.model1;
    rq.prior.model_b = in.model2;
    rq.prior.b_from_a.R = in.R_2_from_1;
    rq.prior.b_from_a.t_m = in.t_2_from_1_m;
    rq.image_a = in.image1.view();
    rq.image_b = in.image2.view();
    rq.range_min_m = in.range_min_m;
    rq.range_max_m = in.range_max_m;
    if (o.mast_height_m > 0.0) {
        // The site's up (-z) seen from camera 1 (its attitude is known far better than its
        // position): the ground plane of the visibility mask and of the template warp.
        rq.scene = refine::Scene::kGround;
        rq.up_a = ground::siteFromCam(in.pose1).R.transpose() * Vec3(0.0, 0.0, -1.0);
        rq.camera_height_m = o.mast_height_m;
    } else {
        rq.scene = refine::Scene::kGeneral;
    }
    const auto t0 = std::chrono::steady_clock::now();
    s = run.refiner->refine(rq, run.result);
    run.seconds = seconds(t0);
    return s.isOk() ? "" : statusText("PairRefiner::refine", s);
}

// The refined pose of camera 2: camera 1 stays where it was, the baseline keeps its length.
SimCameraPose refinedPose2(const PairInputs& in, const motion::MotionResult& r) {
    const RigidPose site_from_1 = ground::siteFromCam(in.pose1);
    RigidPose site_from_2;
    site_from_2.R = site_from_1.R * r.R_b_from_a.transpose();
    site_from_2.t_m = site_from_1.t_m - site_from_2.R * r.t_b_from_a_m;
    SimCameraPose p = in.pose2;
    ground::setSiteFromCam(p, site_from_2);
    return p;
}

std::string writeMatches(const std::string& path, const RefineRun& run) {
    if (path.empty()) return "";
    std::ofstream f(path);
    f << "# vtm refine matches: x1 y1 x2 y2 ncc inlier (pixels, (0,0) = centre of the top-left pixel)\n";
    char line[160];
    const refine::Result& r = run.result;
    for (std::size_t i = 0; i < r.matches.size(); ++i) {
        const features::Match& m = r.matches[i];
        std::snprintf(line, sizeof line, "%.3f %.3f %.3f %.3f %.4f %d\n", m.pixel_a.x(), m.pixel_a.y(),
                      m.pixel_b.x(), m.pixel_b.y(), static_cast<double>(m.score), static_cast<int>(r.inliers[i]));
        f << line;
    }
    return f.good() ? "" : path + ": cannot write";
}

// "min / 10th / median / 90th / max" of the inliers' refined ranges, metres: where the
// refined motion was measured. Rows of nearer or farther points are extrapolated
// (docs/wide-baseline-cli.md).
std::string inlierRanges(const RefineRun& run) {
    std::vector<double> r;
    for (std::size_t i = 0; i < run.result.ranges_m.size(); ++i) {
        if (run.result.inliers[i] != 0U && std::isfinite(run.result.ranges_m[i])) r.push_back(run.result.ranges_m[i]);
    }
    if (r.empty()) return "none";
    std::sort(r.begin(), r.end());
    const auto at = [&r](double q) { return r[static_cast<std::size_t>(q * static_cast<double>(r.size() - 1U) + 0.5)]; };
    char t[160];
    std::snprintf(t, sizeof t, "%.2f / %.2f / %.2f / %.2f / %.2f m", r.front(), at(0.1), at(0.5), at(0.9), r.back());
    return t;
}

std::string refineReport(const WideBaselineOptions& o, const PairInputs& in, const RefineRun& run) {
    const refine::Result& res = run.result;
    const motion::MotionResult& r = res.motion;
    const features::MatchStats& ms = res.matching;
    char t[2048];
    std::snprintf(t, sizeof t,
                  "# vtm refine\n\n"
                  "| item | value |\n|---|---|\n"
                  "| images | %s, %s (%dx%d) |\n"
                  "| scene | %s |\n"
                  "| features in image 1 | %d (candidates %d) |\n"
                  "| matches (mutual, NCC >= %.2f) | %d of %d tried (no region %d, low score %d, not refined %d, not mutual %d) |\n"
                  "| inliers | %d of %d |\n"
                  "| inliers' range along camera 1's rays (min / 10th pct / median / 90th pct / max) | %s |\n"
                  "| reprojection RMS, odometry motion | %.3f px |\n"
                  "| reprojection RMS, refined (inliers) | %.3f px |\n"
                  "| rotation change from odometry | %.3f deg (1-sigma %.4f deg) |\n"
                  "| translation direction change | %.3f deg (1-sigma %.4f deg) |\n"
                  "| predicted vertical disparity after rectification (epipolar 1-sigma) | %.3f px |\n"
                  "| baseline (kept from odometry) | %.4f m |\n"
                  "| LM iterations / passes | %d / %d |\n"
                  "| time: detect + match + refine | %.3f s |\n",
                  o.image1.c_str(), o.image2.c_str(), in.image1.width, in.image1.height,
                  o.mast_height_m > 0.0 ? "ground (--mast-height: visibility mask, templates warped for the ground)"
                                        : "general (features anywhere, fronto-parallel templates)",
                  static_cast<int>(res.features.size()), res.detection.candidates,
                  static_cast<double>(run.refiner->config().matcher.min_score), ms.matched, ms.attempted,
                  ms.no_region, ms.low_score, ms.not_refined, ms.not_mutual, r.inliers, r.matches,
                  inlierRanges(run).c_str(), r.initial_rms_px, r.rms_px, res.rotation_change_deg,
                  r.rotation_sigma_rad * kRadToDeg, res.direction_change_deg, r.direction_sigma_rad * kRadToDeg,
                  r.epipolar_sigma_px, r.t_b_from_a_m.norm(), r.iterations, r.passes, run.seconds);
    return t;
}

}  // namespace

CLI::App* addRefineCommand(CLI::App& app, WideBaselineOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "refine", "refine the relative motion of a wide-baseline pair from odometry poses (features + LM)");
    cmd->add_option("IMAGE1", o.image1, "first image (8-bit PNG, PGM, JPEG or BMP)")->required();
    cmd->add_option("IMAGE2", o.image2, "second image")->required();
    cmd->add_option("--camera", o.camera, "camera model file of image 1 (and 2) (docs/camera-models.md)")->required();
    cmd->add_option("--camera2", o.camera2, "camera model file of image 2, if another camera");
    cmd->add_option("--pose1", o.pose1, "odometry pose of camera 1: FILE or FILE:INDEX (docs/cli-poses.md)")
        ->required();
    cmd->add_option("--pose2", o.pose2, "odometry pose of camera 2: FILE or FILE:INDEX")->required();
    cmd->add_option("--range", o.range, "range of the scene along camera 1's rays, MIN:MAX metres (default 1:1000)");
    cmd->add_option("--margin", o.margin_px, "odometry uncertainty around the predicted match, pixels (default 60)");
    cmd->add_option("--mast-height", o.mast_height_m,
                    "camera 1's height above level ground, m: ground scene, features only where camera 2 sees and "
                    "templates warped for the ground (default 1.9; 0: general scene, features everywhere, "
                    "fronto-parallel templates)");
    cmd->add_option("--max-rotation-sigma", o.max_rotation_sigma_deg,
                    "refuse a refinement whose rotation 1-sigma exceeds this, deg (default: 0.25 in the general "
                    "scene, off in the ground scene; 0: off)");
    cmd->add_option("--out", o.out, "refined poses (vtm-camera-poses 1: frame 0 = camera 1, frame 1 = camera 2)")
        ->required();
    cmd->add_option("--matches", o.matches, "write the matches (x1 y1 x2 y2 ncc inlier)");
    cmd->add_option("--report", o.report, "write the report (Markdown); it is also printed");
    return cmd;
}

int runRefine(const WideBaselineOptions& o) {
    if (!(o.margin_px > 0.0) || !std::isfinite(o.margin_px) || o.margin_px > 1000.0) {
        return failCommand("refine", kExitUsageError, "--margin " + std::to_string(o.margin_px) + ": must be in (0, 1000] px");
    }
    if (!(o.mast_height_m >= 0.0) || !std::isfinite(o.mast_height_m) || o.mast_height_m > 100.0) {
        return failCommand("refine", kExitUsageError,
                    "--mast-height " + std::to_string(o.mast_height_m) + ": must be in [0, 100] m");
    }
    if (!std::isfinite(o.max_rotation_sigma_deg) || o.max_rotation_sigma_deg > 10.0 ||
        (o.max_rotation_sigma_deg > 0.0 && o.max_rotation_sigma_deg < 0.01)) {
        return failCommand("refine", kExitUsageError,
                    "--max-rotation-sigma " + std::to_string(o.max_rotation_sigma_deg) + ": must be 0 (off) or 0.01..10 deg");
    }
    double lo = 0.0;
    double hi = 0.0;
    std::string error = parseRange(o.range, lo, hi);
    if (!error.empty()) return failCommand("refine", kExitUsageError, error);
    PairInputs in;
    error = loadPair(o, in);
    RefineRun run;
    if (error.empty()) error = refinePair(o, in, run);
    if (!error.empty()) return failCommand("refine", kExitInputError, error);
    SimCameraPose p1 = in.pose1;
    SimCameraPose p2 = refinedPose2(in, run.result.motion);
    p1.frame_index = 0U;
    p2.frame_index = 1U;
    std::ofstream f(o.out);
    f << ground::formatCameraPoses({p1, p2});
    if (!f.good()) return failCommand("refine", kExitInputError, o.out + ": cannot write");
    error = writeMatches(o.matches, run);
    const std::string report = refineReport(o, in, run);
    if (error.empty() && !o.report.empty()) {
        std::ofstream r(o.report);
        r << report;
        if (!r.good()) error = o.report + ": cannot write";
    }
    if (!error.empty()) return failCommand("refine", kExitInputError, error);
    std::fputs(report.c_str(), stdout);
    std::printf("\nrefined poses: %s (rectify with --pose1 %s:0 --pose2 %s:1)\n", o.out.c_str(), o.out.c_str(),
                o.out.c_str());
    return kExitOk;
}

// ---- vtm rectify ---------------------------------------------------------------------

namespace {

struct RectifyRun {
    rectify::RectifiedPair pair;
    GreyImage rect1;
    GreyImage rect2;
    double compute_s = 0.0;
    double remap_s = 0.0;
    double kept1 = 0.0;  // fraction of rectified pixels that come from inside the input
    double kept2 = 0.0;
};

double keptFraction(const rectify::Rectifier& r, rectify::Rectifier::Side side, const GreyImage& out,
                    const CameraModel& input) {
    std::size_t inside = 0;
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            Vec2 p;
            if (r.unrectifyPixel(side, Vec2(x, y), p).isOk() && p.x() >= -0.5 && p.y() >= -0.5 &&
                p.x() <= input.width_px - 0.5 && p.y() <= input.height_px - 0.5) {
                ++inside;
            }
        }
    }
    return static_cast<double>(inside) / static_cast<double>(out.pixels.size());
}

std::string runRectifier(const PairInputs& in, RectifyRun& run) {
    rectify::Config c;
    c.max_width = std::max(in.image1.width, in.image2.width);
    c.max_height = std::max(in.image1.height, in.image2.height);
    c.range_min_m = in.range_min_m;
    c.range_max_m = in.range_max_m;
    std::vector<std::byte> pool(rectify::Rectifier::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    static rectify::Rectifier rectifier;
    Status s = rectifier.init(c, arena);
    if (!s.isOk()) return statusText("Rectifier::init", s);
    rectify::RectifyInput ri;
    ri.pair.model_a = in.model1;
    ri.pair.model_b = in.model2;
    ri.pair.b_from_a.R = in.R_2_from_1;
    ri.pair.b_from_a.t_m = in.t_2_from_1_m;
    auto t0 = std::chrono::steady_clock::now();
    s = rectifier.compute(ri, run.pair);
    run.compute_s = seconds(t0);
    if (!s.isOk()) return statusText("Rectifier::compute", s);
    run.rect1 = GreyImage(run.pair.model_a.width_px, run.pair.model_a.height_px);
    run.rect2 = GreyImage(run.pair.model_b.width_px, run.pair.model_b.height_px);
    t0 = std::chrono::steady_clock::now();
    s = rectifier.remap(rectify::Rectifier::Side::kA, in.image1.view(), run.rect1.view());
    if (s.isOk()) s = rectifier.remap(rectify::Rectifier::Side::kB, in.image2.view(), run.rect2.view());
    run.remap_s = seconds(t0);
    if (!s.isOk()) return statusText("Rectifier::remap", s);
    run.kept1 = keptFraction(rectifier, rectify::Rectifier::Side::kA, run.rect1, in.model1);
    run.kept2 = keptFraction(rectifier, rectify::Rectifier::Side::kB, run.rect2, in.model2);
    return "";
}

// Site poses of the two rectified cameras (their optical frames).
void rectifiedPoses(const PairInputs& in, const RectifyRun& run, SimCameraPose& p1, SimCameraPose& p2) {
    const RigidPose site_from_1 = ground::siteFromCam(in.pose1);
    RigidPose site_from_rect1;
    site_from_rect1.R = site_from_1.R * run.pair.R_rect_from_a.transpose();
    // Camera 1's projection centre in its reference frame, as the rectifier published it:
    // the rectified frame's origin is there (models with C != 0 keep it).
    site_from_rect1.t_m = site_from_1.t_m + site_from_1.R * run.pair.centre_a_ref_m;
    RigidPose site_from_rect2;
    site_from_rect2.R = site_from_rect1.R;
    site_from_rect2.t_m = site_from_rect1.t_m + site_from_rect1.R * run.pair.centre_b_rect_m;
    p1 = in.pose1;
    p2 = in.pose2;
    ground::setSiteFromCam(p1, site_from_rect1);
    ground::setSiteFromCam(p2, site_from_rect2);
    p1.frame_index = 0U;
    p2.frame_index = 1U;
}

std::string rectifyReport(const WideBaselineOptions& o, const PairInputs& in, const RectifyRun& run) {
    const rectify::RectifiedPair& p = run.pair;
    char t[2048];
    std::snprintf(t, sizeof t,
                  "# vtm rectify\n\n"
                  "| item | value |\n|---|---|\n"
                  "| images | %s, %s |\n"
                  "| rectified size | %dx%d |\n"
                  "| baseline | %.4f m |\n"
                  "| convergence of the input cameras | %.3f deg |\n"
                  "| rectified focal length | %.3f px |\n"
                  "| principal points (x1, x2, y) | %.3f, %.3f, %.3f px |\n"
                  "| disparity range for ranges %g..%g m | %d:%d px (d = x1 - x2) |\n"
                  "| rectified pixels with input content | %.1f %% (image 1), %.1f %% (image 2) |\n"
                  "| time: tables, remap of both | %.3f s, %.3f s |\n"
                  "\nnext: vtm stereo %s/rectified1.png %s/rectified2.png --disparity %d:%d\n",
                  o.image1.c_str(), o.image2.c_str(), p.model_a.width_px, p.model_a.height_px, p.baseline_m,
                  p.convergence_deg, p.model_a.fx_px, p.model_a.cx_px, p.model_b.cx_px, p.model_a.cy_px,
                  in.range_min_m, in.range_max_m, p.d_min, p.d_max, 100.0 * run.kept1, 100.0 * run.kept2,
                  run.compute_s, run.remap_s, o.out_dir.c_str(), o.out_dir.c_str(), p.d_min, p.d_max);
    return t;
}

std::string writeRectified(const WideBaselineOptions& o, const PairInputs& in, const RectifyRun& run,
                           const std::string& report) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) return o.out_dir + ": cannot create the folder: " + ec.message();
    const std::string d = o.out_dir + "/";
    ground::Outcome w = ground::writePng(d + "rectified1.png", run.rect1);
    if (w.ok) w = ground::writePng(d + "rectified2.png", run.rect2);
    if (w.ok) w = ground::writeCameraModelFile(d + "rectified1.cmod", run.pair.model_a);
    if (w.ok) w = ground::writeCameraModelFile(d + "rectified2.cmod", run.pair.model_b);
    if (!w.ok) return w.error;
    SimCameraPose p1;
    SimCameraPose p2;
    rectifiedPoses(in, run, p1, p2);
    std::ofstream poses(d + "rectified_poses.txt");
    poses << ground::formatCameraPoses({p1, p2});
    std::ofstream r(d + "report.md");
    r << report;
    return (poses.good() && r.good()) ? "" : o.out_dir + ": cannot write rectified_poses.txt or report.md";
}

}  // namespace

CLI::App* addRectifyCommand(CLI::App& app, WideBaselineOptions& o) {
    CLI::App* cmd = app.add_subcommand("rectify", "rectify a (wide-baseline, verged) pair given its poses (Fusiello)");
    cmd->add_option("IMAGE1", o.image1, "first image (8-bit PNG, PGM, JPEG or BMP): the rectified left")->required();
    cmd->add_option("IMAGE2", o.image2, "second image")->required();
    cmd->add_option("--camera", o.camera, "camera model file of image 1 (and 2) (docs/camera-models.md)")->required();
    cmd->add_option("--camera2", o.camera2, "camera model file of image 2, if another camera");
    cmd->add_option("--pose1", o.pose1, "pose of camera 1: FILE or FILE:INDEX (e.g. the output of vtm refine)")
        ->required();
    cmd->add_option("--pose2", o.pose2, "pose of camera 2: FILE or FILE:INDEX")->required();
    cmd->add_option("--range", o.range, "range of the scene, MIN:MAX metres, for the disparity range (default 1:1000)");
    cmd->add_option("--out-dir", o.out_dir,
                    "output folder: rectified1/2.png, rectified1/2.cmod, rectified_poses.txt, report.md")
        ->required();
    return cmd;
}

int runRectify(const WideBaselineOptions& o) {
    double lo = 0.0;
    double hi = 0.0;
    std::string error = parseRange(o.range, lo, hi);
    if (!error.empty()) return failCommand("rectify", kExitUsageError, error);
    PairInputs in;
    error = loadPair(o, in);
    RectifyRun run;
    if (error.empty()) error = runRectifier(in, run);
    const std::string report = error.empty() ? rectifyReport(o, in, run) : "";
    if (error.empty()) error = writeRectified(o, in, run, report);
    if (!error.empty()) return failCommand("rectify", kExitInputError, error);
    std::fputs(report.c_str(), stdout);
    return kExitOk;
}

}  // namespace vtm::tools
