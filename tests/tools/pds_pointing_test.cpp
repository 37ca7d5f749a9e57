// The pointing adjustment of the real MER Navcam frames (../shared/data/mer_opportunity):
// the ties of neighbouring frames (matchPdsNeighbours) closed by adjustPdsPointing (fsw/bundle
// with the frames' centres held), judged on held-out ties (two folds: fit on every other tie
// of each pair, measure on the rest) against the labels' pointing and against OpenCV's
// stitching bundle adjusters on the same ties (docs/pds.md "Pointing adjustment"). Mosaics
// before and after are written when VTM_PDS_POINTING_PICTURES names a directory. Skipped when
// the data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "pds_pointing_peer.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pds_pointing.hpp"

namespace vtm::ground {
namespace {

constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;
constexpr double kRangeMin = 0.5;  // PdsTieConfig's range_min_m: the ties' rays start there

const char* const kNavcam[5] = {"1N491020376ILFCNY9P0706L0M1.IMG", "1N491020519ILFCNY9P0706L0M1.IMG",
                                "1N491020834ILFCNY9P0706L0M1.IMG", "1N491020993ILFCNY9P0706L0M1.IMG",
                                "1N491021154ILFCNY9P0706L0M1.IMG"};

std::string dataDir() { return test::testDataDir() + "/mer_opportunity/"; }

struct Panorama {
    std::vector<PdsImage> frames;
    std::vector<PdsTiePair> pairs;  // 1-2, 3-4, 4-5 (2-3 share nothing)
};

// The frames and their ties, read and matched once for every test of this file.
const Panorama& panorama() {
    static const Panorama p = [] {
        Panorama out;
        for (const char* f : kNavcam) {
            Result<PdsImage> r = readPdsImage(dataDir() + f);
            if (!r.ok) return Panorama{};
            out.frames.push_back(std::move(r.value));
        }
        for (const auto& ab : {std::pair<int, int>{0, 1}, {2, 3}, {3, 4}}) {
            const Result<PdsTieResult> t = matchPdsNeighbours(out.frames[static_cast<std::size_t>(ab.first)],
                                                              out.frames[static_cast<std::size_t>(ab.second)],
                                                              PdsTieConfig{});
            if (!t.ok) return Panorama{};
            out.pairs.push_back(PdsTiePair{ab.first, ab.second, t.value.ties});
        }
        return out;
    }();
    return p;
}

struct Figures {
    double median = 0.0, rms = 0.0, p90 = 0.0;
    int n = 0;
};

Figures figuresOf(std::vector<double> v) {
    Figures f;
    f.n = static_cast<int>(v.size());
    if (v.empty()) return f;
    std::sort(v.begin(), v.end());
    const auto at = [&](double q) { return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1U) + 0.5)]; };
    f.median = at(0.5);
    f.p90 = at(0.9);
    double s = 0.0;
    for (double x : v) s += x * x;
    f.rms = std::sqrt(s / static_cast<double>(v.size()));
    return f;
}

// A method's pointing: per frame the attitude correction and the centre's shift.
struct Pointing {
    std::vector<Vec3> correction_rad;
    std::vector<Vec3> shift_m;
};

// The frames with their attitudes turned about their projection centres and the centres moved.
std::vector<PdsImage> turned(const std::vector<PdsImage>& frames, const Pointing& pointing) {
    std::vector<PdsImage> out = frames;
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i].site_from_rover = pdsTurnedRoverPose(frames[i], pointing.correction_rad[i], pointing.shift_m[i]);
    }
    return out;
}

Pointing labels(std::size_t frames) { return Pointing{std::vector<Vec3>(frames, Vec3::Zero()), std::vector<Vec3>(frames, Vec3::Zero())}; }

// Ties of fold `fold` (every other tie of each pair; -1 for all).
std::vector<PdsTiePair> foldOf(const std::vector<PdsTiePair>& pairs, int fold) {
    std::vector<PdsTiePair> out = pairs;
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        out[p].ties.clear();
        for (std::size_t k = 0; k < pairs[p].ties.size(); ++k) {
            if (fold < 0 || static_cast<int>(k % 2U) == fold) out[p].ties.push_back(pairs[p].ties[k]);
        }
    }
    return out;
}

// Residual (px in B) of each tie of each pair under `frames`' pointing, fold as in foldOf:
//  - epipolar: the distance to the image of A's ray from 0.5 m to infinity (the ties' own
//    geometry: the centres 7-9 cm apart, the scene at any range);
//  - far: the distance to where A's ray lands at infinity (the one-centre model of a
//    rotation-only stitcher: zero only if the ties were far or the centres one).
enum class Residual { kEpipolar, kFar };

