// Issue 5 item 5: the wide-baseline front end (features -> guided matching ->
// MotionRefiner -> Fusiello rectification -> ML stereo) on the simulated world, against
// the simulator's truth and against OpenCV on the same inputs, in the same run.
// docs/wide-baseline-evaluation.md has the scenario, the measured tables (printed here in
// Markdown) and what is asserted:
//  - refined rectification: RMS vertical disparity of TRUE correspondences <= 0.25 px in
//    every case of the sweep, and at least 5x smaller than with the raw odometry pose;
//    (with the VTM matches and, separately, with oracle matches = true correspondences
//    plus 0.3 px noise, which isolates the refiner and the rectifier from the matcher);
//  - the rectifier with the TRUE pose puts true correspondences on one row (< 0.01 px);
//  - full chain on the headline case: median relative range error < 5 % against the
//    rendered true range, with the VTM front end's pose and with the oracle-refined pose;
//  - on request (VTM_EVAL_HILLSIDE=1), the 5-20 m cases on a world with terrain rising in
//    front of the rover: the true-pose and oracle assertions above, front end reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "wide_baseline_harness.hpp"

namespace vtm::eval {
namespace {

const std::string kScenario = std::string(VTM_SCENARIO_DIR) + "/rover_wide_baseline.scn";

// The sweep: seeds x baselines x convergences at kSweepSize_px x kSweepSize_px (docs: run time).
const std::uint64_t kSeeds[] = {101U, 202U, 303U};
const double kBaselines_m[] = {1.0, 2.0, 5.0, 10.0, 20.0};
const double kConvergences_deg[] = {0.0, 10.0, 20.0};
constexpr int kSweepSize_px = 1024;
// Largest baseline at which the whole front end (features + matching + refinement) is held
// to the targets, on every odometry draw; see the sweep test. At 2 m most draws
// meet them, not all (printExtraDraws; docs/wide-baseline-evaluation.md).
constexpr double kFrontEndTargetMaxBaseline_m = 1.0;
// Up to this baseline every case is also run with kExtraDraws more odometry error draws
// (same images): one draw per case says little about how often the front end meets the
// targets there. The CI form draws them only where they are asserted
// (kFrontEndTargetMaxBaseline_m); the long form (VTM_EVAL_FULL) up to 2 m, for the tables.
constexpr double kExtraDrawsMaxBaseline_m = 2.0;
// The long form of the sweep (VTM_EVAL_FULL set) rather than the CI form.
bool longForm() { return std::getenv("VTM_EVAL_FULL") != nullptr; }
double extraDrawsMaxBaseline_m() { return longForm() ? kExtraDrawsMaxBaseline_m : kFrontEndTargetMaxBaseline_m; }
constexpr int kExtraDraws = 3;
// Issue 5's targets: RMS vertical disparity after rectification, and its improvement over
// rectifying with the raw odometry.
constexpr double kTargetVd_px = 0.25;
constexpr double kTargetImprovement = 5.0;

// One estimate of the relative pose and what it gives.
struct PoseEval {
    bool ok = false;
    std::string error;
    double rot_deg = NAN, dir_deg = NAN;
    VerticalDisparity vd_vtm, vd_cv;  // VTM Rectifier / OpenCV stereoRectify on this pose
    // VTM refine only: the refiner's own prediction of vd (MotionResult::epipolar_sigma_px).
    double epipolar_sigma_px = NAN;
};

struct CaseResult {
    std::uint64_t seed = 0U;
    double baseline_m = 0.0, convergence_deg = 0.0;
    OdometryCase odo{};
    double rot_odo = 0.0, dir_odo = 0.0;
    VerticalDisparity vd_odo, vd_truth;  // VTM Rectifier on the odometry / true pose
    int features = 0, matches = 0, correct_matches = 0, inliers = 0;
    double match_err_px = NAN;
    int features_visible = 0;     // A's features whose true point B sees
    double ncc_at_truth = NAN;    // median NCC (11 x 11) of those at their TRUE B position
    PoseEval vtm, cv;                // front end: VTM refine / OpenCV E on the VTM matches
    PoseEval oracle_vtm, oracle_cv;  // oracle matches: VTM refine / OpenCV E
    // A's features (visible in B) whose best NCC on B's TRUE epipolar line is within 2 px
    // of the true match (bestNccOnTrueLine): what NCC matching could reach with the pose known.
    int ceiling_correct = 0;
    // More odometry draws (baselines up to kExtraDrawsMaxBaseline_m): VTM front end only.
    struct Draw {
        VerticalDisparity vd_odo;
        PoseEval vtm;
        int correct_matches = 0;
    };
    std::vector<Draw> extra;
    // Where the matches are in depth, and what that does to the pose (the hillside sweep
    // only; runCase's depth_diagnostics). Ranges are A's true range at the pixel, 10th and
    // 90th percentiles over the true correspondences and over the correct matches.
    struct DepthSpread {
        bool computed = false;
        double corr_p10_m = NAN, corr_p90_m = NAN;
        double match_p10_m = NAN, match_p90_m = NAN;
        // Oracle matches at the correct matches' own A pixels (true B pixel + the oracle's
        // noise; as many as there are correct matches), refined and rectified like the
        // oracle: what matches in those places give with the oracle's accuracy.
        PoseEval oracle_at_matches;
        // vd of the front end's pose over the true correspondences whose range lies between
        // the matches' 10th and 90th percentiles (count in vd_in_band.count).
        VerticalDisparity vd_in_band;
    } depth;
};

double medianOf(std::vector<double> v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
    if (v.empty()) {
        return NAN;
    }
    std::sort(v.begin(), v.end());
    return v[v.size() / 2U];
}

double worstOf(const std::vector<double>& v) {
    double w = -INFINITY;
    for (const double x : v) {
        w = std::isnan(x) ? INFINITY : std::max(w, x);  // a failure counts as the worst
    }
    return w;
}

std::uint64_t caseSeed(std::uint64_t seed, double baseline_m, double convergence_deg) {
    return seed * 1000003ULL + static_cast<std::uint64_t>(baseline_m * 100.0) * 1009ULL +
           static_cast<std::uint64_t>(convergence_deg * 10.0);
}

// The pose with the true baseline length (OpenCV gives a unit t; rows after rectification
// do not depend on the length).
RelativePose withTrueLength(const RenderedPair& pair, const RelativePose& pose) {
    RelativePose scaled = pose;
    scaled.t_b_from_a_m = pose.t_b_from_a_m.normalized() * pair.truth.t_b_from_a_m.norm();
    return scaled;
}

PoseEval evaluatePose(const RenderedPair& pair, const std::vector<Correspondence>& corr, const RelativePose& pose) {
    PoseEval e;
    e.ok = true;
    e.rot_deg = rotationErrorDeg(pose.R_b_from_a, pair.truth.R_b_from_a);
    e.dir_deg = directionErrorDeg(pose.t_b_from_a_m, pair.truth.t_b_from_a_m);
    const RelativePose scaled = withTrueLength(pair, pose);
    e.vd_vtm = vtmVerticalDisparity(pair, scaled, corr);
    e.vd_cv = opencvVerticalDisparity(pair, scaled, corr);
    return e;
}

// VTM refine on matches.
PoseEval evaluateRefine(const RenderedPair& pair, const std::vector<Correspondence>& corr, const RelativePose& odometry,
                        const std::vector<Vec2>& pa, const std::vector<Vec2>& pb, int* inliers) {
    PoseEval vtm;
    const RefineResult rr = refinePose(pair, odometry, pa, pb);
    if (rr.ok) {
        vtm = evaluatePose(pair, corr, rr.pose);
        vtm.epipolar_sigma_px = rr.epipolar_sigma_px;
        if (inliers != nullptr) {
            *inliers = rr.inliers;
        }
    } else {
        vtm.error = rr.error;
    }
    return vtm;
}

// VTM refine and OpenCV on the same matches.
void evaluateMatches(const RenderedPair& pair, const std::vector<Correspondence>& corr, const RelativePose& odometry,
                     const std::vector<Vec2>& pa, const std::vector<Vec2>& pb, PoseEval& vtm, PoseEval& cv,
                     int* inliers) {
    vtm = evaluateRefine(pair, corr, odometry, pa, pb, inliers);
    const PeerPoseResult p = opencvRelativePose(pair.model, pa, pb);
    if (p.ok) {
        cv = evaluatePose(pair, corr, p.pose);
    } else {
        cv.error = "findEssentialMat/recoverPose: no pose";
    }
}

constexpr std::size_t kOracleMatches = 300U;
constexpr double kOracleSigmaPx = 0.3;

double percentile(std::vector<double> v, double q) {
    if (v.empty()) {
        return NAN;
    }
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1U))];
}

