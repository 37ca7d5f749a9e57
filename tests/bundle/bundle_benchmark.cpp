// Host time of one adjustment of a 40-station (80-image) panorama with about 2,000 tie points
// (docs/bundle.md "Cost"). Reports, does not judge: time is for benchmarks, not for tests.
//   build/host-release/tests/bundle/vtm_bundle_benchmark [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <memory>
#include <vector>

#include "panorama_network.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"

int main(int argc, char** argv) {
    using namespace vtm;
    const int repeats = argc > 1 ? std::atoi(argv[1]) : 5;
    bundle::test::NetworkSpec spec;
    spec.azimuths = 20;
    spec.tiers = 2;
    spec.hfov_deg = 45.0;
    spec.candidate_points = 2000;
    spec.outlier_fraction = 0.02;
    spec.seed = 3U;
    const bundle::test::Network net = bundle::test::makeNetwork(spec);
    bundle::BundleConfig c;
    c.max_stations = 40;
    c.max_points = 2048;
    c.max_observations = 16384;
    const std::size_t bytes = bundle::BundleAdjuster::workspaceBytes(c);
    std::unique_ptr<std::byte[]> pool(new std::byte[bytes]);
    Arena arena(pool.get(), bytes);
    bundle::BundleAdjuster adjuster;
    if (!adjuster.init(c, arena).isOk()) return 1;
    std::vector<double> ms;
    std::vector<double> cpu;
    bundle::BundleResult r;
    for (int i = 0; i < repeats; ++i) {
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        const Status s = adjuster.adjust(Span<const NetworkStation>(net.approx.data(), net.approx.size()),
                                         Span<const TieObservation>(net.observations.data(), net.observations.size()),
                                         static_cast<std::uint32_t>(net.points_m.size()), r);
        const auto t1 = std::chrono::steady_clock::now();
        cpu.push_back(1000.0 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        if (!s.isOk()) {
            std::printf("refused: %s (%lld)\n", s.reason(), static_cast<long long>(s.detail()));
            return 1;
        }
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    std::sort(cpu.begin(), cpu.end());
    std::printf("stations %d (images %d), points %d adjusted %d, observations %d, outliers %d, iterations %d, rounds %d, "
                "rms %.3f -> %.3f px\nworkspace %zu bytes; host wall time median %.1f ms of %d (min %.1f, max %.1f), process CPU median %.1f ms\n",
                r.stations, 2 * r.stations, r.points, r.points_adjusted, r.observations, r.outliers, r.iterations, r.rounds,
                r.rms_before_px, r.rms_after_px, bytes, ms[ms.size() / 2], repeats, ms.front(), ms.back(), cpu[cpu.size() / 2]);
    return 0;
}
