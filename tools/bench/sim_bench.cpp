// vtm_bench_sim: render speed of the simulated camera (sim/render), one thread.
//
//   SimRender/navcam1024/...   1024 x 1024 pinhole, 45 deg horizontal field of view, on a
//                              Navcam-like mast 1.9 m above the default Mars world,
//                              looking 25 deg down (about 10 % sky), 8-bit, noise on:
//       plain        image only, no shadows
//       shadows      image with cast shadows (one more ray per sunlit pixel)
//       truth        shadows + every ground-truth view (range, depth, point, normal)
//   SimRender/cahvor1024/shadows  the same view through a CAHVOR model (iterative
//                              back-projection)
//   SimRender/disparity1024    rectifiedDisparity of a 0.42 m pair (with visibility)
//
// Counter "Mpx/s" = pixels per call / CPU time / 1e6. The terrain (about 100 MB) is built
// once, outside the timing. It reports; it never fails on time (docs/benchmarks.md).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"

namespace {

constexpr std::int32_t kSize = 1024;

const vtm::sim::Terrain* world() {
    static std::vector<std::byte> pool;
    static vtm::sim::Terrain terrain;
    static bool tried = false;
    if (!tried) {
        tried = true;
        const vtm::sim::TerrainParams params = vtm::sim::defaultMarsTerrainParams();
        pool.resize(vtm::sim::Terrain::storageBytes(params));
        vtm::Arena arena(pool.data(), pool.size());
        if (!terrain.build(params, arena).isOk()) {
            return nullptr;
        }
    }
    return terrain.built() ? &terrain : nullptr;
}

vtm::RigidPose mastPose(const vtm::sim::Terrain& t) {
    const double ground = t.elevationAt(0.0, 0.0);
    const double down = 25.0 * 3.14159265358979323846 / 180.0;
    const vtm::Vec3 eye(0.0, 0.0, -(ground + 1.9));
    return vtm::sim::poseLookingAt(eye, eye + vtm::Vec3(std::cos(down), 0.0, std::sin(down)));
}

vtm::CameraModel cahvorNavcam() {
    vtm::CameraModel m = vtm::cahvFromPinhole(vtm::makePinhole(kSize, kSize, 45.0));
    m.kind = vtm::CameraModelKind::kCahvor;
    m.o[2] = 1.0;
    m.r[1] = -0.05;
    return m;
}

struct Buffers {
    std::vector<std::uint8_t> image = std::vector<std::uint8_t>(kSize * kSize);
    std::vector<float> range = std::vector<float>(kSize * kSize);
    std::vector<float> depth = std::vector<float>(kSize * kSize);
    std::vector<float> point = std::vector<float>(3 * kSize * kSize);
    std::vector<float> normal = std::vector<float>(3 * kSize * kSize);
};

void setRate(benchmark::State& state) {
    state.counters["Mpx/s"] = benchmark::Counter(static_cast<double>(kSize) * kSize / 1e6 *
                                                     static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}

void SimRender(benchmark::State& state, bool cahvor, bool shadows, bool truth) {
    const vtm::sim::Terrain* t = world();
    if (t == nullptr) {
        state.SkipWithError("terrain build failed");
        return;
    }
    vtm::sim::FrameRequest r;
    r.terrain = t;
    r.model = cahvor ? cahvorNavcam() : vtm::makePinhole(kSize, kSize, 45.0);
    r.pose = mastPose(*t);
    r.lighting.shadows = shadows;
    static Buffers b;
    vtm::sim::FrameOutput out;
    out.image8 = vtm::ImageView<std::uint8_t>(b.image.data(), kSize, kSize);
    if (truth) {
        out.truth.range_m = vtm::ImageView<float>(b.range.data(), kSize, kSize);
        out.truth.depth_m = vtm::ImageView<float>(b.depth.data(), kSize, kSize);
        out.truth.point_site_m = vtm::ImageView<float>(b.point.data(), 3 * kSize, kSize);
        out.truth.normal_site = vtm::ImageView<float>(b.normal.data(), 3 * kSize, kSize);
    }
    vtm::sim::RenderStats stats;
    for (auto _ : state) {
        if (!vtm::sim::renderFrame(r, out, &stats).isOk()) {
            state.SkipWithError("renderFrame failed");
            return;
        }
        r.frame_index += 1U;
        benchmark::DoNotOptimize(b.image.data());
    }
    setRate(state);
    state.counters["sky_fraction"] = static_cast<double>(stats.sky_pixels) / (static_cast<double>(kSize) * kSize);
    state.counters["shadow_fraction"] =
        static_cast<double>(stats.shadowed_pixels) / (static_cast<double>(kSize) * kSize);
}

void SimDisparity(benchmark::State& state) {
    const vtm::sim::Terrain* t = world();
    if (t == nullptr) {
        state.SkipWithError("terrain build failed");
        return;
    }
    vtm::sim::StereoTruthRequest r;
    r.terrain = t;
    r.left_model = vtm::makePinhole(kSize, kSize, 45.0);
    r.left_pose = mastPose(*t);
    r.baseline_m = 0.42;
    static Buffers b;
    static std::vector<std::uint8_t> code(kSize * kSize);
    const vtm::sim::StereoTruthOutput out{vtm::ImageView<float>(b.range.data(), kSize, kSize),
                                          vtm::ImageView<std::uint8_t>(code.data(), kSize, kSize),
                                          vtm::ImageView<float>()};
    for (auto _ : state) {
        if (!vtm::sim::rectifiedDisparity(r, out).isOk()) {
            state.SkipWithError("rectifiedDisparity failed");
            return;
        }
        benchmark::DoNotOptimize(b.range.data());
    }
    setRate(state);
}

BENCHMARK_CAPTURE(SimRender, plain, false, false, false)->Name("SimRender/navcam1024/plain")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SimRender, shadows, false, true, false)
    ->Name("SimRender/navcam1024/shadows")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SimRender, truth, false, true, true)->Name("SimRender/navcam1024/truth")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SimRender, cahvor, true, true, false)
    ->Name("SimRender/cahvor1024/shadows")
    ->Unit(benchmark::kMillisecond);
BENCHMARK(SimDisparity)->Name("SimRender/disparity1024")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
