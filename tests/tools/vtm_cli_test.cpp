// The `vtm` executable as a user runs it: exit codes, one-line error messages that name
// the offending input, the stereo output files (orientation and units checked against a
// synthetic pair with known disparities) and `vtm eval` on hand-computed cases.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/middlebury.hpp"
#include "vtm/ground/pfm.hpp"

namespace vtm::ground {
namespace {

using test::CommandRun;
using test::runCommand;
using test::slurp;

// Runs `vtm ARGS` with stdout and stderr captured into files of `dir`.
CommandRun vtm(const test::TempDir& dir, const std::string& args) { return runCommand(dir, VTM_EXECUTABLE, args); }

// A failed run: exit code `code`, nothing on stdout, exactly one line on stderr that
// contains `needle`.
::testing::AssertionResult failsWith(const CommandRun& r, int code, const std::string& needle) {
    const bool one_line = !r.err.empty() && r.err.find('\n') == r.err.size() - 1;
    if (r.exit_code == code && one_line && r.err.find(needle) != std::string::npos) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << "exit " << r.exit_code << " (want " << code << "), stderr \"" << r.err
                                         << "\" (want one line containing \"" << needle << "\")";
}

// Texture for matching: uniform random grey levels (fixed seed), one byte per pixel.
std::vector<std::uint16_t> noise(int count, unsigned seed) {
    std::vector<std::uint16_t> v(static_cast<std::size_t>(count));
    for (std::uint16_t& p : v) {
        seed = seed * 1103515245U + 12345U;
        p = static_cast<std::uint16_t>((seed >> 16) & 0xFFU);
    }
    return v;
}

constexpr int kW = 96;
constexpr int kH = 48;
// Top half at disparity 3, bottom half at 9: an upside-down PFM would swap them.
int trueDisparity(int y) { return (y < kH / 2) ? 3 : 9; }

// Left and right PGMs of the two-band scene: right (x, y) = texture (x + 16, y) and
// left (x, y) = right (x - d, y) = texture (x - d + 16, y); the texture is 16 px wider
// than the images so that every shifted pixel exists.
void writeTwoBandPair(const test::TempDir& dir) {
    constexpr int kTexW = kW + 16;
    const std::vector<std::uint16_t> tex = noise(kTexW * kH, 7U);
    const auto texel = [&](int x, int y) { return tex[static_cast<std::size_t>(y * kTexW + x)]; };
    std::vector<std::uint16_t> left;
    std::vector<std::uint16_t> right;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            right.push_back(texel(x + 16, y));
            left.push_back(texel(x - trueDisparity(y) + 16, y));
        }
    }
    test::writeBytes(dir.file("left.pgm"), test::pgmBytes(kW, kH, left));
    test::writeBytes(dir.file("right.pgm"), test::pgmBytes(kW, kH, right));
}

TEST(VtmCli, ExistingCommandsKeepTheirBehaviour) {
    test::TempDir dir;
    CommandRun r = vtm(dir, "version");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out.rfind("vtm ", 0), 0U) << r.out;
    EXPECT_NE(r.out.find("(Visual Terrain Mapper)"), std::string::npos);
    r = vtm(dir, "");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Build configuration"), std::string::npos);
    EXPECT_NE(r.out.find("Static memory budget"), std::string::npos);
    r = vtm(dir, "budget");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Static memory budget"), std::string::npos);
    EXPECT_NE(r.out.find("wide-baseline mapper workspace (1024x1024, coarse to fine)"), std::string::npos);
}

// `vtm budget --timing FILE` prints the report the timing script wrote, naming it; a
// missing report is one line that says how to measure it.
TEST(VtmCli, BudgetTimingPrintsTheMeasuredReportOrSaysHowToMeasureIt) {
    test::TempDir dir;
    CommandRun r = vtm(dir, "budget --timing " + dir.file("none.md"));
    EXPECT_TRUE(failsWith(r, 1, dir.file("none.md") + ": cannot open; measure it first with tools/budget/timing_budget.sh"));
    test::writeBytes(dir.file("t.md"), std::vector<std::uint8_t>{'|', ' ', 'r', 'e', 'f', 'i', 'n', 'e', ' ', '|', '\n'});
    r = vtm(dir, "budget --timing " + dir.file("t.md"));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("as measured by tools/budget/timing_budget.sh (" + dir.file("t.md") + ")"), std::string::npos);
    EXPECT_NE(r.out.find("| refine |"), std::string::npos);
}

