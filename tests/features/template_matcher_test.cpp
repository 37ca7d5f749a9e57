// TemplateMatcher: image B is image A's continuous texture translated by (17.3, 4.0) px,
// which is exactly what a pinhole pair sees of a fronto-parallel plane at 10 m when B's
// centre is moved sideways (t = shift * Z / f). Truth: pixel_b = pixel_a + shift.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "no_heap_guard.hpp"
#include "test_images.hpp"
#include "vtm/features/features.hpp"

namespace vtm::features {
namespace {

using test::Image;
using test::Texture;

constexpr std::int32_t kW = 256, kH = 224;
constexpr double kShiftX = 17.3, kShiftY = 4.0, kPlaneZ = 10.0, kPad = 80.0;

struct Scene {
    CameraModel cam = makePinhole(kW, kH, 60.0);
    // Bilinear noise with a node every 2 px (no blur): with a smoother texture (3x3-blurred
    // nodes) NCC finds false peaks >= 0.8 a few px away (measured: 4 of 56 features matched
    // inside a wrong region, and a worst error of 0.21 px instead of 0.11 px).
    Texture texture{21U, kW / 2 + 100, 0};
    Image a = test::renderTexture(texture, kW, kH, 0.0, 0.0, kPad);
    Image b = test::renderTexture(texture, kW, kH, kShiftX, kShiftY, kPad);
    MatchPrediction prediction() const {
        MatchPrediction p;
        p.pair.model_a = cam;
        p.pair.model_b = cam;
        p.pair.b_from_a.t_m = Vec3(kShiftX * kPlaneZ / cam.fx_px, kShiftY * kPlaneZ / cam.fy_px, 0.0);
        p.range_min_m = 5.0;   // the plane is at 10..11.6 m along the rays
        p.range_max_m = 40.0;
        p.margin_px = 10.0;
        return p;
    }
};

struct Modules {
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    ForstnerDetector detector;
    TemplateMatcher matcher;
    Modules(const DetectorConfig& dc, const MatcherConfig& mc)
        : pool(ForstnerDetector::workspaceBytes(dc) + TemplateMatcher::workspaceBytes(mc)) {
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        EXPECT_TRUE(detector.init(dc, *arena).isOk());
        EXPECT_TRUE(matcher.init(mc, *arena).isOk());
    }
};

DetectorConfig detectorConfig() {
    DetectorConfig c;
    c.max_width = kW;
    c.max_height = kH;
    c.grid_cols = 8;
    c.grid_rows = 7;
    c.per_cell = 1;
    c.border_px = 24;
    return c;
}

MatcherConfig matcherConfig() {
    MatcherConfig c;
    c.max_width = kW;
    c.max_height = kH;
    return c;
}

TEST(TemplateMatcher, MatchesAShiftedImageWithinAFifthOfAPixel) {
    const auto scene = std::make_unique<Scene>();
    Modules m(detectorConfig(), matcherConfig());
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    ASSERT_TRUE(m.detector.detect(scene->a.view(), *fs).isOk());
    ASSERT_GE(fs->count, 40);
    MatchStats stats;
    vtm::test::NoHeapScope scope;
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, scene->prediction(), *out, &stats).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(stats.attempted, fs->count);
    EXPECT_EQ(stats.no_region + stats.low_score + stats.unverified + stats.not_refined + stats.not_mutual + stats.matched,
              stats.attempted);
    // Features whose true match keeps the template inside B must all match.
    double worst = 0.0, sum_sq = 0.0;
    for (std::int32_t i = 0; i < out->count; ++i) {
        const Match& mt = out->items[i];
        EXPECT_EQ(mt.pixel_a, fs->items[mt.feature_index].pixel);
        const double e = (mt.pixel_b - mt.pixel_a - Vec2(kShiftX, kShiftY)).norm();
        worst = std::max(worst, e);
        sum_sq += e * e;
        EXPECT_GE(mt.score, 0.8f);
    }
    std::printf("[ measure  ] %d features, %d matched, error worst %.3f px, RMS %.3f px\n", fs->count,
                out->count, worst, std::sqrt(sum_sq / std::max(1, out->count)));
    EXPECT_GE(out->count, fs->count * 8 / 10);
    EXPECT_LT(worst, 0.2);
}

// prepare() once and matchPrepared() one feature at a time (what fsw/tiepoints' inter
// search does) give match()'s bits; matchPrepared() refuses until prepare() has succeeded.
TEST(TemplateMatcher, PreparedPyramidsGiveMatchsBits) {
    const auto scene = std::make_unique<Scene>();
    Modules m(detectorConfig(), matcherConfig());
    const auto fs = std::make_unique<FeatureSet>();
    const auto all = std::make_unique<MatchSet>();
    const auto one = std::make_unique<MatchSet>();
    const auto single = std::make_unique<FeatureSet>();
    ASSERT_TRUE(m.detector.detect(scene->a.view(), *fs).isOk());
    fs->count = std::min(fs->count, 8);  // eight features are enough to compare bits
    ASSERT_EQ(m.matcher.matchPrepared(*fs, scene->prediction(), *one).code(), StatusCode::kNotInitialized);
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, scene->prediction(), *all).isOk());
    ASSERT_GE(all->count, 4);
    EXPECT_EQ(m.matcher.prepare(ImageView<const std::uint8_t>(), scene->b.view()).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(m.matcher.matchPrepared(*fs, scene->prediction(), *one).code(), StatusCode::kNotInitialized);
    ASSERT_TRUE(m.matcher.prepare(scene->a.view(), scene->b.view()).isOk());
    std::int32_t next = 0;  // index into all->items
    vtm::test::NoHeapScope scope;
    for (std::int32_t i = 0; i < fs->count; ++i) {
        single->items[0] = fs->items[i];
        single->count = 1;
        ASSERT_TRUE(m.matcher.matchPrepared(*single, scene->prediction(), *one).isOk());
        const bool matched = next < all->count && all->items[next].feature_index == i;
        ASSERT_EQ(one->count, matched ? 1 : 0) << "feature " << i;
        if (matched) {
            EXPECT_EQ(std::memcmp(one->items[0].pixel_b.data(), all->items[next].pixel_b.data(), sizeof(Vec2)), 0);
            EXPECT_EQ(one->items[0].score, all->items[next].score);
            ++next;
        }
    }
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(next, all->count);
}