// CaseResult::DepthSpread of a case whose front end gave `fe`.
void depthSpread(const RenderedPair& pair, const std::vector<Correspondence>& corr, const RelativePose& odometry,
                 const FrontEndResult& fe, std::uint64_t seed, CaseResult::DepthSpread& d) {
    d.computed = true;
    std::vector<double> corr_range;
    for (const Correspondence& c : corr) {
        corr_range.push_back(c.range_a_m);
    }
    d.corr_p10_m = percentile(corr_range, 0.1);
    d.corr_p90_m = percentile(corr_range, 0.9);
    std::vector<Correspondence> at_matches;  // the correct matches, at their true B pixels
    std::vector<double> match_range;
    for (std::size_t i = 0; i < fe.pixels_a.size(); ++i) {
        if (fe.correct[i] != 0U) {
            const long x = std::lround(fe.pixels_a[i].x());
            const long y = std::lround(fe.pixels_a[i].y());
            const double range = pair.range_a_m[static_cast<std::size_t>(y * pair.width + x)];
            at_matches.push_back(Correspondence{fe.pixels_a[i], fe.truth_b[i], range});
            match_range.push_back(range);
        }
    }
    d.match_p10_m = percentile(match_range, 0.1);
    d.match_p90_m = percentile(match_range, 0.9);
    std::vector<Vec2> pa, pb;
    noisyTrueMatches(at_matches, at_matches.size(), kOracleSigmaPx, seed, pa, pb);
    d.oracle_at_matches = evaluateRefine(pair, corr, odometry, pa, pb, nullptr);
    if (fe.ok && !match_range.empty()) {
        std::vector<Correspondence> band;
        for (const Correspondence& c : corr) {
            if (c.range_a_m >= d.match_p10_m && c.range_a_m <= d.match_p90_m) {
                band.push_back(c);
            }
        }
        d.vd_in_band = vtmVerticalDisparity(pair, withTrueLength(pair, fe.refined), band);
    }
}

