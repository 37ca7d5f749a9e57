// Instruction-count probe of the descent plane sweep (vtm::descent::PlaneSweep), built
// for every target. tools/qemu/count_descent.sh runs it under qemu-user with the
// instruction-counting plugin and differences the counts so that only compute() remains.
//
//   vtm_descent_insn_probe SIZE PLANES REPEAT [CONTENT]
//
// Synthetic nadir pair: image 1 a deterministic texture (CONTENT "texture", the default:
// 3x3-smoothed xoshiro noise, 12-bit; or an adversarial one of probe_content.hpp) seen
// from 2000 m; image 2 the same ground plane (depth 2000 m) seen from
// 1040 m, 20 m to the east (the descent scenario's first step); 64-plane-style sweep over
// 1800..2200 m with the default Config otherwise. compute() runs REPEAT times; one
// compute() = count(REPEAT = 2) - count(REPEAT = 1). Prints the valid-pixel count and a
// hash of the depth bits (identical on every target). Test code: heap for the images.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "probe_content.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/random.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace {

int parseArg(const char* s, int lo, int hi, const char* what) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) {
        std::fprintf(stderr, "descent_insn_probe: %s must be %d..%d\n", what, lo, hi);
        std::exit(2);
    }
    return static_cast<int>(v);
}

// Image 1: smoothed noise. Image 2: image 1's ground plane seen by camera 2 (bilinear,
// in double: exact enough for a cost probe, and deterministic with + - * / only).
void makePair(int n, const vtm::descent::PairGeometry& g, const char* content, std::vector<std::uint16_t>& i1,
              std::vector<std::uint16_t>& i2) {
    vtm::Random rng(0xDE5CE17u);
    std::vector<std::uint16_t> noise(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    for (auto& v : noise) {
        v = static_cast<std::uint16_t>(rng.nextU32() >> 20);
    }
    i1.assign(noise.size(), 0);
    i2.assign(noise.size(), 0);
    auto at = [&](const std::vector<std::uint16_t>& img, int x, int y) {
        x = x < 0 ? 0 : (x >= n ? n - 1 : x);
        y = y < 0 ? 0 : (y >= n ? n - 1 : y);
        return static_cast<int>(img[static_cast<std::size_t>(y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(x)]);
    };
    const std::string kind = content;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            int s = 0;
            for (int k = 0; k < 9; ++k) {
                s += at(noise, x + k % 3 - 1, y + k / 3 - 1);
            }
            const std::size_t i = static_cast<std::size_t>(y * n + x);
            i1[i] = static_cast<std::uint16_t>(
                vtm::bench::contentValue(kind, {4095, 2048, 1000, 3000}, x, y, n, s / 9, noise[i]));
        }
    }
    // Camera 2 pixel -> ground point at depth 2000 m below camera 1 -> camera 1 pixel.
    const double f = g.camera.fx_px, c = g.camera.cx_px;
    const vtm::Vec3 d = g.site_from_cam2.t_m - g.site_from_cam1.t_m;  // R = I for both
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const double z2 = 2000.0 - d.z();
            const double u = ((x - c) / f * z2 + d.x()) / 2000.0 * f + c;
            const double v = ((y - c) / f * z2 + d.y()) / 2000.0 * f + c;
            const int ix = static_cast<int>(std::floor(u)), iy = static_cast<int>(std::floor(v));
            const double fx = u - ix, fy = v - iy;
            const double val = (1 - fy) * ((1 - fx) * at(i1, ix, iy) + fx * at(i1, ix + 1, iy)) +
                               fy * ((1 - fx) * at(i1, ix, iy + 1) + fx * at(i1, ix + 1, iy + 1));
            i2[static_cast<std::size_t>(y * n + x)] = static_cast<std::uint16_t>(val + 0.5);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4 && argc != 5) {
        std::fprintf(stderr, "usage: %s SIZE PLANES REPEAT [%s]\n", argv[0], vtm::bench::kContents);
        return 2;
    }
    const char* content = argc == 5 ? argv[4] : "texture";
    if (!vtm::bench::knownContent(content, "descent_insn_probe")) {
        return 2;
    }
    const int n = parseArg(argv[1], 32, 4096, "SIZE");
    const int planes = parseArg(argv[2], 3, 256, "PLANES");
    const int repeat = parseArg(argv[3], 0, 100, "REPEAT");
    vtm::descent::PairGeometry g;
    g.camera = vtm::makePinhole(static_cast<std::uint16_t>(n), static_cast<std::uint16_t>(n), 45.0);
    g.site_from_cam1.t_m = vtm::Vec3(0.0, 0.0, -2000.0);
    g.site_from_cam2.t_m = vtm::Vec3(0.0, 20.0, -1040.0);
    std::vector<std::uint16_t> i1, i2;
    makePair(n, g, content, i1, i2);
    vtm::descent::Config config;
    config.max_width = n;
    config.max_height = n;
    config.planes = planes;
    config.depth_min_m = 1800.0;
    config.depth_max_m = 2200.0;
    std::vector<std::byte> pool(vtm::descent::PlaneSweep::workspaceBytes(config));
    vtm::Arena arena(pool.data(), pool.size());
    static vtm::descent::PlaneSweep sweep;
    const vtm::Status st = sweep.init(config, arena);
    if (!st.isOk()) {
        std::fprintf(stderr, "descent_insn_probe: init: %s\n", st.reason());
        return 1;
    }
    std::vector<float> depth(i1.size());
    const vtm::descent::SweepOutput out{vtm::ImageView<float>(depth.data(), n, n), {}, {}};
    vtm::descent::SweepStats stats;
    for (int i = 0; i < repeat; ++i) {
        const vtm::Status s = sweep.compute(vtm::ImageView<const std::uint16_t>(i1.data(), n, n),
                                            vtm::ImageView<const std::uint16_t>(i2.data(), n, n), g, out, &stats);
        if (!s.isOk()) {
            std::fprintf(stderr, "descent_insn_probe: compute: %s\n", s.reason());
            return 1;
        }
    }
    std::uint64_t hash = 1469598103934665603ULL;  // FNV-1a over the depth bits
    for (const float v : depth) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &v, sizeof bits);
        hash = (hash ^ bits) * 1099511628211ULL;
    }
    std::printf("size %dx%d planes %d repeat %d valid %d hash %016llx\n", n, n, planes, repeat,
                static_cast<int>(stats.valid_pixels), static_cast<unsigned long long>(hash));
    return 0;
}
