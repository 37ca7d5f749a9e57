// Tie points between the overlapping real MER Navcam frames (../shared/data/mer_opportunity)
// with fsw/features, and their residuals under the labels' pointing: the "before" figures
// of a pointing adjustment (docs/pds.md). A mosaic of the five frames on a cylinder is
// written when VTM_PDS_MOSAIC names a PNG path. Skipped when the data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pds_panorama.hpp"

namespace vtm::ground {
namespace {

const char* const kNavcam[5] = {"1N491020376ILFCNY9P0706L0M1.IMG", "1N491020519ILFCNY9P0706L0M1.IMG",
                                "1N491020834ILFCNY9P0706L0M1.IMG", "1N491020993ILFCNY9P0706L0M1.IMG",
                                "1N491021154ILFCNY9P0706L0M1.IMG"};

std::string dataDir() { return test::testDataSet("mer_opportunity"); }

std::vector<PdsImage> loadNavcam() {
    std::vector<PdsImage> frames;
    for (const char* f : kNavcam) {
        Result<PdsImage> r = readPdsImage(dataDir() + f);
        if (!r.ok) return {};
        frames.push_back(std::move(r.value));
    }
    return frames;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return -1.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1U) + 0.5)];
}

// The overlapping pairs (frames 2 and 3 are 72 deg apart and share nothing). Every tie
// lies within the search margin of the image of A's ray in B; under the labels' pointing
// the ties are a pixel or so off their rays (median < 1.5 px, 90 % < 3 px per pair: the
// "before" figure of a pointing adjustment, printed). Ranges from 0.5 m: frames 4 and 5
// look back over the rover's deck, about 1 m from the mast.
TEST(PdsPanorama, TiePointsInTheNavcamOverlapsAndTheirResiduals) {
    const std::vector<PdsImage> frames = loadNavcam();
    if (frames.empty()) {
        VTM_REQUIRE_TEST_DATA(dataDir());
        FAIL() << "no MER frame loaded from " << dataDir();
    }
    const PdsTieConfig config;
    const int pairs[3][2] = {{0, 1}, {2, 3}, {3, 4}};
    std::vector<double> all_epipolar;
    for (const auto& pair : pairs) {
        const PdsImage& a = frames[static_cast<std::size_t>(pair[0])];
        const PdsImage& b = frames[static_cast<std::size_t>(pair[1])];
        const Result<PdsTieResult> r = matchPdsNeighbours(a, b, config);
        ASSERT_TRUE(r.ok) << r.error;
        std::vector<double> epipolar, sphere;
        for (const PdsTie& t : r.value.ties) {
            epipolar.push_back(t.epipolar_px);
            sphere.push_back(t.sphere_px);
            EXPECT_LE(t.epipolar_px, config.margin_px + 1.0);
            EXPECT_GE(t.score, config.min_score);
            // In A's right part, in B's left part: the overlap strip.
            EXPECT_GT(t.pixel_a.x(), 600.0);
            EXPECT_LT(t.pixel_b.x(), 424.0);
        }
        all_epipolar.insert(all_epipolar.end(), epipolar.begin(), epipolar.end());
        std::printf("frames %d-%d: %d features in the overlap, %d ties (low score %d, not refined %d, not mutual %d, "
                    "no region %d); epipolar residual median %.2f px, 90%% %.2f px, max %.2f px; "
                    "20 m sphere residual median %.2f px, 90%% %.2f px\n",
                    pair[0] + 1, pair[1] + 1, r.value.features, static_cast<int>(r.value.ties.size()),
                    r.value.low_score, r.value.not_refined, r.value.not_mutual, r.value.no_region,
                    quantile(epipolar, 0.5), quantile(epipolar, 0.9), quantile(epipolar, 1.0), quantile(sphere, 0.5),
                    quantile(sphere, 0.9));
        EXPECT_GE(r.value.ties.size(), 20U) << "frames " << pair[0] + 1 << "-" << pair[1] + 1;
        EXPECT_LT(quantile(epipolar, 0.5), 1.5) << "frames " << pair[0] + 1 << "-" << pair[1] + 1;
        EXPECT_LT(quantile(epipolar, 0.9), 3.0) << "frames " << pair[0] + 1 << "-" << pair[1] + 1;
    }
    std::printf("all pairs: %d ties, epipolar residual median %.2f px, 90%% %.2f px\n",
                static_cast<int>(all_epipolar.size()), quantile(all_epipolar, 0.5), quantile(all_epipolar, 0.9));
}