CaseResult runCase(const World& world, std::uint64_t seed, double baseline_m, double convergence_deg,
                   bool depth_diagnostics) {
    CaseResult c;
    c.seed = seed;
    c.baseline_m = baseline_m;
    c.convergence_deg = convergence_deg;
    PairSpec spec;
    spec.baseline_m = baseline_m;
    spec.convergence_deg = convergence_deg;
    spec.size_px = kSweepSize_px;
    RenderedPair pair;
    std::string error;
    if (!renderPair(world, spec, pair, error)) {
        c.vtm.error = error;
        return c;
    }
    const std::uint64_t s = caseSeed(seed, baseline_m, convergence_deg);
    c.odo = perturbedOdometry(pair, OdometryErrorSpec{}, s);
    c.rot_odo = rotationErrorDeg(c.odo.pose.R_b_from_a, pair.truth.R_b_from_a);
    c.dir_odo = directionErrorDeg(c.odo.pose.t_b_from_a_m, pair.truth.t_b_from_a_m);
    const std::vector<Correspondence> corr = trueCorrespondences(pair, 4);
    c.vd_odo = vtmVerticalDisparity(pair, c.odo.pose, corr);
    c.vd_truth = vtmVerticalDisparity(pair, pair.truth, corr);

    const FrontEndSpec spec_default{};
    const FrontEndResult fe = runVtmFrontEnd(pair, c.odo.pose, spec_default);
    c.features = fe.features;
    c.matches = fe.matches;
    c.correct_matches = fe.correct_matches;
    c.match_err_px = fe.match_error_median_px;
    std::vector<double> ncc;
    for (const Vec2& f : fe.feature_pixels) {
        Vec2 tb;
        if (truthMatch(pair, f, tb, true)) {
            ++c.features_visible;
            const double v = nccAt(pair, f, tb, 11);
            if (!std::isnan(v)) {
                ncc.push_back(v);
            }
        }
    }
    c.ncc_at_truth = medianOf(ncc);
    c.ceiling_correct =
        bestNccOnTrueLine(pair, fe.feature_pixels, spec_default.range_min_m, spec_default.range_max_m).correct;
    if (baseline_m <= extraDrawsMaxBaseline_m()) {
        for (int k = 1; k <= kExtraDraws; ++k) {
            CaseResult::Draw d;
            const OdometryCase odo =
                perturbedOdometry(pair, OdometryErrorSpec{}, s + 7919ULL * static_cast<std::uint64_t>(k));
            d.vd_odo = vtmVerticalDisparity(pair, odo.pose, corr);
            const FrontEndResult fk = runVtmFrontEnd(pair, odo.pose, spec_default);
            d.correct_matches = fk.correct_matches;
            if (fk.ok) {
                d.vtm = evaluatePose(pair, corr, fk.refined);
                d.vtm.epipolar_sigma_px = fk.refine_epipolar_sigma_px;
            } else {
                d.vtm.error = fk.error;
            }
            c.extra.push_back(d);
        }
    }
    evaluateMatches(pair, corr, c.odo.pose, fe.pixels_a, fe.pixels_b, c.vtm, c.cv, &c.inliers);

    std::vector<Vec2> pa, pb;
    noisyTrueMatches(corr, kOracleMatches, kOracleSigmaPx, s + 1U, pa, pb);
    evaluateMatches(pair, corr, c.odo.pose, pa, pb, c.oracle_vtm, c.oracle_cv, nullptr);
    if (depth_diagnostics) {
        depthSpread(pair, corr, c.odo.pose, fe, s + 2U, c.depth);
    }
    return c;
}

const char* fmt(double v, char* buf, const char* f) {
    if (std::isnan(v)) {
        return "fail";
    }
    std::snprintf(buf, 32, f, v);
    return buf;
}

void printPoseCells(const PoseEval& e) {
    char b1[32], b2[32], b3[32], b4[32];
    std::printf(" %s | %s | %s | %s |", fmt(e.ok ? e.rot_deg : NAN, b1, "%.4f"), fmt(e.ok ? e.dir_deg : NAN, b2, "%.3f"),
                fmt(e.ok && e.vd_vtm.ok ? e.vd_vtm.rms_px : NAN, b3, "%.3f"),
                fmt(e.ok && e.vd_cv.ok ? e.vd_cv.rms_px : NAN, b4, "%.3f"));
}

void printCaseTables(const std::vector<CaseResult>& cases) {
    std::printf("\n#### Per case, %d x %d (angles deg; vd = RMS vertical disparity of true correspondences, px)\n\n",
                kSweepSize_px, kSweepSize_px);
    std::printf("| seed | B m | conv | odo t %% / hdg deg | rot odo | dir odo | vd odo | vd true pose | pts |"
                " features | visible in B | NCC at truth | correct on the true line | matches | correct | inliers |"
                " match err px | rot VTM | dir VTM | vd VTM | vd CV-rect (VTM pose) |"
                " rot CV | dir CV | vd VTM-rect (CV pose) | vd CV (CV pose) |"
                " oracle rot VTM | dir VTM | vd VTM | vd CV-rect | oracle rot CV | dir CV | vd VTM-rect | vd CV |\n");
    std::printf("|");
    for (int i = 0; i < 33; ++i) {
        std::printf("---|");
    }
    std::printf("\n");
    for (const CaseResult& c : cases) {
        char b[32];
        char b2[32];
        std::printf("| %llu | %.0f | %.0f | %.1f / %+.2f | %.3f | %.2f | %.2f | %.4f | %d | %d | %d | %s | %d | %d | %d |"
                    " %d | %s |",
                    static_cast<unsigned long long>(c.seed), c.baseline_m, c.convergence_deg,
                    100.0 * c.odo.translation_error_fraction, c.odo.heading_error_deg, c.rot_odo, c.dir_odo,
                    c.vd_odo.rms_px, c.vd_truth.rms_px, c.vd_truth.count, c.features, c.features_visible,
                    fmt(c.ncc_at_truth, b2, "%.2f"), c.ceiling_correct, c.matches, c.correct_matches, c.inliers,
                    fmt(c.match_err_px, b, "%.2f"));
        printPoseCells(c.vtm);
        printPoseCells(c.cv);
        printPoseCells(c.oracle_vtm);
        printPoseCells(c.oracle_cv);
        std::printf("\n");
    }
}