std::vector<std::vector<double>> residuals(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                                           int fold, Residual kind = Residual::kEpipolar) {
    std::vector<std::vector<double>> out;
    for (const PdsTiePair& p : foldOf(pairs, fold)) {
        out.emplace_back();
        const PdsImage& a = frames[static_cast<std::size_t>(p.frame_a)];
        const PdsImage& b = frames[static_cast<std::size_t>(p.frame_b)];
        for (const PdsTie& t : p.ties) {
            Vec2 far;
            const double r = kind == Residual::kEpipolar ? pdsEpipolarDistance(a, b, t.pixel_a, t.pixel_b, kRangeMin)
                             : pdsTransferPixel(a, b, t.pixel_a, 1e7, far) ? (far - t.pixel_b).norm()
                                                                            : 1e3;
            out.back().push_back(r);
        }
    }
    return out;
}

// The methods: the module (default config, or with the centres held) and OpenCV's two.
enum class Method { kModule, kModuleCentresHeld, kOpenCvReproj, kOpenCvRay };

Pointing fit(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs, Method method) {
    if (method == Method::kModule || method == Method::kModuleCentresHeld) {
        PdsPointingConfig config;
        if (method == Method::kModuleCentresHeld) config.centre_sigma_m = 0.0;
        const Result<PdsPointingResult> r = adjustPdsPointing(frames, pairs, config);
        EXPECT_TRUE(r.ok) << r.error;
        return r.ok ? Pointing{r.value.correction_rad, r.value.shift_m} : labels(frames.size());
    }
    const test::OpenCvPointing r = test::openCvPointing(
        frames, pairs, method == Method::kOpenCvRay ? test::OpenCvAdjuster::kRay : test::OpenCvAdjuster::kReproj);
    EXPECT_TRUE(r.ok) << r.error;
    return r.ok ? Pointing{r.correction_rad, labels(frames.size()).shift_m} : labels(frames.size());
}

// Held-out residuals per pair: fit on fold 0, measure fold 1, and the other way round.
std::vector<std::vector<double>> heldOut(const Panorama& pano, Method method, Residual kind = Residual::kEpipolar) {
    std::vector<std::vector<double>> out(pano.pairs.size());
    for (int fold = 0; fold < 2; ++fold) {
        const Pointing c = fit(pano.frames, foldOf(pano.pairs, fold), method);
        const std::vector<std::vector<double>> r = residuals(turned(pano.frames, c), pano.pairs, 1 - fold, kind);
        for (std::size_t p = 0; p < r.size(); ++p) out[p].insert(out[p].end(), r[p].begin(), r[p].end());
    }
    return out;
}

std::vector<double> joined(const std::vector<std::vector<double>>& v) {
    std::vector<double> out;
    for (const auto& x : v) out.insert(out.end(), x.begin(), x.end());
    return out;
}

void printRow(const char* what, const std::vector<std::vector<double>>& r) {
    std::printf("[ MEASURED ] %-40s", what);
    for (std::size_t p = 0; p <= r.size(); ++p) {
        const Figures f = figuresOf(p < r.size() ? r[p] : joined(r));
        std::printf(" | %.2f / %.2f / %.2f (%d)", f.median, f.rms, f.p90, f.n);
    }
    std::printf("\n");
}

void printCorrections(const char* what, const std::vector<Vec3>& c) {
    std::printf("[ MEASURED ] %-40s", what);
    for (const Vec3& v : c) std::printf(" | %.3f (%+.3f %+.3f %+.3f)", v.norm() * kDegPerRad, v.x() * kDegPerRad,
                                        v.y() * kDegPerRad, v.z() * kDegPerRad);
    std::printf("\n");
}