TEST(VtmCli, StereoRefusesMissingFile) {
    test::TempDir dir;
    test::writeBytes(dir.file("right.pgm"), test::pgmBytes(16, 16, noise(256, 1U)));
    const CommandRun r = vtm(dir, "stereo " + dir.file("nope.png") + " " + dir.file("right.pgm") + " --disparity 0:7");
    EXPECT_TRUE(failsWith(r, 1, dir.file("nope.png") + ": cannot open: No such file or directory"));
}

TEST(VtmCli, StereoRefusesDifferentSizes) {
    test::TempDir dir;
    test::writeBytes(dir.file("a.pgm"), test::pgmBytes(16, 16, noise(256, 1U)));
    test::writeBytes(dir.file("b.pgm"), test::pgmBytes(20, 16, noise(320, 2U)));
    const CommandRun r = vtm(dir, "stereo " + dir.file("a.pgm") + " " + dir.file("b.pgm") + " --disparity 0:7");
    EXPECT_TRUE(failsWith(r, 1, "a.pgm is 16x16 but " + dir.file("b.pgm") + " is 20x16"));
}

TEST(VtmCli, StereoRefusesEmptyAndUnparsableRanges) {
    test::TempDir dir;
    test::writeBytes(dir.file("a.pgm"), test::pgmBytes(16, 16, noise(256, 1U)));
    const std::string pair = "stereo " + dir.file("a.pgm") + " " + dir.file("a.pgm");
    EXPECT_TRUE(failsWith(vtm(dir, pair + " --disparity 10:5"), 2, "--disparity '10:5': empty range (MIN > MAX)"));
    EXPECT_TRUE(failsWith(vtm(dir, pair + " --disparity abc"), 2, "--disparity 'abc': expected MIN:MAX"));
    EXPECT_TRUE(failsWith(vtm(dir, pair + " --disparity 3"), 2, "--disparity '3'"));
    EXPECT_TRUE(failsWith(vtm(dir, pair + " --disparity 0:7x"), 2, "--disparity '0:7x'"));
    EXPECT_TRUE(failsWith(vtm(dir, pair), 2, "--disparity is required"));
}

// 8192 px (the module's widest image) by 1024 disparities: a dense matcher keeps at
// least one byte per (column, disparity) of cost, 8 MiB already, so any implementation
// exceeds the 8 MiB flight budget.
TEST(VtmCli, StereoRefusesRangeOverTheFlightBudget) {
    test::TempDir dir;
    test::writeBytes(dir.file("wide.pgm"), test::pgmBytes(8192, 8, noise(8192 * 8, 3U)));
    const std::string pair = "stereo " + dir.file("wide.pgm") + " " + dir.file("wide.pgm");
    const CommandRun r = vtm(dir, pair + " --disparity 0:1023");
    EXPECT_TRUE(failsWith(r, 1, "--disparity 0:1023 on 8192x8"));
    EXPECT_NE(r.err.find("bytes of workspace, over the budget of 8388608 bytes (8 MiB)"), std::string::npos) << r.err;
}

TEST(VtmCli, StereoRefusesRangeBeyondTheModuleLimit) {
    test::TempDir dir;
    test::writeBytes(dir.file("a.pgm"), test::pgmBytes(16, 16, noise(256, 1U)));
    const std::string pair = "stereo " + dir.file("a.pgm") + " " + dir.file("a.pgm");
    const CommandRun r = vtm(dir, pair + " --disparity 0:2000");
    EXPECT_TRUE(failsWith(r, 1, "configuration refused for --disparity 0:2000"));
    EXPECT_TRUE(failsWith(vtm(dir, pair + " --disparity 0:7 --window 4"), 1, "window"));
}

