// Host timing of ForstnerDetector::detect and TemplateMatcher::match on a 1024x1024 pair
// (B = A's texture shifted by (17.3, 4.0) px), 512 features. Reports, never fails:
//   build/<dir>/tests/features/vtm_features_timing
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "test_images.hpp"
#include "vtm/features/features.hpp"

int main() {
    using namespace vtm;
    using namespace vtm::features;
    constexpr std::int32_t kSize = 1024;
    const test::Texture texture(5U, kSize / 2 + 100, 0);
    const test::Image a = test::renderTexture(texture, kSize, kSize, 0.0, 0.0, 80.0);
    const test::Image b = test::renderTexture(texture, kSize, kSize, 17.3, 4.0, 80.0);
    const CameraModel cam = makePinhole(kSize, kSize, 60.0);
    DetectorConfig dc;   // defaults: 1024 x 1024, window 5, 16 x 16 grid, 2 per cell, 512 max
    MatcherConfig mc;    // defaults: 11 px template, 2 pyramid levels
    std::vector<std::byte> pool(ForstnerDetector::workspaceBytes(dc) + TemplateMatcher::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    ForstnerDetector detector;
    TemplateMatcher matcher;
    if (!detector.init(dc, arena).isOk() || !matcher.init(mc, arena).isOk()) {
        return 1;
    }
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    MatchPrediction p;
    p.pair.model_a = cam;
    p.pair.model_b = cam;
    p.pair.b_from_a.t_m = Vec3(17.3 * 10.0 / cam.fx_px, 4.0 * 10.0 / cam.fy_px, 0.0);
    p.range_min_m = 5.0;
    p.range_max_m = 40.0;
    p.margin_px = 40.0;
    const auto t0 = std::chrono::steady_clock::now();
    const Status s1 = detector.detect(a.view(), *fs);
    const auto t1 = std::chrono::steady_clock::now();
    MatchStats st;
    const Status s2 = matcher.match(a.view(), b.view(), *fs, p, *out, &st);
    const auto t2 = std::chrono::steady_clock::now();
    if (!s1.isOk() || !s2.isOk()) {
        return 1;
    }
    const double detect_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    const double match_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    std::printf("workspace: detector %zu B, matcher %zu B\n", ForstnerDetector::workspaceBytes(dc),
                TemplateMatcher::workspaceBytes(mc));
    std::printf("detect: %d features in %.1f ms\n", fs->count, detect_ms);
    std::printf("match:  %d matched (no_region %d, low_score %d, not_refined %d, not_mutual %d) in %.1f ms (margin %.0f px, ranges %.0f..%.0f m)\n",
                out->count, st.no_region, st.low_score, st.not_refined, st.not_mutual, match_ms, p.margin_px, p.range_min_m,
                p.range_max_m);
    return 0;
}
