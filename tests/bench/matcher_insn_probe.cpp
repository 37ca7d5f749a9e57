// Instruction-count probe of the features template matcher (vtm::features::TemplateMatcher,
// the bulk of the pair refinement's cost), built for every target. tools/qemu/
// count_matcher.sh runs it under qemu-user with the counting plugin and differences two
// repeat counts so that only match() remains.
//
//   vtm_matcher_insn_probe REPEAT
//
// A 512 x 448 pair of the features tests' smooth random texture, image B shifted by
// (17.3, 4.0) px: image A's Förstner features (8 x 7 cells, 2 per cell), each searched along
// the image of its ray over ranges 2..200 m with a 40 px margin (long, wide regions as in
// the rover's request), both warp hypotheses (a tilted plane normal), mutual check and
// affine refinement on: the default MatcherConfig otherwise. match() runs REPEAT times.
// Prints the attempted and matched counts and a hash of the matched positions' bits.
// Test code: heap for the images.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "test_images.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/features/features.hpp"

namespace {

using namespace vtm;
using namespace vtm::features;

constexpr std::int32_t kW = 512, kH = 448;
constexpr double kShiftX = 17.3, kShiftY = 4.0, kPlaneZ = 10.0, kPad = 80.0;

}  // namespace

int main(int argc, char** argv) {
    char* end = nullptr;
    const long repeat = argc == 2 ? std::strtol(argv[1], &end, 10) : -1;
    if (argc != 2 || end == argv[1] || *end != '\0' || repeat < 0 || repeat > 100) {
        std::fprintf(stderr, "usage: %s REPEAT (0..100)\n", argv[0]);
        return 2;
    }
    const test::Texture texture(21U, kW / 2 + 100, 0);
    const test::Image a = test::renderTexture(texture, kW, kH, 0.0, 0.0, kPad);
    const test::Image b = test::renderTexture(texture, kW, kH, kShiftX, kShiftY, kPad);
    const CameraModel cam = makePinhole(kW, kH, 60.0);
    MatchPrediction p;
    p.pair.model_a = cam;
    p.pair.model_b = cam;
    p.pair.b_from_a.t_m = Vec3(kShiftX * kPlaneZ / cam.fx_px, kShiftY * kPlaneZ / cam.fy_px, 0.0);
    p.range_min_m = 2.0;
    p.range_max_m = 200.0;
    p.margin_px = 40.0;
    p.surface_normal_a = Vec3(0.0, -0.3, -1.0).normalized();  // a terrain normal: both warp hypotheses
    DetectorConfig dc;
    dc.max_width = kW;
    dc.max_height = kH;
    dc.grid_cols = 8;
    dc.grid_rows = 7;
    dc.per_cell = 2;
    dc.border_px = 24;
    MatcherConfig mc;
    mc.max_width = kW;
    mc.max_height = kH;
    std::vector<std::byte> pool(ForstnerDetector::workspaceBytes(dc) + TemplateMatcher::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    static ForstnerDetector detector;
    static TemplateMatcher matcher;
    if (!detector.init(dc, arena).isOk() || !matcher.init(mc, arena).isOk()) {
        std::fprintf(stderr, "matcher_insn_probe: init failed\n");
        return 1;
    }
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    if (!detector.detect(a.view(), *fs).isOk()) {
        std::fprintf(stderr, "matcher_insn_probe: detect failed\n");
        return 1;
    }
    MatchStats stats;
    for (long i = 0; i < repeat; ++i) {
        const Status st = matcher.match(a.view(), b.view(), *fs, p, *out, &stats);
        if (!st.isOk()) {
            std::fprintf(stderr, "matcher_insn_probe: match: %s\n", st.reason());
            return 1;
        }
    }
    // FNV-1a over the matched positions' bits, each value's bytes little-endian first (the
    // same hash on big- and little-endian targets).
    std::uint64_t hash = 1469598103934665603ULL;
    for (std::int32_t i = 0; i < out->count; ++i) {
        for (const double v : {out->items[i].pixel_b.x(), out->items[i].pixel_b.y()}) {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &v, sizeof bits);
            for (int k = 0; k < 8; ++k) {
                hash = (hash ^ ((bits >> (8 * k)) & 0xFFU)) * 1099511628211ULL;
            }
        }
    }
    std::printf("features %d attempted %d matched %d repeat %ld hash %016llx\n", fs->count, stats.attempted,
                out->count, repeat, static_cast<unsigned long long>(hash));
    return 0;
}
