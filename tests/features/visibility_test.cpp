// predictVisibility against the analytic answer: a level camera h metres above flat ground
// and a second camera b metres to its right, parallel. A ground point seen at row y below
// the horizon lies at depth z = h f / (y - cy); camera B sees it at x_b = x - f b / z =
// x - b (y - cy) / h. Pixels at or above the horizon get range_max (x_b ~ x).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "no_heap_guard.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/features/visibility.hpp"

namespace vtm::features {
namespace {

TEST(Visibility, LevelPairOverFlatGroundMatchesTheAnalyticFootprint) {
    constexpr std::int32_t kW = 160, kH = 120;
    const CameraModel m = makePinhole(kW, kH, 60.0);
    MatchPrediction p;
    p.pair.model_a = m;
    p.pair.model_b = m;
    const double b = 1.0;
    p.pair.b_from_a.t_m = Vec3(-b, 0.0, 0.0);  // B at A's +x: X_b = X_a - (b, 0, 0)
    p.range_min_m = 0.5;
    p.range_max_m = 1.0e4;
    VisibilityPrior prior;
    prior.up_a = Vec3(0.0, -1.0, 0.0);  // optical frame: +y is down
    prior.camera_height_m = 2.0;
    prior.margin_px = 4.0;
    prior.stride_px = 1;
    std::vector<std::uint8_t> mask(kW * kH, 7U);
    std::int64_t visible = 0;
    test::NoHeapScope scope;
    ASSERT_TRUE(predictVisibility(p, prior, ImageView<std::uint8_t>(mask.data(), kW, kH), visible).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    std::int64_t count = 0, checked = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const std::uint8_t v = mask[static_cast<std::size_t>(y * kW + x)];
            ASSERT_TRUE(v == 0U || v == 1U);
            count += v;
            const double dy = y - m.cy_px;
            const double xb = (dy > 0.0) ? x - b * dy / prior.camera_height_m : x - m.fx_px * b / p.range_max_m;
            const double left = prior.margin_px - 0.5;
            const double right = kW - 0.5 - prior.margin_px;
            const double slack = 0.01;  // away from the decision boundary
            // Rows do not change between the two (level, parallel) cameras: y must be inside too.
            const bool row_inside = y > prior.margin_px - 0.5 && y < kH - 0.5 - prior.margin_px;
            const bool row_outside = y < prior.margin_px - 0.5 || y > kH - 0.5 - prior.margin_px;
            if (row_outside) {
                EXPECT_EQ(v, 0U) << x << "," << y;
                ++checked;
            } else if (!row_inside) {
                continue;
            } else if (xb > left + slack && xb < right - slack) {
                EXPECT_EQ(v, 1U) << x << "," << y;
                ++checked;
            } else if (xb < left - slack || xb > right + slack) {
                EXPECT_EQ(v, 0U) << x << "," << y;
                ++checked;
            }
        }
    }
    EXPECT_EQ(count, visible);
    EXPECT_GT(checked, kW * kH * 9 / 10);
    // Near the bottom-left corner (near ground) outside B; near the top-left (sky) inside.
    EXPECT_EQ(mask[static_cast<std::size_t>((kH - 10) * kW + 10)], 0U);
    EXPECT_EQ(mask[static_cast<std::size_t>(10 * kW + 10)], 1U);
}

TEST(Visibility, BadInputsAreNamed) {
    const CameraModel m = makePinhole(64, 48, 60.0);
    MatchPrediction p;
    p.pair.model_a = m;
    p.pair.model_b = m;
    p.pair.b_from_a.t_m = Vec3(-1.0, 0.0, 0.0);
    VisibilityPrior prior;
    prior.up_a = Vec3(0.0, -1.0, 0.0);
    std::vector<std::uint8_t> mask(64 * 48);
    std::int64_t visible = 0;
    const ImageView<std::uint8_t> view(mask.data(), 64, 48);
    VisibilityPrior bad = prior;
    bad.up_a = Vec3::Zero();
    EXPECT_NE(std::strstr(predictVisibility(p, bad, view, visible).reason(), "up_a"), nullptr);
    bad = prior;
    bad.camera_height_m = 0.0;
    EXPECT_NE(std::strstr(predictVisibility(p, bad, view, visible).reason(), "camera_height_m"), nullptr);
    bad = prior;
    bad.stride_px = 0;
    EXPECT_NE(std::strstr(predictVisibility(p, bad, view, visible).reason(), "stride_px"), nullptr);
    EXPECT_EQ(predictVisibility(p, prior, ImageView<std::uint8_t>(mask.data(), 32, 48), visible).code(),
              StatusCode::kSizeMismatch);
    MatchPrediction other = p;  // the mask must be pair.model_a's size
    other.pair.model_a = makePinhole(32, 48, 60.0);
    EXPECT_EQ(predictVisibility(other, prior, view, visible).code(), StatusCode::kSizeMismatch);
}

TEST(Visibility, DetectorKeepsFeaturesInsideTheMask) {
    // A checkerboard-like texture everywhere; mask = right half only.
    constexpr std::int32_t kW = 128, kH = 96;
    std::vector<std::uint8_t> img(kW * kH), mask(kW * kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            img[static_cast<std::size_t>(y * kW + x)] = (((x / 8) + (y / 8)) % 2 != 0) ? 200U : 50U;
            mask[static_cast<std::size_t>(y * kW + x)] = (x >= kW / 2) ? 1U : 0U;
        }
    }
    DetectorConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.grid_cols = 8;
    c.grid_rows = 6;
    std::vector<std::byte> pool(ForstnerDetector::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    ForstnerDetector d;
    ASSERT_TRUE(d.init(c, arena).isOk());
    static FeatureSet all, masked;
    ASSERT_TRUE(d.detect(ImageView<const std::uint8_t>(img.data(), kW, kH), all).isOk());
    ASSERT_TRUE(d.detect(ImageView<const std::uint8_t>(img.data(), kW, kH), masked, nullptr,
                         ImageView<const std::uint8_t>(mask.data(), kW, kH))
                    .isOk());
    std::int32_t left_all = 0;
    for (std::int32_t i = 0; i < all.count; ++i) {
        left_all += all.items[i].pixel.x() < kW / 2 - 1 ? 1 : 0;
    }
    EXPECT_GT(left_all, 5);
    ASSERT_GT(masked.count, 5);
    for (std::int32_t i = 0; i < masked.count; ++i) {
        EXPECT_GE(masked.items[i].pixel.x(), kW / 2 - 1.0) << i;  // subpixel may move 0.5 px
    }
    EXPECT_EQ(d.detect(ImageView<const std::uint8_t>(img.data(), kW, kH), masked, nullptr,
                       ImageView<const std::uint8_t>(mask.data(), kW / 2, kH))
                  .code(),
              StatusCode::kSizeMismatch);
}

}  // namespace
}  // namespace vtm::features