// A region larger than kMaxCoarseCandidates positions (full resolution only, 120 px
// margin: about 240 x 210 positions) is searched on a stride over all of it, not cut off
// in raster order: the features still match, as precisely as with a small region.
TEST(TemplateMatcher, LargeRegionIsSearchedWhole) {
    const auto scene = std::make_unique<Scene>();
    MatcherConfig mc = matcherConfig();
    mc.pyramid_levels = 0;
    Modules m(detectorConfig(), mc);
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    ASSERT_TRUE(m.detector.detect(scene->a.view(), *fs).isOk());
    MatchPrediction p = scene->prediction();
    p.margin_px = 120.0;
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, p, *out).isOk());
    double worst = 0.0;
    for (std::int32_t i = 0; i < out->count; ++i) {
        worst = std::max(worst, (out->items[i].pixel_b - out->items[i].pixel_a - Vec2(kShiftX, kShiftY)).norm());
    }
    std::printf("[ measure  ] stride search: %d features, %d matched, worst %.3f px\n", fs->count, out->count, worst);
    EXPECT_GE(out->count, fs->count * 7 / 10);
    EXPECT_LT(worst, 0.2);
}

// max_verified bounds the affine refinements and backward searches of a call: only the
// passing features with the best forward scores go on, and each of them ends as it does
// without the bound (the same pixels, bit for bit); the rest are counted as unverified.
TEST(TemplateMatcher, VerifiesOnlyTheBestForwardScoresUpToMaxVerified) {
    const auto scene = std::make_unique<Scene>();
    const auto fs = std::make_unique<FeatureSet>();
    const auto all = std::make_unique<MatchSet>();
    const auto capped = std::make_unique<MatchSet>();
    Modules m(detectorConfig(), matcherConfig());
    ASSERT_TRUE(m.detector.detect(scene->a.view(), *fs).isOk());
    MatchStats sa;
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, scene->prediction(), *all, &sa).isOk());
    const std::int32_t passed = sa.attempted - sa.no_region - sa.low_score;
    EXPECT_EQ(sa.unverified, 0);
    ASSERT_GE(all->count, 30);
    MatcherConfig mc = matcherConfig();
    mc.max_verified = all->count / 2;
    Modules mk(detectorConfig(), mc);
    MatchStats sk;
    vtm::test::NoHeapScope scope;
    ASSERT_TRUE(mk.matcher.match(scene->a.view(), scene->b.view(), *fs, scene->prediction(), *capped, &sk).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
    EXPECT_EQ(sk.attempted - sk.no_region - sk.low_score, passed);
    EXPECT_EQ(sk.unverified, passed - mc.max_verified);
    EXPECT_EQ(sk.not_refined + sk.not_mutual + sk.matched, mc.max_verified);  // the verification work
    EXPECT_EQ(sk.no_region + sk.low_score + sk.unverified + sk.not_refined + sk.not_mutual + sk.matched, sk.attempted);
    // Every capped match is the unbounded call's match of that feature, and no match the
    // bound left out has a better forward score than one it kept.
    std::vector<bool> kept(static_cast<std::size_t>(fs->count), false);
    float worst_kept = 2.0f;
    for (std::int32_t i = 0; i < capped->count; ++i) {
        const Match& c = capped->items[i];
        kept[static_cast<std::size_t>(c.feature_index)] = true;
        worst_kept = std::min(worst_kept, c.score);
        const Match* same = nullptr;
        for (std::int32_t j = 0; j < all->count; ++j) {
            if (all->items[j].feature_index == c.feature_index) {
                same = &all->items[j];
            }
        }
        ASSERT_NE(same, nullptr) << c.feature_index;
        EXPECT_EQ(same->pixel_b, c.pixel_b);
        EXPECT_EQ(same->score, c.score);
    }
    std::int32_t left_out = 0;
    for (std::int32_t j = 0; j < all->count; ++j) {
        if (!kept[static_cast<std::size_t>(all->items[j].feature_index)]) {
            ++left_out;
            EXPECT_LE(all->items[j].score, worst_kept) << all->items[j].feature_index;
        }
    }
    EXPECT_EQ(left_out, all->count - capped->count);
    EXPECT_LT(capped->count, all->count);
}