TEST(VtmCli, StereoWritesPixelsUprightWithInfinityForNoMatch) {
    test::TempDir dir;
    writeTwoBandPair(dir);
    const CommandRun r = vtm(dir, "stereo " + dir.file("left.pgm") + " " + dir.file("right.pgm") +
                                      " --disparity 0:15 --window 7 --out " + dir.file("d.pfm") + " --uncertainty " +
                                      dir.file("u.pfm") + " --color " + dir.file("d.png"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("valid"), std::string::npos) << r.out;
    const Result<FloatImage> d = readPfm(dir.file("d.pfm"));
    ASSERT_TRUE(d.ok) << d.error;
    ASSERT_EQ(d.value.width, kW);
    ASSERT_EQ(d.value.height, kH);
    // Away from the left border and the band edge: mostly the true disparity, in pixels.
    int near[2] = {0, 0};
    int total[2] = {0, 0};
    for (int y = 8; y < kH - 8; ++y) {
        if (std::abs(y - kH / 2) < 6) {
            continue;
        }
        for (int x = 24; x < kW - 8; ++x) {
            const int band = (y < kH / 2) ? 0 : 1;
            ++total[band];
            near[band] += (std::fabs(d.value.at(x, y) - static_cast<float>(trueDisparity(y))) <= 0.5F) ? 1 : 0;
        }
    }
    EXPECT_GT(near[0], total[0] * 8 / 10) << "top band (d = 3)";
    EXPECT_GT(near[1], total[1] * 8 / 10) << "bottom band (d = 9)";
    // No match is +inf, never a finite sentinel; the uncertainty is +inf there too.
    const Result<FloatImage> u = readPfm(dir.file("u.pfm"));
    ASSERT_TRUE(u.ok) << u.error;
    for (std::size_t i = 0; i < d.value.pixels.size(); ++i) {
        const float v = d.value.pixels[i];
        ASSERT_TRUE(std::isinf(v) || (v >= 0.0F && v <= 15.0F)) << v;
        ASSERT_TRUE(std::isfinite(v) || std::isinf(u.value.pixels[i])) << i;
    }
    const Result<GreyImage> png = loadGrey8(dir.file("d.png"));
    ASSERT_TRUE(png.ok) << png.error;
    EXPECT_EQ(png.value.width, kW);
}

// Estimate 10, 10.5, 12, no match against ground truth 10 (level 40 at scale 4):
// errors 0, 0.5, 2, no match.
void writeEvalCase(const test::TempDir& dir) {
    test::Bytes pfm = test::textBytes("Pf\n4 1\n-1\n");
    pfm.insert(pfm.end(), {0x00, 0x00, 0x20, 0x41,    // 10.0
                           0x00, 0x00, 0x28, 0x41,    // 10.5
                           0x00, 0x00, 0x40, 0x41,    // 12.0
                           0x00, 0x00, 0x80, 0x7F});  // +inf
    test::writeBytes(dir.file("est.pfm"), pfm);
    test::writeBytes(dir.file("gt.pgm"), test::pgmBytes(4, 1, {40, 40, 40, 40}));
    test::writeBytes(dir.file("mask.pgm"), test::pgmBytes(4, 1, {255, 255, 255, 0}));
}

TEST(VtmCli, EvalPrintsHandComputedFigures) {
    test::TempDir dir;
    writeEvalCase(dir);
    CommandRun r = vtm(dir, "eval " + dir.file("est.pfm") + " " + dir.file("gt.pgm") + " --scale 4");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // bad>0.5: 2.0 + no match = 2/4; bad>1 the same; bad>2: no match only (2.0 is not > 2).
    EXPECT_NE(r.out.find("bad>0.5         50.00 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bad>1           50.00 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bad>2           25.00 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("invalid         25.00 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("MAE             0.833 px"), std::string::npos) << r.out;  // 2.5 / 3

    r = vtm(dir,
            "eval " + dir.file("est.pfm") + " " + dir.file("gt.pgm") + " --scale 4 --mask " + dir.file("mask.pgm"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("evaluated     3 px"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bad>0.5         33.33 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("invalid          0.00 %"), std::string::npos) << r.out;
}

TEST(VtmCli, EvalRefusesBadInputs) {
    test::TempDir dir;
    writeEvalCase(dir);
    const std::string est = dir.file("est.pfm");
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + dir.file("none.pfm") + " " + dir.file("gt.pgm") + " --scale 4"), 1,
                          dir.file("none.pfm") + ": cannot open"));
    EXPECT_TRUE(
        failsWith(vtm(dir, "eval " + est + " " + dir.file("gt.pgm")), 2, "gt.pgm: integer ground truth needs --scale"));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + est + " " + dir.file("no_gt.png")), 1,
                          dir.file("no_gt.png") + ": cannot open: No such file or directory"));
    test::writeBytes(dir.file("gt5.pgm"), test::pgmBytes(5, 1, {40, 40, 40, 40, 40}));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + est + " " + dir.file("gt5.pgm") + " --scale 4"), 1,
                          "disparity is 4x1 but ground truth is 5x1"));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + est + " " + dir.file("gt.pgm") + " --scale 4 --mask " + dir.file("m.png")),
                          1, "m.png: cannot open"));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + est + " --middlebury art --data " + dir.file("")), 1,
                          "unknown Middlebury set 'art'"));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + dir.file("gt.pgm") + " " + dir.file("gt.pgm") + " --scale 4"), 1,
                          "gt.pgm: not a PFM file"));
    EXPECT_TRUE(failsWith(vtm(dir, "eval " + est), 2, "give either GT or --middlebury SET"));
}

