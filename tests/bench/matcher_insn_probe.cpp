// Instruction-count probe of the features template matcher (vtm::features::TemplateMatcher,
// the bulk of the pair refinement's cost), built for every target. tools/qemu/
// count_matcher.sh runs it under qemu-user with the counting plugin and differences two
// repeat counts so that only match() remains.
//
//   vtm_matcher_insn_probe REPEAT [CONTENT [OPERATION]]
//
// OPERATION "match" (the default) repeats match(); "detect" repeats the Förstner detection
// of image A instead (its cost by content) and hashes the features' positions.
// A 512 x 448 pair of the features tests' smooth random texture (CONTENT "texture", the
// default; or an adversarial one of probe_content.hpp, here drawn as continuous functions:
// "noise" a new grey level at every pixel, "saturated" the texture's contrast about 128
// times 4, clipped), image B shifted by
// (17.3, 4.0) px (bilinear between the pixels of the lattice contents): image A's Förstner features (8 x 7 cells, 2 per cell), each searched along
// the image of its ray over ranges 2..200 m with a 40 px margin (long, wide regions as in
// the rover's request), both warp hypotheses (a tilted plane normal), mutual check and
// affine refinement on: the default MatcherConfig otherwise. match() runs REPEAT times.
// Prints the attempted and matched counts and a hash of the matched positions' bits.
// Test code: heap for the images.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "probe_content.hpp"
#include "test_images.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/features/features.hpp"

namespace {

using namespace vtm;
using namespace vtm::features;

constexpr std::int32_t kW = 512, kH = 448;
constexpr double kShiftX = 17.3, kShiftY = 4.0, kPlaneZ = 10.0, kPad = 80.0;

// A content on a lattice of one value per pixel, read bilinearly: noise and allbins.
double latticeAt(const std::string& kind, double u, double v) {
    const auto value = [&](std::int64_t i, std::int64_t j) {
        if (kind == "noise") {
            std::uint64_t z = static_cast<std::uint64_t>(i * 73856093LL ^ j * 19349663LL) + 0x9E3779B97F4A7C15ULL;
            z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
            z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
            return static_cast<double>((z ^ (z >> 31U)) & 0xFFU);
        }
        return static_cast<double>((i + j * kW) & 0xFF);  // allbins
    };
    const double fu = std::floor(u), fv = std::floor(v);
    const auto i = static_cast<std::int64_t>(fu);
    const auto j = static_cast<std::int64_t>(fv);
    const double a = u - fu, b = v - fv;
    return (value(i, j) * (1 - a) + value(i + 1, j) * a) * (1 - b) + (value(i, j + 1) * (1 - a) + value(i + 1, j + 1) * a) * b;
}

// Image whose pixel (x, y) is the content at (x - shift_x + kPad, y - shift_y + kPad).
test::Image render(const std::string& kind, const test::Texture& t, double shift_x, double shift_y) {
    if (kind == "texture") {
        return test::renderTexture(t, kW, kH, shift_x, shift_y, kPad);
    }
    test::Image img(kW, kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            const double u = x - shift_x + kPad, v = y - shift_y + kPad;
            double g = 128.0;
            if (kind == "periodic") {
                g = static_cast<std::int64_t>(std::floor(u / 2.0)) % 2 == 0 ? 60.0 : 190.0;
            } else if (kind == "saturated") {
                g = 128.0 + 4.0 * (t.at(u, v) - 128.0);
            } else if (kind == "noise" || kind == "allbins") {
                g = latticeAt(kind, u, v);
            }
            img.at(x, y) = test::toGrey(g);
        }
    }
    return img;
}

}  // namespace

int main(int argc, char** argv) {
    char* end = nullptr;
    const long repeat = argc >= 2 ? std::strtol(argv[1], &end, 10) : -1;
    const std::string kind = argc >= 3 ? argv[2] : "texture";
    const std::string operation = argc == 4 ? argv[3] : "match";
    if (argc < 2 || argc > 4 || end == argv[1] || *end != '\0' || repeat < 0 || repeat > 100 ||
        (operation != "match" && operation != "detect")) {
        std::fprintf(stderr, "usage: %s REPEAT (0..100) [%s [match|detect]]\n", argv[0], vtm::bench::kContents);
        return 2;
    }
    if (!vtm::bench::knownContent(kind, "matcher_insn_probe")) {
        return 2;
    }
    const test::Texture texture(21U, kW / 2 + 100, 0);
    const test::Image a = render(kind, texture, 0.0, 0.0);
    const test::Image b = render(kind, texture, kShiftX, kShiftY);
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
    const long detections = operation == "detect" ? repeat : 0;
    for (long i = 0; i < detections; ++i) {
        if (!detector.detect(a.view(), *fs).isOk()) {
            std::fprintf(stderr, "matcher_insn_probe: detect failed\n");
            return 1;
        }
    }
    const long matches = operation == "match" ? repeat : 0;
    for (long i = 0; i < matches; ++i) {
        const Status st = matcher.match(a.view(), b.view(), *fs, p, *out, &stats);
        if (!st.isOk()) {
            std::fprintf(stderr, "matcher_insn_probe: match: %s\n", st.reason());
            return 1;
        }
    }
    // FNV-1a over the matched (detect: the features') positions' bits, each value's bytes
    // little-endian first (the same hash on big- and little-endian targets).
    std::uint64_t hash = 1469598103934665603ULL;
    const bool detect = operation == "detect";
    for (std::int32_t i = 0; i < (detect ? fs->count : out->count); ++i) {
        const Vec2 at = detect ? fs->items[i].pixel : out->items[i].pixel_b;
        for (const double v : {at.x(), at.y()}) {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &v, sizeof bits);
            for (int k = 0; k < 8; ++k) {
                hash = (hash ^ ((bits >> (8 * k)) & 0xFFU)) * 1099511628211ULL;
            }
        }
    }
    std::printf("pixels %d features %d attempted %d matched %d repeat %ld hash %016llx\n", kW * kH, fs->count,
                stats.attempted, out->count, repeat, static_cast<unsigned long long>(hash));
    return 0;
}