double rot(const PoseEval& e) { return e.ok ? e.rot_deg : NAN; }
double dir(const PoseEval& e) { return e.ok ? e.dir_deg : NAN; }
double vdv(const PoseEval& e) { return e.ok && e.vd_vtm.ok ? e.vd_vtm.rms_px : NAN; }
double vdc(const PoseEval& e) { return e.ok && e.vd_cv.ok ? e.vd_cv.rms_px : NAN; }

const char* winner(double vtm, double cv) {
    if (std::isnan(vtm) && std::isnan(cv)) {
        return "none";
    }
    if (std::isnan(cv) || vtm < cv) {
        return "VTM";
    }
    return (std::isnan(vtm) || cv < vtm) ? "OpenCV" : "tie";
}

// "Who wins where": medians over seeds per (baseline, convergence); a failed estimate
// counts as the worst (median over the failures is "fail" when most failed).
void printWhoWins(const std::vector<CaseResult>& cases, bool oracle) {
    std::map<std::pair<double, double>, std::vector<const CaseResult*>> groups;
    for (const CaseResult& c : cases) {
        groups[{c.baseline_m, c.convergence_deg}].push_back(&c);
    }
    std::printf("\n#### Who wins where, %s (median over %zu seeds; rotation / direction error deg; "
                "vertical disparity RMS px on the VTM-refined pose)\n\n",
                oracle ? "oracle matches (true, 0.3 px noise)" : "VTM matches", std::size(kSeeds));
    std::printf("| B m | conv | rot VTM | rot CV | dir VTM | dir CV | pose winner | vd VTM rect | vd CV stereoRectify |"
                " rect winner | vd odometry | features visible in B | NCC at truth | correct on the true line |"
                " correct matches |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& [key, list] : groups) {
        std::vector<double> rv, rc, dv, dc, vv, vc, vo, fv, nc, cl, cm;
        for (const CaseResult* c : list) {
            fv.push_back(c->features_visible);
            nc.push_back(c->ncc_at_truth);
            cl.push_back(c->ceiling_correct);
            cm.push_back(c->correct_matches);
            const PoseEval& v = oracle ? c->oracle_vtm : c->vtm;
            const PoseEval& o = oracle ? c->oracle_cv : c->cv;
            rv.push_back(rot(v));
            rc.push_back(rot(o));
            dv.push_back(dir(v));
            dc.push_back(dir(o));
            vv.push_back(vdv(v));
            vc.push_back(vdc(v));
            vo.push_back(c->vd_odo.rms_px);
        }
        // failures as +inf so that they count against the estimator in the median
        for (auto* vec : {&rv, &rc, &dv, &dc, &vv, &vc}) {
            for (double& x : *vec) {
                x = std::isnan(x) ? INFINITY : x;
            }
        }
        const double mrv = medianOf(rv), mrc = medianOf(rc), mdv = medianOf(dv), mdc = medianOf(dc);
        const double mvv = medianOf(vv), mvc = medianOf(vc);
        const char* rw = winner(mrv, mrc);
        const char* dw = winner(mdv, mdc);
        char pose_winner[32];
        std::snprintf(pose_winner, sizeof pose_winner, "%s", std::string(rw) == dw ? rw : "split");
        // Rectification: the two are the same maths on the same pose; call it a tie within 0.005 px.
        const char* rect = std::fabs(mvv - mvc) < 0.005 ? "tie" : winner(mvv, mvc);
        std::printf("| %.0f | %.0f | %.4f | %.4f | %.3f | %.3f | %s | %.3f | %.3f | %s | %.2f | %.0f | %.2f | %.0f | %.0f |\n",
                    key.first, key.second, mrv, mrc, mdv, mdc, pose_winner, mvv, mvc, rect, medianOf(vo), medianOf(fv),
                    medianOf(nc), medianOf(cl), medianOf(cm));
    }
}

void printSummary(const std::vector<CaseResult>& cases) {
    std::vector<double> rot_o, dir_o, vd_o;
    std::vector<double> r[4], d[4], vv[4], ratio[4];
    for (const CaseResult& c : cases) {
        rot_o.push_back(c.rot_odo);
        dir_o.push_back(c.dir_odo);
        vd_o.push_back(c.vd_odo.rms_px);
        const PoseEval* e[4] = {&c.vtm, &c.cv, &c.oracle_vtm, &c.oracle_cv};
        for (int k = 0; k < 4; ++k) {
            r[k].push_back(rot(*e[k]));
            d[k].push_back(dir(*e[k]));
            vv[k].push_back(vdv(*e[k]));
            ratio[k].push_back(c.vd_odo.rms_px / vdv(*e[k]));
        }
    }
    const auto least = [](const std::vector<double>& v) {
        double m = INFINITY;
        for (const double x : v) {
            m = std::isnan(x) ? -INFINITY : std::min(m, x);
        }
        return m;
    };
    const auto failures = [](const std::vector<double>& v) {
        return static_cast<int>(std::count_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }));
    };
    std::printf("\n#### Summary over %zu cases (median / worst; \"inf\" = at least one failure)\n\n", cases.size());
    std::printf("| quantity | odometry | VTM matches + VTM refine | VTM matches + OpenCV E | oracle + VTM refine |"
                " oracle + OpenCV E |\n|---|---|---|---|---|---|\n");
    std::printf("| rotation error deg | %.3f / %.3f |", medianOf(rot_o), worstOf(rot_o));
    for (int k = 0; k < 4; ++k) {
        std::printf(" %.4f / %.4f |", medianOf(r[k]), worstOf(r[k]));
    }
    std::printf("\n| translation direction error deg | %.2f / %.2f |", medianOf(dir_o), worstOf(dir_o));
    for (int k = 0; k < 4; ++k) {
        std::printf(" %.3f / %.3f |", medianOf(d[k]), worstOf(d[k]));
    }
    std::printf("\n| vd RMS px, VTM rectification of that pose | %.2f / %.2f |", medianOf(vd_o), worstOf(vd_o));
    for (int k = 0; k < 4; ++k) {
        std::printf(" %.3f / %.3f |", medianOf(vv[k]), worstOf(vv[k]));
    }
    std::printf("\n| vd odometry / vd of that pose (median / smallest) | - |");
    for (int k = 0; k < 4; ++k) {
        std::printf(" %.0f / %.1f |", medianOf(ratio[k]), least(ratio[k]));
    }
    std::printf("\n| failed estimates | - |");
    for (int k = 0; k < 4; ++k) {
        std::printf(" %d |", failures(r[k]));
    }
    std::printf("\n");
}

