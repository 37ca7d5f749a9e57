// Real wide-baseline pairs with true cameras (issue 21 item 5): the Strecha views
// (../shared/data/strecha, README there: herz-jesus-p8 and entry-p10, 1024 x 683, K, R, C
// per view; neighbours 1-5 m and 10-50 deg apart). For neighbouring and second-neighbour
// views the flight refiner (general scene: no ground, no mast height) starts from the true
// relative pose spoiled by 2 deg of rotation and 5 % of the baseline sideways; OpenCV SIFT +
// findEssentialMat + recoverPose solve the same pairs from nothing, in the same run. Then
// the refined neighbour pairs are rectified and matched by the ML stereo, and SIFT matches,
// found independently, must lie on one row. VTM_STRECHA_FULL=1 adds the second neighbours
// of both sets (CI: the neighbours of both, 16 pairs); VTM_STRECHA_OUT=DIR writes each
// mapped pair's rectified images and disparity picture (docs/wide-baseline-evaluation.md).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "real_pair_support.hpp"
#include "test_data.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/motion/motion_refiner.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/rectify/rectifier.hpp"

#include <Eigen/SVD>  // after vtm/core/eigen.hpp (real_pair_support.hpp): the test's own SVD

namespace vtm {
namespace {

using test::DenseMap;
using test::denseMap;
using test::greyView;
using test::inlierPixels;
using test::matchDisparities;
using test::rowStats;
using test::RowStats;
using test::siftMatches;
using test::Workspace;
using test::writeDisparityPng;

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const std::string kRoot = vtm::test::testDataSet("strecha");

struct View {
    cv::Mat image;
    CameraModel model{};
    RigidPose site_from_cam{};  // X_world = R X_cam + C (the README's R and C)
};

// NNNN.camera: K (3 lines), distortion, R camera-to-world (3 lines), C, width height.
bool loadView(const std::string& set, int index, View& v) {
    char name[16];
    std::snprintf(name, sizeof name, "%04d", index);
    const std::string base = kRoot + set + "/" + name;
    v.image = cv::imread(base + ".png", cv::IMREAD_GRAYSCALE);
    std::ifstream f(base + ".camera");
    double k[9], dist[3], r[9], c[3];
    int w = 0, h = 0;
    for (double& x : k) f >> x;
    for (double& x : dist) f >> x;
    for (double& x : r) f >> x;
    for (double& x : c) f >> x;
    f >> w >> h;
    if (!f || v.image.empty() || v.image.cols != w || v.image.rows != h || k[1] != 0.0) return false;
    v.model = makePinhole(static_cast<std::uint16_t>(w), static_cast<std::uint16_t>(h), 45.0);
    v.model.fx_px = k[0];
    v.model.fy_px = k[4];
    v.model.cx_px = k[2];
    v.model.cy_px = k[5];
    // The files give R to 9 digits, orthonormal to about 1e-6 only: the nearest rotation.
    Mat3 m;
    m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    const Eigen::JacobiSVD<Mat3> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
    v.site_from_cam.R = svd.matrixU() * svd.matrixV().transpose();
    v.site_from_cam.t_m = Vec3(c[0], c[1], c[2]);
    return true;
}

struct Errors {
    bool ok = false;
    double rotation_deg = 0.0;
    double direction_deg = 0.0;
};

Errors errorsOf(const Mat3& R, const Vec3& t, const RigidPose& truth) {
    return {true, motion::rotationAngleRad(R, truth.R) / kDeg, motion::directionAngleRad(t, truth.t_m) / kDeg};
}

// The prior: the truth turned by 2 deg about an axis that changes from pair to pair and
// moved sideways (perpendicular to the baseline) by 5 % of its length.
CameraPair spoiledPrior(const View& a, const View& b, int k) {
    CameraPair p;
    p.model_a = a.model;
    p.model_b = b.model;
    const RigidPose truth = relativePose(a.site_from_cam, b.site_from_cam);
    const Vec3 axis = Vec3(std::cos(1.3 * k), std::sin(1.3 * k), 0.6).normalized();
    p.b_from_a.R = Eigen::AngleAxisd(2.0 * kDeg, axis).toRotationMatrix() * truth.R;
    const Vec3 side = truth.t_m.cross(k % 2 == 0 ? Vec3::UnitY() : Vec3::UnitX()).normalized();
    p.b_from_a.t_m = truth.t_m + 0.05 * truth.t_m.norm() * side;
    return p;
}

// The dense map of a rectified pair against the SIFT matches that the TRUE cameras confirm
// (Sampson distance <= 1 px): their disparity after rectification, found without the
// flight modules, and the map's at their rectified pixel in A.
struct DenseCheck {
    bool done = false;
    std::string why;  // when not done
    std::int32_t d_min = 0, d_max = 0;
    double share = 0.0;              // of A's rectified pixels with content, mapped
    std::size_t checked = 0;         // true-geometry SIFT matches inside both rectified images
    std::size_t mapped = 0;          // of those, with a dense disparity
    double within1 = 0.0;            // of the mapped, |dense - SIFT| <= 1 px
    double median_abs = 0.0;         // |dense - SIFT|, px
};

struct PairRun {
    std::string name;
    Errors prior, ours, opencv;
    std::int32_t inliers = 0;
    std::int32_t cv_inliers = 0;
    refine::Result result;
    std::string failure;
    int step = 1;  // 1: neighbouring views, 2: second neighbours
    std::vector<Vec2> sift_a, sift_b;  // OpenCV's matches, for the rows after rectification
    RowStats rows;                     // of those matches, rectified with the refined pose
    bool rectified = false;
    DenseCheck dense;                  // the ML stereo of the rectified pair
};

void runOurs(const View& a, const View& b, int k, PairRun& run) {
    refine::Config rc;
    rc.match_margin_px = 60.0;  // 2 deg at f 920 px: 32 px, and the sideways move
    rc.max_rotation_sigma_deg = refine::kGeneralSceneMaxRotationSigmaDeg;  // as `vtm refine`
    static Workspace rw(refine::PairRefiner::workspaceBytes(rc));
    static refine::PairRefiner refiner;
    static const bool ready = refiner.init(rc, rw.arena).isOk();
    ASSERT_TRUE(ready);
    refine::Request rq;
    rq.prior = spoiledPrior(a, b, k);
    rq.image_a = greyView(a.image);
    rq.image_b = greyView(b.image);
    // The caller's range prior: the facades and courtyards lie 5-25 m from the cameras.
    // With 1-200 m the search segments are four times longer: 8 of 22 pairs refused and
    // three refined 3-8 deg wrong on 21-97 inliers (docs/wide-baseline-evaluation.md).
    rq.range_min_m = 3.0;
    rq.range_max_m = 50.0;
    rq.scene = refine::Scene::kGeneral;
    const RigidPose truth = relativePose(a.site_from_cam, b.site_from_cam);
    run.prior = errorsOf(rq.prior.b_from_a.R, rq.prior.b_from_a.t_m, truth);
    const Status st = refiner.refine(rq, run.result);
    if (!st.isOk()) {
        run.failure = st.reason();
        if (st.detail() != 0 && std::strstr(st.reason(), "too uncertain") != nullptr) {
            // The certainty gate: what the refusal kept from being published.
            const Errors held = errorsOf(run.result.motion.R_b_from_a, run.result.motion.t_b_from_a_m, truth);
            run.failure += " (1-sigma " + std::to_string(st.detail()) + " mdeg; it was " +
                           std::to_string(held.rotation_deg) + " / " + std::to_string(held.direction_deg) + " deg off)";
        }
        return;
    }
    run.ours = errorsOf(run.result.refined.b_from_a.R, run.result.refined.b_from_a.t_m, truth);
    run.inliers = run.result.motion.inliers;
}

// SIFT matches, normalised by each view's K, the essential matrix by RANSAC (1 px) and
// the pose by the cheirality test: OpenCV's answer from the images alone.
void runOpenCv(const View& a, const View& b, PairRun& run) {
    std::vector<Vec2>& pa = run.sift_a;
    std::vector<Vec2>& pb = run.sift_b;
    siftMatches(a.image, b.image, pa, pb);
    if (pa.size() < 8U) return;
    std::vector<cv::Point2d> na, nb;
    for (std::size_t i = 0; i < pa.size(); ++i) {
        na.emplace_back((pa[i].x() - a.model.cx_px) / a.model.fx_px, (pa[i].y() - a.model.cy_px) / a.model.fy_px);
        nb.emplace_back((pb[i].x() - b.model.cx_px) / b.model.fx_px, (pb[i].y() - b.model.cy_px) / b.model.fy_px);
    }
    cv::Mat mask;
    const double f = 0.5 * (a.model.fx_px + a.model.fy_px);
    const cv::Mat E = cv::findEssentialMat(na, nb, 1.0, cv::Point2d(0, 0), cv::RANSAC, 0.999, 1.0 / f, mask);
    if (E.rows != 3 || E.cols != 3) return;
    cv::Mat R, t;
    run.cv_inliers = cv::recoverPose(E, na, nb, R, t, 1.0, cv::Point2d(0, 0), mask);
    Mat3 r;
    for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = R.at<double>(i / 3, i % 3);
    const RigidPose truth = relativePose(a.site_from_cam, b.site_from_cam);
    run.opencv = errorsOf(r, Vec3(t.at<double>(0), t.at<double>(1), t.at<double>(2)), truth);
}

// The fundamental matrix of the two views' TRUE cameras (x_b^T F x_a = 0).
Mat3 trueFundamental(const View& a, const View& b) {
    const RigidPose truth = relativePose(a.site_from_cam, b.site_from_cam);
    const Vec3& t = truth.t_m;
    Mat3 tx;
    tx << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
    Mat3 ka, kb;
    ka << a.model.fx_px, 0.0, a.model.cx_px, 0.0, a.model.fy_px, a.model.cy_px, 0.0, 0.0, 1.0;
    kb << b.model.fx_px, 0.0, b.model.cx_px, 0.0, b.model.fy_px, b.model.cy_px, 0.0, 0.0, 1.0;
    return kb.inverse().transpose() * tx * truth.R * ka.inverse();
}

// Sampson distance (px) of a match under the fundamental matrix f.
double sampsonPx(const Mat3& f, const Vec2& pa, const Vec2& pb) {
    const Vec3 xa(pa.x(), pa.y(), 1.0), xb(pb.x(), pb.y(), 1.0);
    const Vec3 fa = f * xa, fb = f.transpose() * xb;
    const double e = xb.dot(fa);
    return std::fabs(e) / std::sqrt(fa.x() * fa.x() + fa.y() * fa.y() + fb.x() * fb.x() + fb.y() * fb.y());
}

// The ML stereo of the rectified pair over the disparities of the refiner's inliers, 16 px
// wider each side, and its check against the true-geometry SIFT matches (DenseCheck).
void mapDense(const View& a, const View& b, const rectify::Rectifier& rectifier, const rectify::RectifiedPair& pair,
              PairRun& run) {
    std::vector<Vec2> inl_a, inl_b;
    inlierPixels(run.result, inl_a, inl_b);
    const std::vector<double> inlier_d = matchDisparities(rectifier, inl_a, inl_b);
    DenseCheck& c = run.dense;
    if (inlier_d.size() < 2U) {
        c.why = "no inlier disparities";
        return;
    }
    c.d_min = static_cast<std::int32_t>(std::floor(*std::min_element(inlier_d.begin(), inlier_d.end()))) - 16;
    c.d_max = static_cast<std::int32_t>(std::ceil(*std::max_element(inlier_d.begin(), inlier_d.end()))) + 16;
    if (c.d_max - c.d_min + 1 > 1024) {
        c.why = "inlier disparities span more than the ML stereo's 1024 values";
        return;
    }
    DenseMap dense;
    const Status st = denseMap(rectifier, pair, a.image, b.image, c.d_min, c.d_max, dense);
    if (!st.isOk()) {
        c.why = st.reason();
        return;
    }
    c.done = true;
    c.share = dense.share();
    const Mat3 f = trueFundamental(a, b);
    std::vector<double> diff;
    for (std::size_t i = 0; i < run.sift_a.size(); ++i) {
        if (sampsonPx(f, run.sift_a[i], run.sift_b[i]) > 1.0) continue;
        Vec2 ra, rb;
        if (!rectifier.rectifyPixel(rectify::Rectifier::Side::kA, run.sift_a[i], ra).isOk() ||
            !rectifier.rectifyPixel(rectify::Rectifier::Side::kB, run.sift_b[i], rb).isOk()) {
            continue;
        }
        const auto x = static_cast<std::int32_t>(std::lround(ra.x()));
        const auto y = static_cast<std::int32_t>(std::lround(ra.y()));
        if (x < 0 || y < 0 || x >= dense.rect_a.cols || y >= dense.rect_a.rows || rb.x() < 0.0 ||
            rb.x() > dense.rect_a.cols - 1.0) {
            continue;
        }
        ++c.checked;
        double d = 0.0;
        if (dense.at(x, y, d)) {
            diff.push_back(std::fabs(d - (ra.x() - rb.x())));
        }
    }
    c.mapped = diff.size();
    if (!diff.empty()) {
        c.within1 = static_cast<double>(std::count_if(diff.begin(), diff.end(), [](double v) { return v <= 1.0; })) /
                    static_cast<double>(diff.size());
        std::nth_element(diff.begin(), diff.begin() + static_cast<std::ptrdiff_t>(diff.size() / 2), diff.end());
        c.median_abs = diff[diff.size() / 2];
    }
    if (const char* dir = std::getenv("VTM_STRECHA_OUT")) {
        std::string name = run.name;
        std::replace(name.begin(), name.end(), ' ', '-');
        const std::string base = std::string(dir) + "/strecha-" + name;
        cv::imwrite(base + "-rectified1.png", dense.rect_a);
        cv::imwrite(base + "-rectified2.png", dense.rect_b);
        writeDisparityPng(base + "-disparity.png", dense, static_cast<float>(c.d_min), static_cast<float>(c.d_max));
    }
}

// The refined pair rectified (Fusiello, docs/rectify.md); the rows of OpenCV's matches,
// found without the refinement, after it. RANSAC-free: wrong SIFT matches stay in
// (RowStats' RMS counts |vd| <= 2 px only; the median takes all).
void rectifyRefined(const View& a, const View& b, PairRun& run) {
    if (!run.ours.ok || run.sift_a.empty()) return;
    rectify::Config xc;
    xc.range_min_m = 3.0;
    xc.range_max_m = 50.0;
    static Workspace xw(rectify::Rectifier::workspaceBytes(xc));
    static rectify::Rectifier rectifier;
    static const bool ready = rectifier.init(xc, xw.arena).isOk();
    ASSERT_TRUE(ready);
    rectify::RectifiedPair pair;
    if (!rectifier.compute({run.result.refined}, pair).isOk()) return;
    run.rows = rowStats(rectifier, run.sift_a, run.sift_b);
    run.rectified = true;
    mapDense(a, b, rectifier, pair, run);
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

struct Set {
    const char* name;
    int views;
    bool second_in_ci;  // second neighbours in the CI form too
};
constexpr Set kSets[] = {{"herz-jesus-p8", 8, false}, {"entry-p10", 10, false}};

bool full() { return std::getenv("VTM_STRECHA_FULL") != nullptr; }

TEST(StrechaPairs, RefinedFromASpoiledPriorBesideOpenCvEssentialMatrix) {
    VTM_REQUIRE_TEST_DATA(kRoot);
    std::vector<PairRun> runs;
    for (std::size_t si = 0; si < sizeof kSets / sizeof kSets[0]; ++si) {
        const Set& s = kSets[si];
        std::vector<View> views(static_cast<std::size_t>(s.views));
        for (int i = 0; i < s.views; ++i) ASSERT_TRUE(loadView(s.name, i, views[static_cast<std::size_t>(i)])) << s.name << " " << i;
        for (int step = 1; step <= 2; ++step) {
            if (step == 2 && !s.second_in_ci && !full()) continue;
            for (int i = 0; i + step < s.views; ++i) {
                PairRun run;
                run.step = step;
                run.name = std::string(s.name) + " " + std::to_string(i) + "-" + std::to_string(i + step);
                // The prior's spoiling axis depends on the pair alone (not on which pairs ran before).
                const int k = 100 * static_cast<int>(si) + 10 * step + i;
                runOurs(views[static_cast<std::size_t>(i)], views[static_cast<std::size_t>(i + step)], k, run);
                runOpenCv(views[static_cast<std::size_t>(i)], views[static_cast<std::size_t>(i + step)], run);
                rectifyRefined(views[static_cast<std::size_t>(i)], views[static_cast<std::size_t>(i + step)], run);
                runs.push_back(run);
            }
        }
    }
    std::vector<double> our_rot, our_dir, cv_rot, cv_dir;
    double our_worst = 0.0, cv_worst = 0.0;
    int ours_better = 0, failures = 0;
    std::printf("| pair | prior rot / dir deg | VTM rot / dir deg (inliers) | OpenCV rot / dir deg (inliers) | SIFT rows after rectification: median |vd| / RMS (|vd| <= 2) px / within 1 px (matches) |\n");
    for (const PairRun& r : runs) {
        std::printf("| %s | %.2f / %.2f | ", r.name.c_str(), r.prior.rotation_deg, r.prior.direction_deg);
        if (r.ours.ok) {
            std::printf("%.4f / %.3f (%d) | ", r.ours.rotation_deg, r.ours.direction_deg, r.inliers);
            our_rot.push_back(r.ours.rotation_deg);
            our_dir.push_back(r.ours.direction_deg);
            our_worst = std::max({our_worst, r.ours.rotation_deg, r.ours.direction_deg});
        } else {
            std::printf("refused: %s | ", r.failure.c_str());
            ++failures;
        }
        std::printf("%.4f / %.3f (%d) | ", r.opencv.rotation_deg, r.opencv.direction_deg, r.cv_inliers);
        if (r.rectified) {
            std::printf("%.3f / %.3f / %.1f %% (%zu) |\n", r.rows.median_abs, r.rows.rms_px, 100.0 * r.rows.within1,
                        r.rows.count);
        } else {
            std::printf("- |\n");
        }
        cv_rot.push_back(r.opencv.ok ? r.opencv.rotation_deg : 180.0);
        cv_dir.push_back(r.opencv.ok ? r.opencv.direction_deg : 180.0);
        cv_worst = std::max({cv_worst, cv_rot.back(), cv_dir.back()});
        ours_better += r.ours.ok && r.ours.rotation_deg + r.ours.direction_deg <
                                        cv_rot.back() + cv_dir.back() ? 1 : 0;
    }
    std::printf("\n| pair | disparities searched | mapped (of rectified pixels with content) | true-geometry SIFT matches: in view / with a dense disparity | within 1 px of SIFT | median abs difference px |\n|---|---|---|---|---|---|\n");
    for (const PairRun& r : runs) {
        if (!r.rectified) continue;
        const DenseCheck& c = r.dense;
        if (!c.done) {
            std::printf("| %s | not mapped: %s | | | | |\n", r.name.c_str(), c.why.c_str());
            continue;
        }
        std::printf("| %s | %d..%d | %.1f %% | %zu / %zu | %.1f %% | %.2f |\n", r.name.c_str(), c.d_min, c.d_max,
                    100.0 * c.share, c.checked, c.mapped, 100.0 * c.within1, c.median_abs);
    }
    std::printf("[ strecha ] %zu pairs: VTM median rotation %.4f deg, direction %.3f deg, worst %.3f deg, %d refused; "
                "OpenCV median rotation %.4f deg, direction %.3f deg, worst %.3f deg; VTM better on %d\n",
                runs.size(), median(our_rot), median(our_dir), our_worst, failures, median(cv_rot), median(cv_dir),
                cv_worst, ours_better);
    // Issue 21 item 5's targets: median rotation <= 0.05 deg and direction <= 0.5 deg, no
    // pair worse than 1 deg. A pair the refiner cannot refine (too few matches, or its own
    // rotation 1-sigma above the general scene's gate) is refused with its reason, not
    // published wrong: every pair refined within 1 deg, and at most one neighbouring pair in
    // five refused (second neighbours, 20-50 deg apart, are refused more often: too few
    // template matches; docs/wide-baseline-evaluation.md).
    int neighbours = 0, neighbours_refused = 0;
    for (const PairRun& r : runs) {
        neighbours += r.step == 1 ? 1 : 0;
        neighbours_refused += r.step == 1 && !r.ours.ok ? 1 : 0;
    }
    EXPECT_LE(5 * neighbours_refused, neighbours);
    for (const PairRun& r : runs) {
        if (r.ours.ok) {
            EXPECT_LE(std::max(r.ours.rotation_deg, r.ours.direction_deg), 1.0) << r.name;
        }
    }
    EXPECT_LE(median(our_rot), 0.05);
    EXPECT_LE(median(our_dir), 0.5);
    // Rows after rectification with the refined pose (item 5: <= 0.3 px): OpenCV's matches,
    // found independently, median |vd| 0.07-0.19 px on the pairs refined on >= 50 inliers
    // (the rectifier refuses two pairs whose baseline lies within 30 deg of the view).
    int rectified = 0;
    for (const PairRun& r : runs) {
        if (r.ours.ok && r.inliers >= 50) {
            if (r.rectified) {
                ++rectified;
                EXPECT_LE(r.rows.median_abs, 0.3) << r.name;
            }
        }
    }
    EXPECT_GE(rectified, 10);
    // The dense map of each rectified pair (item 5's ML stereo) against the SIFT matches the
    // true cameras confirm: measured 2026-12-06 on the 11 mapped neighbour pairs, 28-81 % of
    // the rectified pixels mapped, 78-97 % of the checked matches within 1 px of the map
    // (median difference 0.16-0.50 px). Bounds below those figures, so that a regression
    // fails: every mapped neighbour pair >= 20 % mapped (second neighbours, VTM_STRECHA_FULL:
    // 15.8-53.2 %, not bounded), every mapped pair >= 70 % within 1 px; over the neighbour
    // pairs, the median >= 40 % mapped and >= 90 % within 1 px; at least 10 of them mapped.
    std::vector<double> shares, agreement;
    for (const PairRun& r : runs) {
        if (!r.dense.done) continue;
        if (r.step == 1) {
            shares.push_back(r.dense.share);
            agreement.push_back(r.dense.within1);
            EXPECT_GE(r.dense.share, 0.2) << r.name;
        }
        EXPECT_GE(r.dense.mapped, 50U) << r.name << ": too few confirmed matches to judge the map";
        EXPECT_GE(r.dense.within1, 0.7) << r.name;
    }
    EXPECT_GE(shares.size(), 10U);
    EXPECT_GE(median(shares), 0.4);
    EXPECT_GE(median(agreement), 0.9);
    EXPECT_LT(median(our_rot), median(cv_rot));
    EXPECT_LT(median(our_dir), median(cv_dir));
}

}  // namespace
}  // namespace vtm
