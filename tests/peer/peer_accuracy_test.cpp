// The peers reproduce the README's peer table (shared/data/middlebury/README.md):
// bad>1 over non-occluded pixels, no-match counted bad, full image and "interior"
// (leftmost numDisparities columns left out), within kTolerancePoints percentage points.
// Evaluated with vtm_ground (loaders, non-occluded masks, evaluateDisparity): the same
// pipeline that scores VTM in stereo_accuracy_test.cpp, so this test also validates it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "middlebury_fixture.hpp"
#include "vtm/peer/peer_stereo.hpp"

namespace {

using vtm::peer::fixture::score;
using vtm::peer::fixture::toFloatImage;

constexpr double kTolerancePoints = 0.5;

enum class Method { kBm, kSgbm, kZncc };

struct PeerFigure {
    const char* set;
    Method method;
    double bad1;          // README "bad>1"
    double bad1Interior;  // README "bad>1 interior"
};

// The README's table, as published with the data (OpenCV 4.6, grey input).
constexpr PeerFigure kReadme[] = {
    {"tsukuba", Method::kBm, 14.8, 14.8},   {"tsukuba", Method::kSgbm, 6.1, 6.1},
    {"tsukuba", Method::kZncc, 13.2, 13.2}, {"venus", Method::kBm, 20.0, 15.8},
    {"venus", Method::kSgbm, 6.8, 1.9},     {"venus", Method::kZncc, 9.3, 8.9},
    {"teddy", Method::kBm, 28.6, 22.4},     {"teddy", Method::kSgbm, 16.9, 9.7},
    {"teddy", Method::kZncc, 15.4, 15.7},   {"cones", Method::kBm, 20.0, 13.1},
    {"cones", Method::kSgbm, 13.6, 6.1},    {"cones", Method::kZncc, 10.3, 9.9},
};

const char* methodName(Method m) {
    switch (m) {
        case Method::kBm: return "StereoBM bs9";
        case Method::kSgbm: return "StereoSGBM_3WAY bs5";
        case Method::kZncc: return "ZNCC 7x7 WTA";
    }
    return "?";
}

class PeerAccuracy : public ::testing::TestWithParam<const char*> {};

TEST_P(PeerAccuracy, ReproducesReadmeTable) {
    const std::string set = GetParam();
    VTM_REQUIRE_MIDDLEBURY(set);
    const auto loaded = vtm::ground::loadMiddleburyPair(vtm::peer::fixture::dataDir(), set);
    ASSERT_TRUE(loaded.ok) << loaded.error;
    const vtm::ground::MiddleburyPair& pair = loaded.value;
    const int nd = vtm::peer::numDisparitiesFor(vtm::peer::fixture::maxKnownDisparity(pair));
    // "Interior": the leftmost numDisparities columns, which OpenCV never computes, left out.
    vtm::ground::GreyImage interior = pair.truth.nonoccluded;
    for (std::int32_t y = 0; y < interior.height; ++y) {
        for (std::int32_t x = 0; x < nd && x < interior.width; ++x) {
            interior.at(x, y) = 0;
        }
    }
    const cv::Mat left = vtm::peer::asMat(pair.left.view());
    const cv::Mat right = vtm::peer::asMat(pair.right.view());
    for (const PeerFigure& f : kReadme) {
        if (set != f.set) {
            continue;
        }
        cv::Mat d;
        switch (f.method) {
            case Method::kBm: d = vtm::peer::stereoBm(left, right, nd); break;
            case Method::kSgbm: d = vtm::peer::stereoSgbm3Way(left, right, nd); break;
            case Method::kZncc: d = vtm::peer::znccWta(left, right, nd); break;
        }
        const vtm::ground::FloatImage px = toFloatImage(d);
        const double bad = score(px, pair).bad1_percent;
        const double badInterior = score(px, pair, &interior).bad1_percent;
        std::printf("%-8s %-20s nd %2d  bad>1 %5.2f (README %4.1f)  interior %5.2f (README %4.1f)\n",
                    set.c_str(), methodName(f.method), nd, bad, f.bad1, badInterior, f.bad1Interior);
        EXPECT_NEAR(bad, f.bad1, kTolerancePoints) << set << " " << methodName(f.method);
        EXPECT_NEAR(badInterior, f.bad1Interior, kTolerancePoints) << set << " " << methodName(f.method);
    }
}

INSTANTIATE_TEST_SUITE_P(Middlebury, PeerAccuracy, ::testing::Values("tsukuba", "venus", "teddy", "cones"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// numDisparities follows the README: ground-truth maximum rounded up to 16.
TEST(PeerParameters, NumDisparitiesRoundsUpTo16) {
    EXPECT_EQ(vtm::peer::numDisparitiesFor(14.0), 16);
    EXPECT_EQ(vtm::peer::numDisparitiesFor(19.75), 32);
    EXPECT_EQ(vtm::peer::numDisparitiesFor(52.75), 64);
    EXPECT_EQ(vtm::peer::numDisparitiesFor(55.0), 64);
    EXPECT_EQ(vtm::peer::numDisparitiesFor(64.0), 64);
}

// OpenCV's fixed point: negative (minDisparity - 1) * 16 is no match, else value / 16.
TEST(PeerParameters, FixedPointConversion) {
    cv::Mat d16 = (cv::Mat_<std::int16_t>(1, 4) << -16, 0, 17, 1023);
    const cv::Mat f = vtm::peer::fixedPointToFloat(d16);
    EXPECT_TRUE(std::isinf(f.at<float>(0, 0)));
    EXPECT_FLOAT_EQ(f.at<float>(0, 1), 0.0F);
    EXPECT_FLOAT_EQ(f.at<float>(0, 2), 17.0F / 16.0F);
    EXPECT_FLOAT_EQ(f.at<float>(0, 3), 1023.0F / 16.0F);
}

// ZNCC on a synthetic pair with a known constant shift: exact where the shift is
// visible; border rules as documented (zero padding: every pixel matched, column x
// searches d <= x; inside-only: no match in the r-pixel frame and where x - r < d).
TEST(PeerZncc, FindsKnownShiftAndFollowsBorderRules) {
    const int w = 80, h = 40, shift = 5;
    cv::Mat right(h, w, CV_8UC1), left(h, w, CV_8UC1);
    cv::RNG rng(12345);
    rng.fill(right, cv::RNG::UNIFORM, 0, 256);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            left.at<std::uint8_t>(y, x) = right.at<std::uint8_t>(y, x - shift >= 0 ? x - shift : 0);
        }
    }
    vtm::peer::ZnccOptions inside;
    inside.border = vtm::peer::ZnccBorder::kInsideOnly;
    const cv::Mat padded = vtm::peer::znccWta(left, right, 16);
    const cv::Mat strict = vtm::peer::znccWta(left, right, 16, inside);
    EXPECT_TRUE(std::isinf(strict.at<float>(0, 40)));   // top frame (r = 3)
    EXPECT_TRUE(std::isinf(strict.at<float>(20, 2)));   // left frame
    EXPECT_TRUE(std::isinf(strict.at<float>(20, 78)));  // right frame
    EXPECT_EQ(padded.at<float>(20, 0), 0.0F);           // column 0 can only search d = 0
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            ASSERT_TRUE(std::isfinite(padded.at<float>(y, x))) << x << "," << y;
            if (y >= 3 && y < h - 3 && x >= shift + 6 && x < w - 3) {
                ASSERT_EQ(strict.at<float>(y, x), static_cast<float>(shift)) << x << "," << y;
                ASSERT_EQ(padded.at<float>(y, x), static_cast<float>(shift)) << x << "," << y;
            }
        }
    }
}

// The view bridges: asMat wraps without copying; copyDisparity copies, +inf kept.
TEST(PeerViews, WrapAndCopy) {
    std::uint8_t grey[2 * 3] = {1, 2, 3, 4, 5, 6};
    const vtm::ImageView<const std::uint8_t> v(grey, 2, 2, 3);  // stride 3
    const cv::Mat m = vtm::peer::asMat(v);
    EXPECT_EQ(m.cols, 2);
    EXPECT_EQ(m.rows, 2);
    EXPECT_EQ(m.at<std::uint8_t>(1, 1), 5);
    EXPECT_EQ(m.data, grey);
    cv::Mat d = (cv::Mat_<float>(1, 2) << 1.5F, std::numeric_limits<float>::infinity());
    float out[2] = {};
    vtm::peer::copyDisparity(d, vtm::ImageView<float>(out, 2, 1));
    EXPECT_EQ(out[0], 1.5F);
    EXPECT_TRUE(std::isinf(out[1]));
    EXPECT_THROW(vtm::peer::copyDisparity(d, vtm::ImageView<float>(out, 1, 1)), std::invalid_argument);
}

}  // namespace
