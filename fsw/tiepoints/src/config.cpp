// Config::validate, workspaceBytes and init of the tie-point extractor (tiepoints.hpp).

#include "vtm/core/math.hpp"
#include "vtm/core/config_check.hpp"
#include "vtm/tiepoints/tiepoints.hpp"
#include "workspace.hpp"

namespace vtm::tiepoints {
namespace {

terrain::HeightMapConfig mapConfig(const Config& c) noexcept {
    terrain::HeightMapConfig m;
    m.grid.cols = c.map_side;
    m.grid.rows = c.map_side;
    m.grid.cell_m = c.map_cell_m;
    m.reducer = terrain::Reducer::kMean;
    return m;
}

}  // namespace

features::DetectorConfig Config::detectorConfig() const noexcept {
    return detector.withCapacity(max_width, max_height);
}

features::MatcherConfig Config::matcherConfig() const noexcept {
    return matcher.withCapacity(max_width, max_height);
}

Status Config::validate() const noexcept {
    if (max_width < 1 || max_width > 4096 || max_height < 1 || max_height > 4096) {
        return invalidConfig("tiepoints.max_width/max_height: must be 1..4096", max_width);
    }
    if (max_stations < 1 || max_stations > kMaxStations) {
        return invalidConfig("tiepoints.max_stations: must be 1..64", max_stations);
    }
    if (max_observations < 1 || max_observations > (1 << 20)) {
        return invalidConfig("tiepoints.max_observations: must be 1..1048576", max_observations);
    }
    VTM_RETURN_IF_ERROR(detectorConfig().validate());
    VTM_RETURN_IF_ERROR(matcherConfig().validate());
    if (!(math::isFinite(range_min_m) && math::isFinite(range_max_m) && range_min_m > 0.0 &&
          range_min_m < range_max_m)) {
        return invalidConfig("tiepoints.range_min_m/range_max_m: need 0 < min < max, finite");
    }
    if (!isInRange(rig_margin_px, 0.0, 50.0)) {
        return invalidConfig("tiepoints.rig_margin_px: must be 0..50");
    }
    VTM_RETURN_IF_ERROR(parallax.validate());
    VTM_RETURN_IF_ERROR(intra_grid.validate());
    VTM_RETURN_IF_ERROR(inter_grid.validate());
    if (!isInRange(pointing_sigma_rad, 1e-9, 0.2)) {
        return invalidConfig("tiepoints.pointing_sigma_rad: must be (0, 0.2]");
    }
    if (!isInRange(position_sigma_m, 0.0, 1.0)) {
        return invalidConfig("tiepoints.position_sigma_m: must be 0..1");
    }
    if (!isInRange(sigma_multiplier, 1.0, 10.0)) {
        return invalidConfig("tiepoints.sigma_multiplier: must be 1..10");
    }
    if (!isInRange(range_band_fraction, 1e-6, 4.0)) {
        return invalidConfig("tiepoints.range_band_fraction: must be (0, 4]");
    }
    if (!isInRange(map_cell_m, 1e-6, 100.0)) {
        return invalidConfig("tiepoints.map_cell_m: must be (0, 100]");
    }
    if (map_side < 4 || map_side > 512) {
        return invalidConfig("tiepoints.map_side: must be 4..512", map_side);
    }
    if (map_fill_radius < 0 || map_fill_radius > 16) {
        return invalidConfig("tiepoints.map_fill_radius: must be 0..16", map_fill_radius);
    }
    if (ray_steps < 8 || ray_steps > 4096) {
        return invalidConfig("tiepoints.ray_steps: must be 8..4096", ray_steps);
    }
    return Status::ok();
}

std::size_t TiePointExtractor::workspaceBytes(const Config& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t slots = detail::featureSlots(config);
    const std::size_t points = detail::pointCapacity(config);
    return features::ForstnerDetector::workspaceBytes(config.detectorConfig()) +
           features::TemplateMatcher::workspaceBytes(config.matcherConfig()) +
           terrain::HeightMap::workspaceBytes(mapConfig(config)) +
           2U * Arena::constructBytes<features::FeatureSet>(1U) + 2U * Arena::constructBytes<features::MatchSet>(1U) +
           Arena::arrayBytes<std::uint8_t>(static_cast<std::size_t>(features::kMaxFeatures))  // keep
           + Arena::constructBytes<features::Feature>(slots) + Arena::arrayBytes<std::int32_t>(slots)  // point ids
           + Arena::constructBytes<Vec3>(slots) + Arena::arrayBytes<std::uint8_t>(slots)                // stereo points
           + Arena::arrayBytes<std::int32_t>(static_cast<std::size_t>(config.max_stations))           // feature counts
           + Arena::constructBytes<TieObservation>(static_cast<std::size_t>(config.max_observations)) +
           Arena::constructBytes<PairCount>(detail::pairCapacity(config)) +
           Arena::constructBytes<ImageRef>(points * detail::kMaxSightings) + Arena::arrayBytes<std::uint8_t>(points);
}

Status TiePointExtractor::init(const Config& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    VTM_RETURN_IF_ERROR(detector_.init(config.detectorConfig(), arena));
    VTM_RETURN_IF_ERROR(matcher_.init(config.matcherConfig(), arena));
    VTM_RETURN_IF_ERROR(map_.init(mapConfig(config), arena));
    const std::size_t slots = detail::featureSlots(config);
    const std::size_t points = detail::pointCapacity(config);
    detected_ = arena.construct<features::FeatureSet>(1U);
    single_ = arena.construct<features::FeatureSet>(1U);
    found_ = arena.construct<features::MatchSet>(1U);
    matches_ = arena.construct<features::MatchSet>(1U);
    keep_ = arena.allocateArray<std::uint8_t>(static_cast<std::size_t>(features::kMaxFeatures));
    features::Feature* f = arena.construct<features::Feature>(slots);
    pointId_ = arena.allocateArray<std::int32_t>(slots);
    Vec3* stereo = arena.construct<Vec3>(slots);
    hasStereo_ = arena.allocateArray<std::uint8_t>(slots);
    featureCount_ = arena.allocateArray<std::int32_t>(static_cast<std::size_t>(config.max_stations));
    TieObservation* obs = arena.construct<TieObservation>(static_cast<std::size_t>(config.max_observations));
    PairCount* pairs = arena.construct<PairCount>(detail::pairCapacity(config));
    ImageRef* seen = arena.construct<ImageRef>(points * detail::kMaxSightings);
    sightingCount_ = arena.allocateArray<std::uint8_t>(points);
    if (detected_ == nullptr || single_ == nullptr || found_ == nullptr || matches_ == nullptr || keep_.empty() ||
        f == nullptr || pointId_.empty() || stereo == nullptr || hasStereo_.empty() || featureCount_.empty() ||
        obs == nullptr || pairs == nullptr || seen == nullptr || sightingCount_.empty()) {
        return Status(StatusCode::kOutOfMemory, "TiePointExtractor::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    features_ = Span<features::Feature>(f, slots);
    stereo_ = Span<Vec3>(stereo, slots);
    observations_ = Span<TieObservation>(obs, static_cast<std::size_t>(config.max_observations));
    pairs_ = Span<PairCount>(pairs, detail::pairCapacity(config));
    sightings_ = Span<ImageRef>(seen, points * detail::kMaxSightings);
    config_ = config;
    initialized_ = true;
    reset();
    return Status::ok();
}

}  // namespace vtm::tiepoints
