// Cost probe of the panorama tie points (vtm::tiepoints::TiePointExtractor, docs/tiepoints.md
// "Cost"), built wherever the tie points and the simulator's renderer are:
//
//   vtm_tiepoints_probe REPEAT
//
// Renders the tie-point tests' panorama once (tests/tiepoints/scene_fixture: three stations,
// 256 x 256, the tests' configuration) and runs the extraction REPEAT times. One run's host
// instructions = (count(REPEAT = 3) - count(REPEAT = 1)) / 2, counted by
// `perf stat -e instructions:u` (or valgrind); the probe prints the funnel, a hash of the
// observations (the same on every target and for every REPEAT) and the host CPU time per run
// (a report, never a pass/fail). Test code: the heap holds the scene and the pool.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "scene_fixture.hpp"
#include "vtm/core/arena.hpp"

namespace {

using vtm::tiepoints::test::kStations;

std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001B3ULL;
    }
    return h;
}

// Canonical (little-endian) bytes of a value's bit pattern: the same hash on every target.
std::uint64_t addU64(std::uint64_t h, std::uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) {
        b[i] = static_cast<unsigned char>((v >> (8 * i)) & 0xFFU);
    }
    return fnv(h, b, sizeof b);
}
std::uint64_t addDouble(std::uint64_t h, double d) {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &d, sizeof bits);
    return addU64(h, bits);
}

}  // namespace

int main(int argc, char** argv) {
    char* end = nullptr;
    const long repeat = argc == 2 ? std::strtol(argv[1], &end, 10) : 0;
    if (argc != 2 || end == argv[1] || *end != '\0' || repeat < 1 || repeat > 100) {
        std::fprintf(stderr, "usage: vtm_tiepoints_probe REPEAT (1..100)\n");
        return 2;
    }
    const auto& s = vtm::tiepoints::test::scene();
    if (!s.ok) {
        std::fprintf(stderr, "tiepoints_probe: the scene did not render\n");
        return 1;
    }
    const vtm::tiepoints::Config config = vtm::tiepoints::test::sceneConfig();
    std::vector<std::byte> pool(vtm::tiepoints::TiePointExtractor::workspaceBytes(config));
    vtm::Arena arena(pool.data(), pool.size());
    auto extractor = std::make_unique<vtm::tiepoints::TiePointExtractor>();
    if (!extractor->init(config, arena).isOk()) {
        std::fprintf(stderr, "tiepoints_probe: init failed\n");
        return 1;
    }
    vtm::tiepoints::Stats st;
    const auto t0 = std::clock();
    for (long r = 0; r < repeat; ++r) {
        const vtm::Status status = extractor->run(vtm::Span<const vtm::NetworkStation>(s.stations, kStations),
                                                  vtm::Span<const vtm::StationImages>(s.images, kStations), &st);
        if (!status.isOk()) {
            std::fprintf(stderr, "tiepoints_probe: run: %s\n", status.reason());
            return 1;
        }
    }
    const double ms = 1000.0 * static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC / static_cast<double>(repeat);
    std::uint64_t h = 0xCBF29CE484222325ULL;
    for (const vtm::TieObservation& o : extractor->observations()) {
        h = addU64(h, (static_cast<std::uint64_t>(o.image.station) << 1U) | (o.image.eye == vtm::Eye::kRight ? 1U : 0U));
        h = addU64(h, o.point);
        h = addDouble(h, o.pixel_px.x());
        h = addDouble(h, o.pixel_px.y());
    }
    std::printf("points %d observations %d intra %d/%d/%d inter predicted %d matched %d consistent %d ties %d "
                "hash %016llx\n",
                st.points, st.observations, st.intra_matched, st.intra_consistent, st.intra_ties, st.inter_predicted,
                st.inter_matched, st.inter_consistent, st.inter_ties, static_cast<unsigned long long>(h));
    std::printf("cpu per run %.1f ms (repeat %ld)\n", ms, repeat);
    return 0;
}
