// vtm_bench_descent: time of the descent plane sweep (fsw/descent) on a 1024 x 1024 nadir
// pair with 64 planes (and 32, for the marginal cost per plane), one thread. Synthetic
// pair: the run time does not depend on the image content (every plane is scored for
// every pixel). Reports; never fails on time. Counters: ns per plane, ns per pixel*plane.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/core/random.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace {

constexpr int kSize = 1024;

void BM_DescentSweep(benchmark::State& state) {
    const int planes = static_cast<int>(state.range(0));
    vtm::descent::PairGeometry g;
    g.camera = vtm::makePinhole(kSize, kSize, 45.0);
    g.site_from_cam1.t_m = vtm::Vec3(0.0, 0.0, -2000.0);
    g.site_from_cam2.t_m = vtm::Vec3(0.0, 20.0, -1040.0);
    std::vector<std::uint16_t> i1(static_cast<std::size_t>(kSize) * kSize), i2(i1.size());
    vtm::Random rng(42u);
    for (std::size_t i = 0; i < i1.size(); ++i) {
        i1[i] = static_cast<std::uint16_t>(rng.nextU32() >> 20);
        i2[i] = static_cast<std::uint16_t>(rng.nextU32() >> 20);
    }
    vtm::descent::Config c;
    c.max_width = kSize;
    c.max_height = kSize;
    c.planes = planes;
    c.depth_min_m = 1800.0;
    c.depth_max_m = 2200.0;
    std::vector<std::byte> pool(vtm::descent::PlaneSweep::workspaceBytes(c));
    vtm::Arena arena(pool.data(), pool.size());
    static vtm::descent::PlaneSweep sweep;
    if (!sweep.init(c, arena).isOk()) {
        state.SkipWithError("init failed");
        return;
    }
    std::vector<float> depth(i1.size());
    const vtm::descent::SweepOutput out{vtm::ImageView<float>(depth.data(), kSize, kSize), {}, {}};
    for (auto _ : state) {
        const vtm::Status s = sweep.compute(vtm::ImageView<const std::uint16_t>(i1.data(), kSize, kSize),
                                            vtm::ImageView<const std::uint16_t>(i2.data(), kSize, kSize), g, out);
        benchmark::DoNotOptimize(s);
        benchmark::DoNotOptimize(depth.data());
    }
    state.counters["ns_per_plane"] = benchmark::Counter(
        static_cast<double>(planes), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["ns_per_pixel_plane"] =
        benchmark::Counter(static_cast<double>(planes) * kSize * kSize,
                           benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DescentSweep)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