// The ground truth itself, written as a PFM, scores zero bad pixels on its own mask.
TEST(VtmCli, EvalMiddleburyGroundTruthAgainstItself) {
    const std::string data = test::testDataRoot();
    VTM_REQUIRE_TEST_DATA(test::testDataSet("middlebury") + "teddy");
    const Result<MiddleburyGroundTruth> truth = loadMiddleburyGroundTruth(data, "teddy");
    ASSERT_TRUE(truth.ok) << truth.error;
    test::TempDir dir;
    ASSERT_TRUE(writePfm(dir.file("gt.pfm"), truth.value.disparity_px).ok);
    const CommandRun r = vtm(dir, "eval " + dir.file("gt.pfm") + " --middlebury teddy --data '" + data + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("bad>0.5          0.00 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("left-right check of disp2.png vs disp6.png"), std::string::npos) << r.out;
}

// `vtm register` (docs/entropy.md "Command line") on real optical-infrared pairs of SRIF
// (../shared/data/srif): the printed G maps image 1's corners within 3 px of the data
// set's ground truth (gt_N.txt, the same convention), for two pairs the module registers
// (its rate over all pairs is SrifEvaluation's); --out holds the same G and the entropy
// images are written at the images' size.
std::vector<double> matrixRows(const std::string& text, const std::string& tag) {
    std::vector<double> g;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream l(line);
        std::string head;
        l >> head;
        if (tag.empty() || head == tag) {
            double v = 0.0;
            if (tag.empty()) {
                g.push_back(std::stod(head));
            }
            while (l >> v) {
                g.push_back(v);
            }
        }
    }
    return g;
}

// Correlation of the picture's image-2 squares with image 2 sampled through the true G
// moved by (dx, dy) px (the test's own bilinear sampling).
double squaresAgainstTruth(const GreyImage& picture, const GreyImage& b, const std::vector<double>& t, double dx,
                           double dy) {
    double n = 0, sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (int y = 0; y < picture.height; ++y) {
        for (int x = 0; x < picture.width; ++x) {
            if (((x / 32) + (y / 32)) % 2 == 0) continue;
            const double u = t[0] * x + t[1] * y + t[2] + dx;
            const double v = t[3] * x + t[4] * y + t[5] + dy;
            if (u < 1.0 || v < 1.0 || u > b.width - 2 || v > b.height - 2) continue;
            const int x0 = static_cast<int>(u);
            const int y0 = static_cast<int>(v);
            const double fx = u - x0, fy = v - y0;
            const double s = (b.at(x0, y0) * (1 - fx) + b.at(x0 + 1, y0) * fx) * (1 - fy) +
                             (b.at(x0, y0 + 1) * (1 - fx) + b.at(x0 + 1, y0 + 1) * fx) * fy;
            const double p = picture.at(x, y);
            n += 1;
            sa += p;
            sb += s;
            saa += p * p;
            sbb += s * s;
            sab += p * s;
        }
    }
    return (n * sab - sa * sb) / std::sqrt((n * saa - sa * sa) * (n * sbb - sb * sb));
}

TEST(VtmCli, RegisterFindsTheKnownTransformOfRealOpticalInfraredPairs) {
    const std::string dir_srif = test::testDataSet("srif") + "optical-infrared/";
    VTM_REQUIRE_TEST_DATA(dir_srif + "pair1_1.jpg");
    for (const int n : {1, 3}) {
        test::TempDir dir;
        const std::string pair = dir_srif + "pair" + std::to_string(n);
        const CommandRun r = vtm(dir, "register '" + pair + "_1.jpg' '" + pair + "_2.jpg' --rotation=-96:6 --scale 0.9:1.1 "
                                      "--shift-range 8 --out '" + dir.file("g.txt") + "' --entropy1 '" + dir.file("e1.png") +
                                      "' --entropy2 '" + dir.file("e2.png") + "' --matches '" + dir.file("m.png") + "'");
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::vector<double> g = matrixRows(r.out, "G");
        const std::vector<double> truth = matrixRows(slurp(dir_srif + "gt_" + std::to_string(n) + ".txt"), "");
        ASSERT_EQ(g.size(), 6U) << r.out;
        ASSERT_EQ(truth.size(), 6U);
        for (const double x : {0.0, 255.0}) {
            for (const double y : {0.0, 255.0}) {
                const double dx = (g[0] - truth[0]) * x + (g[1] - truth[1]) * y + (g[2] - truth[2]);
                const double dy = (g[3] - truth[3]) * x + (g[4] - truth[4]) * y + (g[5] - truth[5]);
                EXPECT_LT(std::hypot(dx, dy), 3.0) << "pair " << n << " corner " << x << "," << y;
            }
        }
        EXPECT_EQ(matrixRows(slurp(dir.file("g.txt")), "G"), g);
        const Result<GreyImage> e1 = loadGrey8(dir.file("e1.png"));
        ASSERT_TRUE(e1.ok) << e1.error;
        EXPECT_EQ(e1.value.width, 256);
        EXPECT_EQ(e1.value.height, 256);
        // The picture of the match: image 1's squares are image 1; image 2's follow image 2
        // through the true transform, and not through one 6 px off.
        const Result<GreyImage> m = loadGrey8(dir.file("m.png"));
        const Result<GreyImage> a = loadGrey8(pair + "_1.jpg");
        const Result<GreyImage> b = loadGrey8(pair + "_2.jpg");
        ASSERT_TRUE(m.ok && a.ok && b.ok) << m.error << a.error << b.error;
        ASSERT_TRUE(m.value.sameSize(a.value));
        EXPECT_EQ(m.value.at(5, 5), a.value.at(5, 5));
        EXPECT_EQ(m.value.at(100, 100), a.value.at(100, 100));
        const double right = squaresAgainstTruth(m.value, b.value, truth, 0.0, 0.0);
        const double off = squaresAgainstTruth(m.value, b.value, truth, 6.0, 0.0);
        EXPECT_GT(right, 0.75) << "pair " << n;
        EXPECT_LT(off, right - 0.3) << "pair " << n;
        std::printf("pair %d: picture's image-2 squares against the truth: NCC %.3f (6 px off: %.3f)\n", n, right, off);
    }
}

// No answer is a named refusal (a flat image has no entropy to match); bad ranges and
// missing files are one line naming the option or the file.
TEST(VtmCli, RegisterRefusesWithOneLineNamingTheInput) {
    test::TempDir dir;
    GreyImage flat(64, 64, 1, 120);
    GreyImage texture(64, 64);
    for (std::size_t i = 0; i < texture.pixels.size(); ++i) {
        texture.pixels[i] = static_cast<std::uint8_t>((i * 2654435761U) >> 24U);
    }
    ASSERT_TRUE(writePng(dir.file("flat.png"), flat).ok);
    ASSERT_TRUE(writePng(dir.file("texture.png"), texture).ok);
    const std::string both = "'" + dir.file("texture.png") + "' '" + dir.file("flat.png") + "'";
    EXPECT_TRUE(failsWith(vtm(dir, "register " + both), 1, "no registration"));
    EXPECT_TRUE(failsWith(vtm(dir, "register " + both + " --rotation 5:-5"), 2, "--rotation '5:-5'"));
    EXPECT_TRUE(failsWith(vtm(dir, "register " + both + " --scale abc"), 2, "--scale 'abc'"));
    EXPECT_TRUE(failsWith(vtm(dir, "register " + both + " --equalise-radius 64"), 2, "--equalise-radius 64"));
    EXPECT_TRUE(failsWith(vtm(dir, "register '" + dir.file("missing.png") + "' '" + dir.file("flat.png") + "'"),
                          1, "missing.png"));
}

}  // namespace
}  // namespace vtm::ground
