// Instruction-count probe of the ML dense stereo (vtm::stereo::MlStereo), built for
// every target. tools/qemu/count_stereo.sh runs it under qemu-user with the
// instruction-counting plugin (tools/qemu/insn_count.c) and differences the counts so
// that everything but the disparity search cancels.
//
//   vtm_stereo_insn_probe WIDTH HEIGHT DISPARITIES REPEAT [CONTENT]
//
// Builds a synthetic rectified pair (deterministic texture, a background plane at
// disparity D/4 and a raised square at D/2, D = DISPARITIES; CONTENT "texture", the
// default, or an adversarial one of probe_content.hpp, 8-bit), initialises MlStereo with
// the default Config except d_min = 0, d_max = D - 1 and the image size as capacity,
// then calls compute() REPEAT times on the same pair. The instruction count of one
// compute() is count(REPEAT = 2) - count(REPEAT = 1): pair synthesis, init and process
// start-up cancel. Prints the valid-pixel count and a hash of the disparity image
// (identical on every target: a cheap cross-target determinism check).
// Test code: uses the heap for its images and workspace.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "probe_content.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace {

int parseArg(const char* s, int lo, int hi, const char* what) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) {
        std::fprintf(stderr, "stereo_insn_probe: %s must be %d..%d\n", what, lo, hi);
        std::exit(2);
    }
    return static_cast<int>(v);
}

// Right image: random grey levels smoothed by a 3x3 box (texture at the scale of a few
// pixels), or the CONTENT made of them. Left image: the right one seen at disparity D/4,
// with a square in the middle third at D/2; uncovered pixels get fresh noise.
void makePair(int w, int h, int nd, const std::string& kind, std::vector<std::uint8_t>& left,
              std::vector<std::uint8_t>& right) {
    vtm::Random rng(0x5EEDu);
    std::vector<std::uint8_t> noise(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (auto& v : noise) {
        v = static_cast<std::uint8_t>(rng.nextU32() >> 24);
    }
    right.assign(noise.size(), 0);
    left.assign(noise.size(), 0);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            int s = 0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int yy = y + dy < 0 ? 0 : (y + dy >= h ? h - 1 : y + dy);
                    const int xx = x + dx < 0 ? 0 : (x + dx >= w ? w - 1 : x + dx);
                    s += noise[static_cast<std::size_t>(yy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(xx)];
                }
            }
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
            right[i] = static_cast<std::uint8_t>(vtm::bench::contentValue(kind, {255, 128, 60, 190}, x, y, w, s / 9, noise[i]));
        }
    }
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const bool inSquare = x >= w / 3 && x < 2 * w / 3 && y >= h / 3 && y < 2 * h / 3;
            const int d = inSquare ? nd / 2 : nd / 4;
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
            left[i] = x - d >= 0 ? right[i - static_cast<std::size_t>(d)] : noise[i];
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 5 && argc != 6) {
        std::fprintf(stderr, "usage: %s WIDTH HEIGHT DISPARITIES REPEAT [%s]\n", argv[0], vtm::bench::kContents);
        return 2;
    }
    const std::string kind = argc == 6 ? argv[5] : "texture";
    if (!vtm::bench::knownContent(kind, "stereo_insn_probe")) {
        return 2;
    }
    const int w = parseArg(argv[1], 16, 4096, "WIDTH");
    const int h = parseArg(argv[2], 16, 4096, "HEIGHT");
    const int nd = parseArg(argv[3], 2, 1024, "DISPARITIES");
    const int repeat = parseArg(argv[4], 0, 100, "REPEAT");

    std::vector<std::uint8_t> left, right;
    makePair(w, h, nd, kind, left, right);

    vtm::stereo::Config config;
    config.max_width = w;
    config.max_height = h;
    config.d_min = 0;
    config.d_max = nd - 1;
    const std::size_t bytes = vtm::stereo::MlStereo::workspaceBytes(config);
    if (bytes == 0U) {
        std::fprintf(stderr, "stereo_insn_probe: invalid config\n");
        return 1;
    }
    std::vector<std::byte> pool(bytes);
    vtm::Arena arena(pool.data(), pool.size());
    static vtm::stereo::MlStereo stereo;
    const vtm::Status st = stereo.init(config, arena);
    if (!st.isOk()) {
        std::fprintf(stderr, "stereo_insn_probe: init: %s (%lld)\n", st.reason(), static_cast<long long>(st.detail()));
        return 1;
    }
    arena.freeze();

    std::vector<std::int16_t> disparity(left.size());
    const vtm::ImageView<const std::uint8_t> lv(left.data(), w, h);
    const vtm::ImageView<const std::uint8_t> rv(right.data(), w, h);
    vtm::stereo::DisparityOutput out;
    out.disparity_px16 = vtm::ImageView<std::int16_t>(disparity.data(), w, h);
    vtm::stereo::StereoStats stats;
    for (int i = 0; i < repeat; ++i) {
        const vtm::Status s = stereo.compute(lv, rv, out, &stats);
        if (!s.isOk()) {
            std::fprintf(stderr, "stereo_insn_probe: compute: %s\n", s.reason());
            return 1;
        }
    }
    std::uint64_t hash = 1469598103934665603ULL;  // FNV-1a over the disparities
    for (const std::int16_t v : disparity) {
        hash = (hash ^ static_cast<std::uint16_t>(v)) * 1099511628211ULL;
    }
    std::printf("size %dx%d disparities %d repeat %d valid %d hash %016llx\n", w, h, nd, repeat,
                static_cast<int>(stats.valid_pixels), static_cast<unsigned long long>(hash));
    return 0;
}