TEST(PdsPointing, AdjustmentClosesHeldOutTiesAgainstTheLabelsAndOpenCv) {
    const Panorama& pano = panorama();
    if (pano.frames.empty()) GTEST_SKIP() << "MER data not found under '" << dataDir() << "' (set VTM_DATA)";
    const std::size_t n = pano.frames.size();
    const Result<PdsPointingResult> all = adjustPdsPointing(pano.frames, pano.pairs, PdsPointingConfig{});
    ASSERT_TRUE(all.ok) << all.error;
    const bundle::BundleResult& b = all.value.bundle;
    std::printf("[ MEASURED ] adjustment on all %d ties: %d used, %d outliers, %d far (not triangulated), %d behind; "
                "%d iterations in %d rounds (stop %d); image RMS %.3f -> %.3f px, sigma0 %.3f\n",
                b.points, b.points_adjusted, b.too_few_inliers, b.not_triangulated, b.behind_camera, b.iterations,
                b.rounds, static_cast<int>(b.stop), b.rms_before_px, b.rms_after_px, b.sigma0);
    std::printf("[ MEASURED ] median / RMS / 90%% px (ties) | frames 1-2 | 3-4 | 4-5 | all\n");
    const auto before = residuals(pano.frames, pano.pairs, -1);
    printRow("epipolar: labels' pointing", before);
    printRow("epipolar: module fitted on all", residuals(turned(pano.frames, Pointing{all.value.correction_rad, all.value.shift_m}), pano.pairs, -1));
    const auto module = heldOut(pano, Method::kModule);
    const auto held = heldOut(pano, Method::kModuleCentresHeld);
    printRow("epipolar: module, held out", module);
    printRow("epipolar: module centres held, held out", held);
    const bool peer = test::openCvStitchingAvailable();
    std::vector<std::vector<double>> reproj, ray;
    if (peer) {
        reproj = heldOut(pano, Method::kOpenCvReproj);
        ray = heldOut(pano, Method::kOpenCvRay);
        printRow("epipolar: OpenCV Reproj, held out", reproj);
        printRow("epipolar: OpenCV Ray, held out", ray);
    }
    const auto far_before = residuals(pano.frames, pano.pairs, -1, Residual::kFar);
    printRow("at infinity: labels' pointing", far_before);
    printRow("at infinity: module, held out", heldOut(pano, Method::kModule, Residual::kFar));
    std::vector<std::vector<double>> far_reproj;
    if (peer) {
        far_reproj = heldOut(pano, Method::kOpenCvReproj, Residual::kFar);
        printRow("at infinity: OpenCV Reproj, held out", far_reproj);
        printRow("at infinity: OpenCV Ray, held out", heldOut(pano, Method::kOpenCvRay, Residual::kFar));
    }
    std::printf("[ MEASURED ] corrections, deg: |c| (about site x north, y east, z down) | frame 1 | 2 | 3 | 4 | 5\n");
    printCorrections("module", all.value.correction_rad);
    std::printf("[ MEASURED ] %-40s", "module sigma (deg), centre shift (mm)");
    for (std::size_t i = 0; i < n; ++i) {
        const Mat3& c = all.value.covariance_rad2[i];
        std::printf(" | %.3f %.3f %.3f, %.1f", std::sqrt(c(0, 0)) * kDegPerRad, std::sqrt(c(1, 1)) * kDegPerRad,
                    std::sqrt(c(2, 2)) * kDegPerRad, all.value.shift_m[i].norm() * 1e3);
    }
    std::printf("\n");
    printCorrections("module, centres held", fit(pano.frames, pano.pairs, Method::kModuleCentresHeld).correction_rad);
    if (peer) {
        printCorrections("OpenCV Reproj", fit(pano.frames, pano.pairs, Method::kOpenCvReproj).correction_rad);
        const test::OpenCvPointing r = test::openCvPointing(pano.frames, pano.pairs, test::OpenCvAdjuster::kRay);
        printCorrections("OpenCV Ray", r.correction_rad);
        std::printf("[ MEASURED ] %-40s", "OpenCV Ray focal (px; labels 1223.3)");
        for (double f : r.focal_px) std::printf(" | %.1f", f);
        std::printf("\n");
    }

    // Gates. Ties the adjustment has not seen close: per pair the held-out median and 90th
    // percentile below the labels' (and the RMS over all pairs, outliers included).
    const Figures before_all = figuresOf(joined(before)), module_all = figuresOf(joined(module));
    for (std::size_t p = 0; p < pano.pairs.size(); ++p) {
        const Figures f0 = figuresOf(before[p]), f1 = figuresOf(module[p]);
        EXPECT_LT(f1.median, f0.median) << "pair " << p;
        EXPECT_LT(f1.p90, f0.p90) << "pair " << p;
    }
    EXPECT_LT(module_all.rms, before_all.rms);
    // With the centres held (rotations only) too, over all pairs.
    EXPECT_LT(figuresOf(joined(held)).median, before_all.median);
    EXPECT_LT(figuresOf(joined(held)).p90, before_all.p90);
    // Almost every tie used; the corrections small: the labels' pointing is good to a fraction
    // of a degree and the mast places the centres to millimetres (two sigma of the prior).
    EXPECT_GE(b.points_adjusted, static_cast<int>(0.95 * b.points));
    EXPECT_EQ(b.stop, bundle::StopReason::kConverged);
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_LT(all.value.correction_rad[i].norm() * kDegPerRad, 0.5) << "frame " << i + 1;
        EXPECT_LT(all.value.shift_m[i].norm(), 2.0 * PdsPointingConfig{}.centre_sigma_m) << "frame " << i + 1;
    }
    // The peer: OpenCV's adjusters assume one projection centre; they lower their own residual
    // (where A's ray lands at infinity) but cannot close ties 1-13 m away seen from centres
    // 7-9 cm apart. The module's held-out residuals are below theirs on every pair.
    if (!peer) GTEST_SKIP() << "OpenCV's stitching module not built in: the peer is skipped";
    EXPECT_LT(figuresOf(joined(far_reproj)).median, figuresOf(joined(far_before)).median);
    for (std::size_t p = 0; p < pano.pairs.size(); ++p) {
        EXPECT_LT(figuresOf(module[p]).median, figuresOf(reproj[p]).median) << "pair " << p;
        EXPECT_LT(figuresOf(module[p]).median, figuresOf(ray[p]).median) << "pair " << p;
        EXPECT_LT(figuresOf(module[p]).p90, figuresOf(reproj[p]).p90) << "pair " << p;
    }
}

}  // namespace
}  // namespace vtm::ground