// Normalised correlation of `one` with `two` shifted by (dx, dy) (two's pixel (x + dx + pad,
// y + dy + pad) against one's (x, y)), over the pixels both frames cover.
double shiftedNcc(const GreyImage& one, const GreyImage& two, int dx, int dy, int pad) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
    for (int y = 0; y < one.height; ++y) {
        for (int x = 0; x < one.width; ++x) {
            const double p = one.at(x, y), q = two.at(x + dx + pad, y + dy + pad);
            if (p == 0.0 || q == 0.0) continue;
            sa += p, sb += q, saa += p * p, sbb += q * q, sab += p * q, n += 1;
        }
    }
    if (n < 0.5 * static_cast<double>(one.pixels.size())) return -1.0;
    return (sab - sa * sb / n) / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
}

// The mosaic: where frames 1 and 2 overlap (site azimuths 90 and 126 deg, 45 deg fields of
// view: around 110 deg) each frame is put on the cylinder on its own, and frame 2's strip is
// slid over frame 1's by up to +-3 deg (0.1 deg per pixel). With the models and poses read
// right the best correlation is where the geometry puts it: within 0.3 deg (the scene is
// assumed 20 m away; the projection centres are a few cm apart). The whole mosaic is
// written as PNG (0.2 deg per pixel) when VTM_PDS_MOSAIC names a path.
TEST(PdsPanorama, CylinderMosaicOfTheFiveFrames) {
    const std::vector<PdsImage> frames = loadNavcam();
    if (frames.empty()) {
        VTM_REQUIRE_TEST_DATA(dataDir());
        FAIL() << "no MER frame loaded from " << dataDir();
    }
    const GreyImage mosaic = pdsCylinderMosaic(frames, PdsMosaicConfig{});
    ASSERT_EQ(mosaic.width, 2400);
    ASSERT_EQ(mosaic.height, 570);
    constexpr int kPad = 30;  // pixels = 3 deg
    const GreyImage one = pdsCylinderMosaic({frames[0]}, PdsMosaicConfig{105.0, 112.0, -25.0, 0.0, 0.1, 20.0});
    const GreyImage two = pdsCylinderMosaic({frames[1]}, PdsMosaicConfig{102.0, 115.0, -28.0, 3.0, 0.1, 20.0});
    ASSERT_EQ(two.width, one.width + 2 * kPad);
    ASSERT_EQ(two.height, one.height + 2 * kPad);
    double best = -2.0;
    int best_dx = 99, best_dy = 99;
    for (int dy = -kPad; dy <= kPad; ++dy) {
        for (int dx = -kPad; dx <= kPad; ++dx) {
            const double ncc = shiftedNcc(one, two, dx, dy, kPad);
            if (ncc > best) best = ncc, best_dx = dx, best_dy = dy;
        }
    }
    const double at_zero = shiftedNcc(one, two, 0, 0, kPad);
    std::printf("frames 1 and 2 on the cylinder (azimuth 105-112 deg, elevation -25..0 deg): NCC %.3f unshifted, "
                "best %.3f at a shift of (%d, %d) x 0.1 deg (azimuth, elevation down)\n",
                at_zero, best, best_dx, best_dy);
    EXPECT_LE(std::abs(best_dx), 3);
    EXPECT_LE(std::abs(best_dy), 3);
    EXPECT_GT(best, 0.6);
    const char* path = std::getenv("VTM_PDS_MOSAIC");
    if (path != nullptr && path[0] != '\0') {
        PdsMosaicConfig picture;
        picture.step_deg = 0.2;  // docs/images/pds_navcam_mosaic.png: 1200 x 285
        const Outcome w = writePng(path, pdsCylinderMosaic(frames, picture));
        EXPECT_TRUE(w.ok) << w.error;
    }
}

}  // namespace
}  // namespace vtm::ground
