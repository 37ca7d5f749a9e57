// Determinism section "tiepoints": fsw/tiepoints on two rendered stations of the tests'
// panorama (128 x 128, 0.42 m rig, 32 deg apart, pointing spoiled by 0.5 deg and 2 cm):
// every observation (image, point id, pixel bits), the pair counts and the statistics.
#include <cstddef>
#include <cstring>

#include "determinism_suite.hpp"
#include "vtm/core/hasher.hpp"
#include "panorama_scene.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm::determinism {
namespace {

constexpr std::int32_t kSide = 128;
constexpr std::int32_t kStations = 2;

struct Storage {
    std::uint8_t images[2 * kStations][kSide * kSide];
    sim::Terrain terrain;
    std::byte terrain_pool[8U << 20U];
    std::byte pool[4U << 20U];
};
Storage g_storage;

tiepoints::Config sectionConfig() noexcept {
    tiepoints::Config c;
    c.max_width = kSide;
    c.max_height = kSide;
    c.max_stations = kStations;
    c.max_observations = 512;
    c.detector.grid_cols = 8;
    c.detector.grid_rows = 8;
    c.detector.per_cell = 2;
    c.detector.max_features = 128;
    c.matcher.pyramid_levels = 1;
    c.intra_grid.cols = 6;
    c.intra_grid.rows = 6;
    c.inter_grid.cols = 6;
    c.inter_grid.rows = 6;
    c.parallax.max_radius_px = 50.0;
    c.map_side = 48;
    return c;
}

}  // namespace

std::uint64_t tiepointsSection() noexcept {
    Hasher h;
    Storage& s = g_storage;
    vtm::test::PanoramaSpec spec;
    spec.width = kSide;
    spec.height = kSide;
    Arena terrain_arena(s.terrain_pool, sizeof s.terrain_pool);
    const Status built = s.terrain.build(vtm::test::panoramaTerrainParams(spec), terrain_arena);
    h.addI64(static_cast<std::int64_t>(built.code()));
    if (!built.isOk()) {
        return h.value();
    }
    const CameraModel model = makePinhole(kSide, kSide, spec.hfov_deg);
    NetworkStation stations[kStations];
    StationImages images[kStations];
    for (std::int32_t k = 0; k < kStations; ++k) {
        RigidPose left;
        RigidPose right;
        vtm::test::truePoses(spec, s.terrain, k, left, right);
        stations[k] = vtm::test::approximateStation(spec, model, left, right, k);
        h.addI64(static_cast<std::int64_t>(
            vtm::test::renderEye(spec, s.terrain, model, left, static_cast<std::uint32_t>(2 * k), s.images[2 * k], nullptr)
                .code()));
        h.addI64(static_cast<std::int64_t>(vtm::test::renderEye(spec, s.terrain, model, right,
                                                                static_cast<std::uint32_t>(2 * k + 1),
                                                                s.images[2 * k + 1], nullptr)
                                               .code()));
        images[k].left = ImageView<const std::uint8_t>(s.images[2 * k], kSide, kSide);
        images[k].right = ImageView<const std::uint8_t>(s.images[2 * k + 1], kSide, kSide);
    }
    Arena arena(s.pool, sizeof s.pool);
    static tiepoints::TiePointExtractor extractor;
    const Status init = extractor.init(sectionConfig(), arena);
    h.addI64(static_cast<std::int64_t>(init.code()));
    if (!init.isOk()) {
        return h.value();
    }
    tiepoints::Stats stats;
    const Status run = extractor.run(Span<const NetworkStation>(stations, kStations),
                                     Span<const StationImages>(images, kStations), &stats);
    h.addI64(static_cast<std::int64_t>(run.code()));
    for (const TieObservation& o : extractor.observations()) {
        h.addI64(o.image.station);
        h.addI64(static_cast<std::int64_t>(o.image.eye));
        h.addI64(o.point);
        h.addDouble(o.pixel_px.x());
        h.addDouble(o.pixel_px.y());
    }
    for (const tiepoints::PairCount& p : extractor.pairCounts()) {
        h.addI64(2 * p.a.station + static_cast<std::int32_t>(p.a.eye));
        h.addI64(2 * p.b.station + static_cast<std::int32_t>(p.b.eye));
        h.addI64(p.count);
    }
    const std::int32_t figures[] = {stats.features,      stats.intra_matched,   stats.intra_consistent,
                                    stats.intra_ties,    stats.inter_predicted, stats.inter_no_ground,
                                    stats.inter_matched, stats.inter_consistent, stats.inter_ties,
                                    stats.points,        stats.observations};
    for (const std::int32_t f : figures) {
        h.addI64(f);
    }
    return h.value();
}

}  // namespace vtm::determinism