// The front end over all odometry draws (the sweep's own plus kExtraDraws) at baselines
// up to kExtraDrawsMaxBaseline_m: per draw vd with the odometry and with the refined pose,
// and per baseline how many draws meet both targets.
bool meetsTargets(const VerticalDisparity& odo, const PoseEval& e) {
    return e.ok && e.vd_vtm.ok && odo.ok && e.vd_vtm.rms_px <= kTargetVd_px &&
           odo.rms_px / e.vd_vtm.rms_px >= kTargetImprovement;
}

void printExtraDraws(const std::vector<CaseResult>& cases) {
    std::printf("\n#### VTM front end over %d odometry draws per case (baselines up to %.0f m; vd RMS px, odometry ->"
                " refined; * = misses a target; predicted = the refiner's epipolar_sigma_px)\n\n| seed | B m | conv |",
                kExtraDraws + 1, extraDrawsMaxBaseline_m());
    for (int k = 0; k <= kExtraDraws; ++k) {
        std::printf(" draw %d |", k);
    }
    std::printf("\n|---|---|---|");
    for (int k = 0; k <= kExtraDraws; ++k) {
        std::printf("---|");
    }
    std::printf("\n");
    std::map<double, std::pair<int, int>> per_baseline;  // met, total
    const auto cell = [&](double b, const VerticalDisparity& odo, const PoseEval& e, int correct) {
        const bool met = meetsTargets(odo, e);
        auto& [m, n] = per_baseline[b];
        m += met ? 1 : 0;
        ++n;
        char v[32], p[32];
        std::printf(" %.2f -> %s%s (%d correct; predicted %s) |", odo.rms_px, fmt(vdv(e), v, "%.3f"), met ? "" : " *",
                    correct, fmt(e.ok ? e.epipolar_sigma_px : NAN, p, "%.3f"));
    };
    for (const CaseResult& c : cases) {
        if (c.extra.empty()) {
            continue;
        }
        std::printf("| %llu | %.0f | %.0f |", static_cast<unsigned long long>(c.seed), c.baseline_m,
                    c.convergence_deg);
        cell(c.baseline_m, c.vd_odo, c.vtm, c.correct_matches);
        for (const CaseResult::Draw& d : c.extra) {
            cell(c.baseline_m, d.vd_odo, d.vtm, d.correct_matches);
        }
        std::printf("\n");
    }
    std::printf("\n");
    for (const auto& [b, mn] : per_baseline) {
        std::printf("- %.0f m: %d of %d draws meet both targets\n", b, mn.first, mn.second);
    }
}

// The refiner's prediction of vd (MotionResult::epipolar_sigma_px) against the measured vd,
// over every VTM refinement: front end (all draws) and oracle matches. Per group the ratio
// measured / predicted, and what a check "predicted <= limit" would keep and reject, by
// whether the pose meets the targets.
void printPredictedVd(const std::vector<CaseResult>& cases) {
    struct Sample {
        double predicted, measured;
        bool met;
    };
    std::map<std::string, std::vector<Sample>> groups;
    const auto add = [&](const std::string& g, const VerticalDisparity& odo, const PoseEval& e) {
        if (e.ok && e.vd_vtm.ok && !std::isnan(e.epipolar_sigma_px)) {
            groups[g].push_back({e.epipolar_sigma_px, e.vd_vtm.rms_px, meetsTargets(odo, e)});
        }
    };
    for (const CaseResult& c : cases) {
        char g[64];
        std::snprintf(g, sizeof g, "front end, %.0f m", c.baseline_m);
        add(g, c.vd_odo, c.vtm);
        for (const CaseResult::Draw& d : c.extra) {
            add(g, d.vd_odo, d.vtm);
        }
        add("oracle matches, 1-20 m", c.vd_odo, c.oracle_vtm);
    }
    const double limits[] = {0.05, 0.1, 0.25};
    std::printf("\n#### Predicted vd (the refiner's epipolar_sigma_px) against measured vd\n\n| poses | n |"
                " measured / predicted: median (min ... max) | meet targets |");
    for (const double l : limits) {
        std::printf(" predicted <= %.2f: kept met / rejected met / kept missed / rejected missed |", l);
    }
    std::printf("\n|---|---|---|---|---|---|---|\n");
    for (const auto& [name, v] : groups) {
        std::vector<double> ratio;
        int met = 0;
        for (const Sample& x : v) {
            ratio.push_back(x.measured / x.predicted);
            met += x.met ? 1 : 0;
        }
        const auto [lo, hi] = std::minmax_element(ratio.begin(), ratio.end());
        std::printf("| %s | %zu | %.2f (%.2f ... %.2f) | %d |", name.c_str(), v.size(), medianOf(ratio), *lo, *hi, met);
        for (const double l : limits) {
            int k_met = 0, r_met = 0, k_miss = 0, r_miss = 0;
            for (const Sample& x : v) {
                const bool kept = x.predicted <= l;
                (x.met ? (kept ? k_met : r_met) : (kept ? k_miss : r_miss)) += 1;
            }
            std::printf(" %d / %d / %d / %d |", k_met, r_met, k_miss, r_miss);
        }
        std::printf("\n");
    }
}

