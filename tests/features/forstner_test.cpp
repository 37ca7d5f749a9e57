// ForstnerDetector: corners of an anti-aliased checkerboard against their analytic
// positions, grid spreading, border, the max_features cap, determinism, no heap, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "no_heap_guard.hpp"
#include "test_images.hpp"
#include "vtm/features/forstner.hpp"

namespace vtm::features {
namespace {

using test::Checkerboard;
using test::Image;

struct Detector {
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    ForstnerDetector detector;
    explicit Detector(const DetectorConfig& c) : pool(ForstnerDetector::workspaceBytes(c)) {
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        const Status s = detector.init(c, *arena);
        EXPECT_TRUE(s.isOk()) << s.reason();
    }
};

DetectorConfig boardConfig(std::int32_t w, std::int32_t h) {
    DetectorConfig c;
    c.max_width = w;
    c.max_height = h;
    c.grid_cols = 8;
    c.grid_rows = 8;
    c.per_cell = 4;
    c.window = 7;  // measured worst corner error: 0.101 px (5), 0.059 px (7), 0.029 px (9)
    return c;
}

// Largest distance from a true corner (at least `inset` px inside the image) to its nearest
// feature, and the number of such corners.
double worstCornerError(const Checkerboard& board, const FeatureSet& fs, std::int32_t w, std::int32_t h,
                        double inset, int& corners) {
    double worst = 0.0;
    corners = 0;
    for (int j = -12; j <= 12; ++j) {
        for (int i = -12; i <= 12; ++i) {
            double x = 0, y = 0;
            board.cornerAt(i, j, x, y);
            if (x < inset || y < inset || x > w - 1 - inset || y > h - 1 - inset) {
                continue;
            }
            ++corners;
            double nearest = 1e9;
            for (std::int32_t k = 0; k < fs.count; ++k) {
                nearest = std::min(nearest, std::hypot(fs.items[k].pixel.x() - x, fs.items[k].pixel.y() - y));
            }
            worst = std::max(worst, nearest);
        }
    }
    return worst;
}

// Checkerboard with 20 px squares, rotated 17 degrees, a corner at a subpixel position:
// every interior corner is found within 0.1 px (Euclidean distance from the analytic
// corner to the nearest feature), and no feature is more than 0.5 px from a corner.
TEST(ForstnerDetector, FindsCheckerboardCornersWithinATenthOfAPixel) {
    constexpr std::int32_t kW = 160, kH = 160;
    const Checkerboard board{80.37, 79.71, 20.0, 17.0 * M_PI / 180.0};
    const Image img = board.render(kW, kH);
    Detector d(boardConfig(kW, kH));
    FeatureSet fs;
    DetectorStats stats;
    vtm::test::NoHeapScope scope;
    ASSERT_TRUE(d.detector.detect(img.view(), fs, &stats).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    int corners = 0;
    const double worst = worstCornerError(board, fs, kW, kH, 16.0, corners);
    std::printf("[ measure  ] checkerboard: %d corners, worst error %.4f px (edge intersection), %d features\n",
                corners, worst, fs.count);
    EXPECT_GE(corners, 30);
    EXPECT_LT(worst, 0.1);
    for (std::int32_t k = 0; k < fs.count; ++k) {
        double nearest = 1e9;
        for (int j = -12; j <= 12; ++j) {
            for (int i = -12; i <= 12; ++i) {
                double x = 0, y = 0;
                board.cornerAt(i, j, x, y);
                nearest = std::min(nearest, std::hypot(fs.items[k].pixel.x() - x, fs.items[k].pixel.y() - y));
            }
        }
        EXPECT_LT(nearest, 0.5) << "feature " << k << " is not at a corner";
        // One feature per corner: the point estimate pulls neighbouring maxima of w onto
        // the same corner, and those duplicates must be gone (min_separation_px).
        for (std::int32_t j = 0; j < k; ++j) {
            EXPECT_GE((fs.items[k].pixel - fs.items[j].pixel).norm(),
                      static_cast<double>(DetectorConfig{}.min_separation_px))
                << "features " << j << " and " << k << " are one corner";
        }
    }
}

// The quadratic fit of w is the cheaper option. Box windows make w flat around an
// X-junction, so the maximum of w may sit anywhere on that plateau: every corner still
// has a feature within the window's half-width (+0.5 px of the clamp), and each offset is
// within 0.5 px per axis of an integer maximum.
TEST(ForstnerDetector, QuadraticFitIsWithinHalfAPixel) {
    constexpr std::int32_t kW = 160, kH = 160;
    const Checkerboard board{80.37, 79.71, 20.0, 17.0 * M_PI / 180.0};
    const Image img = board.render(kW, kH);
    DetectorConfig c = boardConfig(kW, kH);
    c.subpixel = Subpixel::kQuadraticFit;
    Detector d(c);
    FeatureSet fs;
    ASSERT_TRUE(d.detector.detect(img.view(), fs).isOk());
    int corners = 0;
    const double worst = worstCornerError(board, fs, kW, kH, 16.0, corners);
    std::printf("[ measure  ] checkerboard: worst error %.4f px (quadratic fit of w)\n", worst);
    EXPECT_LE(worst, std::hypot(c.window / 2 + 0.5, c.window / 2 + 0.5));
    EXPECT_GE(corners, 30);
}

Image texture(std::int32_t w, std::int32_t h, std::uint64_t seed) {
    const test::Texture t(seed, w / 2 + 8);
    return test::renderTexture(t, w, h, 0.0, 0.0, 4.0);
}

TEST(ForstnerDetector, SpreadsOverTheGridAndKeepsOffTheBorder) {
    constexpr std::int32_t kW = 192, kH = 176;
    const Image img = texture(kW, kH, 7U);
    DetectorConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.grid_cols = 6;
    c.grid_rows = 5;
    c.per_cell = 3;
    c.border_px = 14;
    c.subpixel = Subpixel::kQuadraticFit;  // |offset| <= 0.5: the integer maximum is recoverable
    Detector d(c);
    FeatureSet fs;
    DetectorStats stats;
    ASSERT_TRUE(d.detector.detect(img.view(), fs, &stats).isOk());
    std::vector<int> per_cell(30, 0);
    int last_cell = -1;
    int ambiguous = 0;
    for (std::int32_t k = 0; k < fs.count; ++k) {
        // The integer maximum is the integer within 0.5 px of the feature; when the fit was
        // clamped to exactly +-0.5 it is ambiguous and the feature is left out of the cell
        // checks (border checks hold either way).
        const double px = fs.items[k].pixel.x(), py = fs.items[k].pixel.y();
        if (std::fabs(px - std::floor(px) - 0.5) < 1e-9 || std::fabs(py - std::floor(py) - 0.5) < 1e-9) {
            ++ambiguous;
            EXPECT_GE(px, c.border_px - 0.5);
            EXPECT_GE(py, c.border_px - 0.5);
            EXPECT_LE(px, kW - 0.5 - c.border_px);
            EXPECT_LE(py, kH - 0.5 - c.border_px);
            continue;
        }
        const auto x = static_cast<int>(std::lround(px));
        const auto y = static_cast<int>(std::lround(py));
        EXPECT_GE(x, c.border_px);
        EXPECT_GE(y, c.border_px);
        EXPECT_LE(x, kW - 1 - c.border_px);
        EXPECT_LE(y, kH - 1 - c.border_px);
        const int cell = (y * c.grid_rows / kH) * c.grid_cols + x * c.grid_cols / kW;
        ++per_cell[static_cast<std::size_t>(cell)];
        EXPECT_GE(cell, last_cell) << "output not in cell order";
        last_cell = cell;
        EXPECT_GE(fs.items[k].roundness, c.min_roundness);
    }
    EXPECT_LE(ambiguous, fs.count / 10);
    for (int n : per_cell) {
        EXPECT_LE(n, c.per_cell);
    }
    EXPECT_GE(fs.count, 30 * 2);  // a textured image has corners in every cell
    EXPECT_EQ(stats.kept, fs.count);
    EXPECT_GT(stats.candidates, fs.count);
}

TEST(ForstnerDetector, CapKeepsTheStrongestAndIsDeterministic) {
    constexpr std::int32_t kW = 160, kH = 160;
    const Image img = texture(kW, kH, 11U);
    DetectorConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.grid_cols = 4;
    c.grid_rows = 4;
    c.per_cell = 8;
    c.max_features = 1024;
    Detector all(c);
    c.max_features = 10;
    Detector capped(c);
    FeatureSet fa, fc, fc2;
    ASSERT_TRUE(all.detector.detect(img.view(), fa).isOk());
    ASSERT_TRUE(capped.detector.detect(img.view(), fc).isOk());
    ASSERT_GT(fa.count, 10);
    ASSERT_EQ(fc.count, 10);
    std::vector<float> strengths;
    for (std::int32_t k = 0; k < fa.count; ++k) {
        strengths.push_back(fa.items[k].strength);
    }
    std::sort(strengths.rbegin(), strengths.rend());
    for (std::int32_t k = 0; k < fc.count; ++k) {
        EXPECT_GE(fc.items[k].strength, strengths[9]);
    }
    // Same input, same output bits (also from the same instance a second time).
    ASSERT_TRUE(capped.detector.detect(img.view(), fc2).isOk());
    ASSERT_EQ(fc2.count, fc.count);
    EXPECT_EQ(std::memcmp(fc.items, fc2.items, sizeof(Feature) * static_cast<std::size_t>(fc.count)), 0);
}

// A mask restricts features to the part of A that B sees (predictVisibility). That part
// may be small and faint (a wide baseline shares only A's far field) while the rest of the
// image is strong: the strength threshold is relative to the best w inside the mask and the
// grid spans the mask's bounding box, so the masked part gets a full grid of features.
TEST(ForstnerDetector, MaskGetsAFullGridAndAThresholdOfItsOwn) {
    constexpr std::int32_t kW = 256, kH = 256;
    Image img = texture(kW, kH, 5U);
    // Faint texture (contrast / 12, w / 144: below min_strength_ratio = 0.02 of the strong
    // part) in the box the mask opens: x, y in [160, 224).
    constexpr std::int32_t kX0 = 160, kY0 = 160, kSide = 64;
    for (std::int32_t y = kY0; y < kY0 + kSide; ++y) {
        for (std::int32_t x = kX0; x < kX0 + kSide; ++x) {
            img.at(x, y) = static_cast<std::uint8_t>(128 + (static_cast<int>(img.at(x, y)) - 128) / 12);
        }
    }
    // The mask opens the faint box less a margin the structure tensor's window (and the
    // gradient) does not cross: w there sees the faint texture only.
    constexpr std::int32_t kInset = 6;
    Image mask(kW, kH);
    for (std::int32_t y = kY0 + kInset; y < kY0 + kSide - kInset; ++y) {
        for (std::int32_t x = kX0 + kInset; x < kX0 + kSide - kInset; ++x) {
            mask.at(x, y) = 1U;
        }
    }
    DetectorConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.grid_cols = 4;  // a 64 px cell of the image: the mask's box is one of them
    c.grid_rows = 4;
    c.per_cell = 2;
    c.min_strength_ratio = 0.02f;
    Detector d(c);
    FeatureSet unmasked;
    ASSERT_TRUE(d.detector.detect(img.view(), unmasked).isOk());
    int faint = 0;
    for (std::int32_t k = 0; k < unmasked.count; ++k) {
        const Vec2& p = unmasked.items[k].pixel;
        faint += (p.x() >= kX0 + 4 && p.x() < kX0 + kSide - 4 && p.y() >= kY0 + 4 && p.y() < kY0 + kSide - 4) ? 1 : 0;
    }
    EXPECT_EQ(faint, 0) << "the faint box is below the whole image's threshold";

    FeatureSet fs;
    {
        vtm::test::NoHeapScope scope;  // the masked path allocates nothing either
        ASSERT_TRUE(d.detector.detect(img.view(), fs, nullptr, mask.view()).isOk());
        EXPECT_EQ(scope.heapCalls(), 0U);
    }
    constexpr std::int32_t kM0 = kY0 + kInset, kMSide = kSide - 2 * kInset;  // the mask's box (kX0 == kY0)
    std::vector<int> per_sub(16, 0);  // the mask's box in 4 x 4 sub-boxes
    for (std::int32_t k = 0; k < fs.count; ++k) {
        const Vec2& p = fs.items[k].pixel;
        ASSERT_TRUE(p.x() > kM0 - 3 && p.x() < kM0 + kMSide + 2 && p.y() > kM0 - 3 && p.y() < kM0 + kMSide + 2)
            << "feature at " << p.x() << ", " << p.y() << " outside the mask";
        const auto sx = std::clamp(static_cast<int>(std::floor((p.x() - kM0 + 0.5) * 4.0 / kMSide)), 0, 3);
        const auto sy = std::clamp(static_cast<int>(std::floor((p.y() - kM0 + 0.5) * 4.0 / kMSide)), 0, 3);
        ++per_sub[static_cast<std::size_t>(sy * 4 + sx)];
    }
    // One image cell would hold per_cell = 2 features; the mask's own grid holds up to 32.
    EXPECT_GE(fs.count, 16);
    EXPECT_GE(std::count_if(per_sub.begin(), per_sub.end(), [](int n) { return n > 0; }), 12);
}

TEST(ForstnerDetector, FlatImageHasNoFeatures) {
    Image img(64, 64);
    std::fill(img.pixels.begin(), img.pixels.end(), std::uint8_t{90});
    DetectorConfig c;
    c.max_width = 64;
    c.max_height = 64;
    Detector d(c);
    FeatureSet fs;
    fs.count = 5;
    ASSERT_TRUE(d.detector.detect(img.view(), fs).isOk());
    EXPECT_EQ(fs.count, 0);
}

TEST(ForstnerDetector, RejectsBadConfigAndInput) {
    DetectorConfig c;
    c.window = 4;
    EXPECT_EQ(c.validate().code(), StatusCode::kInvalidConfig);
    EXPECT_NE(std::strstr(c.validate().reason(), "window"), nullptr);
    c = DetectorConfig{};
    c.border_px = 3;
    EXPECT_NE(std::strstr(c.validate().reason(), "border_px"), nullptr);
    c = DetectorConfig{};
    c.max_features = kMaxFeatures + 1;
    EXPECT_NE(std::strstr(c.validate().reason(), "max_features"), nullptr);
    c = DetectorConfig{};
    c.min_roundness = 0.f;
    EXPECT_NE(std::strstr(c.validate().reason(), "min_roundness"), nullptr);
    EXPECT_EQ(ForstnerDetector::workspaceBytes(c), 0U);

    Image img(64, 64);
    FeatureSet fs;
    ForstnerDetector uninit;
    EXPECT_EQ(uninit.detect(img.view(), fs).code(), StatusCode::kNotInitialized);

    c = DetectorConfig{};
    c.max_width = 48;
    c.max_height = 48;
    Detector d(c);
    EXPECT_EQ(d.detector.detect(img.view(), fs).code(), StatusCode::kSizeMismatch);  // over capacity
    EXPECT_EQ(d.detector.detect(ImageView<const std::uint8_t>(), fs).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(d.detector.detect(ImageView<const std::uint8_t>(img.pixels.data(), 20, 20), fs).code(),
              StatusCode::kSizeMismatch);  // smaller than 2 * border_px + 3

    std::byte small[64];
    Arena tiny(small, sizeof small);
    ForstnerDetector d2;
    EXPECT_EQ(d2.init(DetectorConfig{}, tiny).code(), StatusCode::kOutOfMemory);
}

}  // namespace
}  // namespace vtm::features