TEST(TemplateMatcher, DoesNotMatchOutsideThePredictedRegion) {
    const auto scene = std::make_unique<Scene>();
    Modules m(detectorConfig(), matcherConfig());
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    ASSERT_TRUE(m.detector.detect(scene->a.view(), *fs).isOk());
    MatchPrediction p = scene->prediction();
    p.range_min_m = 100.0;  // predicts a shift of 1.7 px at most; the truth (17.7 px) is
    p.range_max_m = 1000.0; // 12 px beyond the 3 px margin
    p.margin_px = 3.0;
    MatchStats stats;
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, p, *out, &stats).isOk());
    EXPECT_EQ(out->count, 0);
    EXPECT_EQ(stats.no_region + stats.low_score + stats.unverified + stats.not_refined + stats.not_mutual, stats.attempted);
    // A region entirely outside B (a 1000 px sideways move at 5..40 m): no region at all.
    p = scene->prediction();
    p.pair.b_from_a.t_m = Vec3(1000.0, 0.0, 0.0);
    ASSERT_TRUE(m.matcher.match(scene->a.view(), scene->b.view(), *fs, p, *out, &stats).isOk());
    EXPECT_EQ(stats.no_region, stats.attempted);
    EXPECT_EQ(out->count, 0);
}

// Repeated texture: A holds, at f1, a blend (0.7 / 0.3) of the 48x48 patch around f2 with
// other texture; in B, f1's true place shows unrelated texture. f1's forward search finds
// f2's image in B (NCC about 0.9 > min_score); from there, the search back into A finds f2
// (NCC 1), not f1: the mutual check rejects f1, and keeps f2.
TEST(TemplateMatcher, MutualCheckRejectsARepeatedTexture) {
    Scene scene;
    const Texture other(99U, kW / 2 + 100);
    const std::int32_t f1x = 60, f1y = 100, f2x = 110, f2y = 100, half = 24;
    for (std::int32_t dy = -half; dy < half; ++dy) {
        for (std::int32_t dx = -half; dx < half; ++dx) {
            const double copy = scene.texture.at(f2x + dx + kPad, f2y + dy + kPad);
            const double mix = other.at(f1x + dx + kPad, f1y + dy + kPad);
            scene.a.at(f1x + dx, f1y + dy) = test::toGrey(0.7 * copy + 0.3 * mix);
            // B at f1's true place: unrelated texture (kept within B's image).
            const auto bx = static_cast<std::int32_t>(f1x + dx + kShiftX), by = static_cast<std::int32_t>(f1y + dy + kShiftY);
            scene.b.at(bx, by) = test::toGrey(other.at(bx + 37.0, by + 11.0));
        }
    }
    const auto fs = std::make_unique<FeatureSet>();
    fs->items[0].pixel = Vec2(f1x, f1y);
    fs->items[1].pixel = Vec2(f2x, f2y);
    fs->count = 2;
    MatchPrediction p = scene.prediction();
    p.range_min_m = 2.5;  // shifts up to 69 px: f2's image in B lies in f1's region
    p.margin_px = 20.0;
    Modules m(detectorConfig(), matcherConfig());
    const auto out = std::make_unique<MatchSet>();
    MatchStats stats;
    ASSERT_TRUE(m.matcher.match(scene.a.view(), scene.b.view(), *fs, p, *out, &stats).isOk());
    EXPECT_EQ(stats.not_mutual, 1);
    ASSERT_EQ(out->count, 1);
    EXPECT_EQ(out->items[0].feature_index, 1);
    EXPECT_LT((out->items[0].pixel_b - Vec2(f2x + kShiftX, f2y + kShiftY)).norm(), 0.2);
    // Control: without an effective mutual check f1 is matched, to f2's place (wrong).
    MatcherConfig loose = matcherConfig();
    loose.mutual_tolerance_px = 1000.f;
    Modules m2(detectorConfig(), loose);
    ASSERT_TRUE(m2.matcher.match(scene.a.view(), scene.b.view(), *fs, p, *out, &stats).isOk());
    ASSERT_EQ(out->count, 2);
    EXPECT_EQ(out->items[0].feature_index, 0);
    EXPECT_LT((out->items[0].pixel_b - Vec2(f2x + kShiftX, f2y + kShiftY)).norm(), 1.0);
}