// The targets for one pose estimate of case c; vd_odo: vd with the odometry pose of the
// draw that estimate started from.
void expectTargets(const CaseResult& c, const VerticalDisparity& vd_odo, const PoseEval& e, const char* path) {
    SCOPED_TRACE(std::string(path) + ": seed " + std::to_string(c.seed) + " baseline " +
                 std::to_string(c.baseline_m) + " m convergence " + std::to_string(c.convergence_deg) + " deg");
    ASSERT_TRUE(e.ok) << e.error;
    ASSERT_TRUE(e.vd_vtm.ok && vd_odo.ok) << e.vd_vtm.error << vd_odo.error;
    ASSERT_GE(e.vd_vtm.count, 50);  // enough true correspondences to measure an RMS
    EXPECT_LE(e.vd_vtm.rms_px, kTargetVd_px);
    EXPECT_GE(vd_odo.rms_px / e.vd_vtm.rms_px, kTargetImprovement);
    // Rotation and direction errors are reported, not asserted: at 10-20 m baselines the
    // overlap holds only distant points and the translation direction is weakly observable
    // (docs/wide-baseline-evaluation.md), while the rows (what rectification needs) stay right.
}

// Where the correct matches lie in depth against the true correspondences on which vd is
// measured, and what the pose from matches in those places gives: per case, and per
// baseline how many cases meet both targets with the front end and with oracle matches at
// the correct matches' A pixels.
void printDepthSpread(const std::vector<CaseResult>& cases) {
    std::printf("\n#### Depth of the matches (A's true range, 10th-90th percentile, m; vd RMS px; * = misses a"
                " target)\n\n| seed | B m | conv | true corr. range | correct matches' range | correct | vd odo |"
                " vd VTM | vd VTM in the matches' range (pts) | oracle at the correct matches: vd |"
                " oracle (300 anywhere): vd |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::map<double, std::pair<int, int>> vtm_met, at_matches_met;
    for (const CaseResult& c : cases) {
        if (!c.depth.computed) {
            continue;
        }
        const CaseResult::DepthSpread& d = c.depth;
        char b1[32], b2[32], b3[32], b4[32], b5[32], b6[32];
        const bool met = meetsTargets(c.vd_odo, c.vtm);
        const bool met_at = meetsTargets(c.vd_odo, d.oracle_at_matches);
        vtm_met[c.baseline_m].first += met ? 1 : 0;
        ++vtm_met[c.baseline_m].second;
        at_matches_met[c.baseline_m].first += met_at ? 1 : 0;
        ++at_matches_met[c.baseline_m].second;
        std::printf("| %llu | %.0f | %.0f | %.0f-%.0f | %s-%s | %d | %.2f | %s%s | %s (%d) | %s%s | %s |\n",
                    static_cast<unsigned long long>(c.seed), c.baseline_m, c.convergence_deg, d.corr_p10_m,
                    d.corr_p90_m, fmt(d.match_p10_m, b1, "%.0f"), fmt(d.match_p90_m, b2, "%.0f"), c.correct_matches,
                    c.vd_odo.rms_px, fmt(vdv(c.vtm), b3, "%.3f"), met ? "" : " *",
                    fmt(d.vd_in_band.ok ? d.vd_in_band.rms_px : NAN, b4, "%.3f"), d.vd_in_band.count,
                    fmt(vdv(d.oracle_at_matches), b5, "%.3f"), met_at ? "" : " *",
                    fmt(vdv(c.oracle_vtm), b6, "%.3f"));
    }
    std::printf("\n");
    for (const auto& [b, mn] : vtm_met) {
        std::printf("- %.0f m: the front end meets both targets in %d of %d cases; oracle matches at its correct"
                    " matches' A pixels in %d of %d\n",
                    b, mn.first, mn.second, at_matches_met[b].first, at_matches_met[b].second);
    }
}

// What every case of a sweep must meet, whatever its front end does: the rectifier with
// the true pose puts true correspondences on one row, and refinement + rectification of
// oracle matches meet the targets.
void expectTruePoseAndOracle(const CaseResult& c) {
    EXPECT_LT(c.vd_truth.rms_px, 0.01);
    expectTargets(c, c.vd_odo, c.oracle_vtm, "oracle matches");
}

// Runs the cases on one thread per core (test code; each case reads its seed's World and
// writes only its own result): the worlds are built first, one thread per seed, then the
// threads take cases from a shared counter. The cases come back in the serial order with
// the same bits whatever the thread count (each case's odometry draw comes from its own
// seed, OpenCV's RANSAC generator is per thread and reset before each call).
std::vector<CaseResult> runSweep(bool hillside, const std::vector<double>& baselines_m) {
    constexpr std::size_t kSeedCount = std::size(kSeeds);
    const std::size_t per_seed = baselines_m.size() * std::size(kConvergences_deg);
    const std::size_t threads = std::max(1U, std::thread::hardware_concurrency());
    World worlds[kSeedCount];
    std::string errors[kSeedCount];
    bool built[kSeedCount] = {};
    {
        std::vector<std::thread> pool;
        for (std::size_t i = 0U; i < kSeedCount; ++i) {
            pool.emplace_back([&, i]() {
                WorldSpec ws;
                ws.seed = kSeeds[i];
                ws.hillside = hillside;
                built[i] = buildWorld(kScenario, ws, worlds[i], errors[i]);
            });
        }
        for (std::thread& t : pool) {
            t.join();
        }
    }
    std::vector<CaseResult> slots(kSeedCount * per_seed);
    std::atomic<std::size_t> next{0U};
    const auto worker = [&]() {
        for (std::size_t k = next++; k < slots.size(); k = next++) {
            const std::size_t i = k / per_seed;
            if (!built[i]) {
                continue;
            }
            const double b = baselines_m[(k % per_seed) / std::size(kConvergences_deg)];
            const double conv = kConvergences_deg[k % std::size(kConvergences_deg)];
            slots[k] = runCase(worlds[i], kSeeds[i], b, conv, hillside);
        }
    };
    {
        std::vector<std::thread> pool;
        for (std::size_t t = 1U; t < threads; ++t) {
            pool.emplace_back(worker);
        }
        worker();
        for (std::thread& t : pool) {
            t.join();
        }
    }
    std::vector<CaseResult> cases;
    for (std::size_t i = 0U; i < kSeedCount; ++i) {
        if (!built[i]) {
            ADD_FAILURE() << "seed " << kSeeds[i] << ": " << errors[i];
            continue;
        }
        std::printf("seed %llu: terrain built in %.2f s\n", static_cast<unsigned long long>(kSeeds[i]),
                    worlds[i].build_seconds);
        cases.insert(cases.end(), slots.begin() + static_cast<std::ptrdiff_t>(i * per_seed),
                     slots.begin() + static_cast<std::ptrdiff_t>((i + 1U) * per_seed));
    }
    std::printf("sweep: %zu cases on %zu threads\n", slots.size(), threads);
    return cases;
}

// The targets per case, with the whole front end (Förstner -> guided NCC ->
// MotionRefiner), and, to tell the matcher's share from the refiner's and the
// rectifier's, with oracle matches (true correspondences + 0.3 px noise).
//
// The CI form sweeps the baselines up to 5 m (27 cases, about 80 s on two cores); the long
// form, VTM_EVAL_FULL=1, adds 10 and 20 m (45 cases, 131 s), which the tables of
// docs/wide-baseline-evaluation.md come from: there only the true pose and the oracle
// matches are asserted, as everywhere.
TEST(WideBaselineEval, SweepPoseAndVerticalDisparityAgainstTruthAndOpenCV) {
    std::vector<double> baselines_m;
    const bool full = longForm();
    for (const double b : kBaselines_m) {
        if (full || b <= 5.0) {
            baselines_m.push_back(b);
        }
    }
    std::printf("sweep: %s form, baselines up to %.0f m\n", full ? "long (VTM_EVAL_FULL)" : "CI", baselines_m.back());
    const std::vector<CaseResult> cases = runSweep(false, baselines_m);
    ASSERT_EQ(cases.size(), std::size(kSeeds) * baselines_m.size() * std::size(kConvergences_deg));
    printCaseTables(cases);
    printWhoWins(cases, false);
    printWhoWins(cases, true);
    printSummary(cases);
    printExtraDraws(cases);
    printPredictedVd(cases);
    for (const CaseResult& c : cases) {
        expectTruePoseAndOracle(c);
        // The whole front end meets the targets on every odometry draw at baselines up to
        // kFrontEndTargetMaxBaseline_m. At 2 m most draws meet them (printExtraDraws); at
        // 5-20 m Förstner + NCC find too few correct matches (the "correct matches" column;
        // at 10-20 m even "correct on the true line", NCC with the pose known, is below the
        // refiner's 12): a known miss, printed above and stated in
        // docs/wide-baseline-evaluation.md, not hidden. Asserted where met, so that a
        // regression there fails.
        if (c.baseline_m <= kFrontEndTargetMaxBaseline_m) {
            expectTargets(c, c.vd_odo, c.vtm, "VTM front end");
            for (const CaseResult::Draw& d : c.extra) {
                expectTargets(c, d.vd_odo, d.vtm, "VTM front end, another odometry draw");
            }
        }
    }
}

// The same front end on a world whose terrain rises in front of the rover (WorldSpec::
// hillside), at the baselines where the sweep's world leaves too little terrain in the
// overlap (5-20 m): measured and printed (docs/wide-baseline-evaluation.md, "Hillside
// world"). Run on request, not in the test suite (about a minute on two cores):
//   VTM_EVAL_HILLSIDE=1 vtm_wide_baseline_eval_tests --gtest_filter='*Hillside*'
// Asserted, as in the sweep: the rectifier with the true pose, and refinement +
// rectification of oracle matches. The front end's figures are reported, not asserted.
TEST(WideBaselineEval, HillsideWorldAtFiveToTwentyMetres) {
    if (std::getenv("VTM_EVAL_HILLSIDE") == nullptr) {
        GTEST_SKIP() << "measurement on request: VTM_EVAL_HILLSIDE=1";
    }
    const std::vector<double> baselines_m = {5.0, 10.0, 20.0};
    const std::vector<CaseResult> cases = runSweep(true, baselines_m);
    ASSERT_EQ(cases.size(), std::size(kSeeds) * baselines_m.size() * std::size(kConvergences_deg));
    std::printf("\n### Hillside world (hills from %.0f m, full height %.0f m at %.0f m, %.0f m long)\n", kHillsideStart_m,
                kHillsideAmplitude_m, kHillsideFull_m, kHillsideWavelength_m);
    printCaseTables(cases);
    printSummary(cases);
    printDepthSpread(cases);
    for (const CaseResult& c : cases) {
        expectTruePoseAndOracle(c);
    }
}

void printChainColumn(const char* label, const ChainResult& r, std::vector<std::string>& rows) {
    char b[160];
    const auto add = [&](std::size_t i, const char* f, double v) {
        std::snprintf(b, sizeof b, f, v);
        rows[i] += std::string(" ") + (r.ok ? b : "fail") + " |";
    };
    rows[0] += std::string(" ") + label + " |";
    rows[1] += " --- |";
    add(2, "%+.2f %%", 100.0 * r.baseline_scale_error);
    rows[3] += " " + std::to_string(r.d_min) + "..." + std::to_string(r.d_max) + " |";
    add(4, "%.1f %%", 100.0 * r.evaluated_fraction);
    add(5, "%.1f %%", 100.0 * r.valid_fraction);
    add(6, "%.2f", r.median_disparity_error_px);
    add(7, "%.1f %%", 100.0 * r.within1px_fraction);
    add(8, "%.2f %%", 100.0 * r.median_rel_error);
    add(9, "%.1f %%", 100.0 * r.within5_fraction);
    add(10, "%.2f %%", 100.0 * r.median_rel_error_true_scale);
    add(11, "%.1f %%", 100.0 * r.within5_fraction_true_scale);
    std::snprintf(b, sizeof b, " %.2f / %.2f |", r.seconds_rectify, r.seconds_stereo);
    rows[12] += b;
}

// Full chain (refine, rectify + remap, ML stereo, triangulate with the odometry baseline
// length) on the scenario's own geometry (5 m, 10 deg), against the rendered true range
// of every rectified A pixel whose true point B sees. Three poses: the VTM front end's,
// the VTM refiner's on oracle matches, and the true pose (the stereo stage alone).
TEST(WideBaselineEval, FullChainRangeAgainstTruthOnTheHeadlineCase) {
    World world;
    std::string error;
    WorldSpec ws;
    ws.seed = 20240601U;
    ASSERT_TRUE(buildWorld(kScenario, ws, world, error)) << error;
    PairSpec spec;  // the scenario's own geometry: 5 m, 10 deg
    spec.size_px = 1024;
    RenderedPair pair;
    ASSERT_TRUE(renderPair(world, spec, pair, error)) << error;
    const OdometryCase odo = perturbedOdometry(pair, OdometryErrorSpec{}, 7U);
    const FrontEndResult fe = runVtmFrontEnd(pair, odo.pose, FrontEndSpec{});
    const std::vector<Correspondence> corr = trueCorrespondences(pair, 8);
    std::vector<Vec2> pa, pb;
    noisyTrueMatches(corr, kOracleMatches, kOracleSigmaPx, 8U, pa, pb);
    const RefineResult oracle = refinePose(pair, odo.pose, pa, pb);
    ASSERT_TRUE(oracle.ok) << oracle.error;
    constexpr double kRangeMin_m = 3.0, kRangeMax_m = 200.0;
    const ChainResult r_fe = fe.ok ? runFullChain(pair, fe.refined, kRangeMin_m, kRangeMax_m) : ChainResult{};
    const ChainResult r_or = runFullChain(pair, oracle.pose, kRangeMin_m, kRangeMax_m);
    RelativePose truth_scaled = pair.truth;  // true direction, odometry length (as the refiner keeps)
    truth_scaled.t_b_from_a_m = pair.truth.t_b_from_a_m.normalized() * odo.pose.t_b_from_a_m.norm();
    const ChainResult r_tr = runFullChain(pair, truth_scaled, kRangeMin_m, kRangeMax_m);

    std::printf("\n#### Full chain, headline case (seed %llu, %d x %d, B %.0f m, convergence %.0f deg; odometry "
                "error %.2f %% of distance, heading %+.2f deg; VTM front end %d matches, %d inliers%s%s)\n\n",
                static_cast<unsigned long long>(ws.seed), pair.width, pair.height, spec.baseline_m,
                spec.convergence_deg, 100.0 * odo.translation_error_fraction, odo.heading_error_deg, fe.matches,
                fe.inliers, fe.ok ? "" : ": ", fe.error.c_str());
    std::vector<std::string> rows = {"| pose used |", "|---|", "| baseline length error (odometry, kept) |",
                                     "| disparity search d_min...d_max px (ML stereo capped at 1024 values) |",
                                     "| rectified A pixels whose true point B sees |",
                                     "| valid disparity (of those) |", "| median disparity error px |",
                                     "| disparity within 1 px |",
                                     "| median relative range error (odometry baseline length) |",
                                     "| within 5 % (odometry baseline length) |",
                                     "| median relative range error (true baseline length) |",
                                     "| within 5 % (true baseline length) |",
                                     "| time: rectify (tables + remap) / ML stereo s |"};
    printChainColumn("VTM front end", r_fe, rows);
    printChainColumn("oracle matches + VTM refine", r_or, rows);
    printChainColumn("true pose", r_tr, rows);
    for (const std::string& row : rows) {
        std::printf("%s\n", row.c_str());
    }
    // Bound: measured 2.9 % (true pose) with the stereo defaults; 5 % leaves margin and
    // still fails on a broken chain (a wrong pose gave 45 %, a wrong sign > 100 %).
    for (const ChainResult* r : {&r_or, &r_fe}) {
        SCOPED_TRACE(r == &r_fe ? "VTM front end pose" : "oracle-match refined pose");
        ASSERT_TRUE(r->ok) << (r == &r_fe ? fe.error : r->error);
        EXPECT_GE(r->valid_fraction, 0.5);
        EXPECT_LT(r->median_rel_error_true_scale, 0.05);
        EXPECT_LT(r->median_rel_error, 0.05 + std::fabs(r->baseline_scale_error));
    }
}

}  // namespace
}  // namespace vtm::eval