TEST(TemplateMatcher, BadInputsGiveTheDocumentedStatus) {
    const auto scene = std::make_unique<Scene>();
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    fs->count = 1;
    fs->items[0].pixel = Vec2(100.0, 100.0);
    TemplateMatcher uninit;
    EXPECT_EQ(uninit.match(scene->a.view(), scene->b.view(), *fs, scene->prediction(), *out).code(),
              StatusCode::kNotInitialized);
    Modules m(detectorConfig(), matcherConfig());
    auto run = [&](const MatchPrediction& p) {
        return m.matcher.match(scene->a.view(), scene->b.view(), *fs, p, *out);
    };
    MatchPrediction p = scene->prediction();
    p.pair.model_b = makePinhole(128, 128, 60.0);  // not image_b's size
    EXPECT_EQ(run(p).code(), StatusCode::kSizeMismatch);
    EXPECT_NE(std::strstr(run(p).reason(), "pair.model_b"), nullptr);
    p = scene->prediction();
    p.range_min_m = 0.0;
    EXPECT_NE(std::strstr(run(p).reason(), "range_min_m"), nullptr);
    p.range_min_m = 50.0;  // >= range_max_m
    EXPECT_NE(std::strstr(run(p).reason(), "range_max_m"), nullptr);
    p = scene->prediction();
    p.margin_px = -1.0;
    EXPECT_NE(std::strstr(run(p).reason(), "margin_px"), nullptr);
    p = scene->prediction();
    p.surface_normal_a = Vec3(0.0, 0.0, 10.0);
    EXPECT_NE(std::strstr(run(p).reason(), "surface_normal_a"), nullptr);
    EXPECT_EQ(m.matcher.match(ImageView<const std::uint8_t>(), scene->b.view(), *fs, scene->prediction(), *out).code(),
              StatusCode::kInvalidArgument);
    const std::vector<std::uint8_t> big(static_cast<std::size_t>((kW + 1) * kH));
    EXPECT_EQ(m.matcher.match(scene->a.view(), ImageView<const std::uint8_t>(big.data(), kW + 1, kH), *fs,
                              scene->prediction(), *out).code(),
              StatusCode::kSizeMismatch);
    const CameraModel small = makePinhole(128, 128, 60.0);
    p = scene->prediction();
    p.pair.model_a = small;
    EXPECT_EQ(run(p).code(), StatusCode::kSizeMismatch);
    fs->count = kMaxFeatures + 1;
    EXPECT_EQ(run(scene->prediction()).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(out->count, 0);
    MatcherConfig c;
    c.template_window = 10;
    EXPECT_NE(std::strstr(c.validate().reason(), "template_window"), nullptr);
    c = MatcherConfig{};
    c.pyramid_levels = 5;
    EXPECT_NE(std::strstr(c.validate().reason(), "pyramid_levels"), nullptr);
    for (const std::int32_t bad : {0, kMaxFeatures + 1}) {
        c = MatcherConfig{};
        c.max_verified = bad;
        EXPECT_NE(std::strstr(c.validate().reason(), "max_verified"), nullptr) << bad;
    }
    std::byte tiny_pool[32];
    Arena tiny(tiny_pool, sizeof tiny_pool);
    TemplateMatcher m3;
    EXPECT_EQ(m3.init(MatcherConfig{}, tiny).code(), StatusCode::kOutOfMemory);
}

}  // namespace
}  // namespace vtm::features
