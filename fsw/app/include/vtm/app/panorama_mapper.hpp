// PanoramaMapper: the mast panorama's mapping executive (issue 23, paper §3). The rover
// stands still and turns its calibrated stereo rig through 360 deg in one or more tilt
// tiers; each exposure is a station (vtm/core/image_network.hpp). The pointing of every
// station comes from the mast's encoders and the rover's attitude, so the caller hands
// the stations in with their pointing priors and their images (map(); docs/app.md
// "PanoramaMapper" says why this executive does not capture through hal::Camera).
// Initialised once from a validated configuration, it owns all its memory (planned by
// workspaceBytes and taken from the caller's Arena at init). Each map() request:
//   tiepoints  fsw/tiepoints on each closed ring of ring_stations consecutive stations
//              (a tilt tier; all stations when ring_stations is 0), gathered into one
//              network (point ids offset ring by ring)
//   bundle     fsw/bundle: every station's pose and every tie point's ground position,
//              the rigs' calibration as a constraint, the pointing priors weighted by
//              their covariances; the adjusted stations replace the approximate ones
//   dense      (dense_stereo) per station: the calibrated rig pair rectified (fsw/rectify),
//              dense disparities (stereo::PyramidStereo; the coarse search follows the
//              plane in disparity space through the station's adjusted tie points, when
//              three or more of them lie in its left image), triangulated (fsw/terrain)
//              with the ADJUSTED pose into site points, binned into the sample grid (the
//              elevation grid's extent, sample_cell_m cells; points whose range sigma
//              exceeds max_point_sigma_m or that lie beyond dense_range_max_m left out);
//              a cell with at least
//              min_cell_points points whose elevations spread at most max_cell_spread_m
//              gives one sample: the points' centroid (not the cell's centre: the visible
//              part of a cell on a slope turned away from the mast is its upper part)
//   krige      the dense samples checked against the adjusted tie points inside the grid
//              (kriged alone at each dense sample: one more than dense_gate_m off is
//              dropped); ordinary kriging (fsw/kriging) of the kept samples and the tie
//              points: the variogram fitted to them, the bounded
//              neighbourhood of the kriging config, elevation and kriging variance per node
//   orthophoto the orthophoto of the kriged elevations from the adjusted stations
// Every stage leaves a StageRecord (Status, quality figure, time from hal::Clock) in
// stages() and one event in hal::EventLog (stage_log.hpp). The first stage that fails ends
// the request with its Status and nothing is published: products() is nullptr until a
// request succeeds, and again from the start of the next one. A published product stays
// valid until the next map(); it does not point into the caller's images after map().
//
// No heap, no exceptions; deterministic for the same stations and images. docs/app.md.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/span.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"
#include "vtm/kriging/orthophoto.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/stereo/disparity_plane.hpp"
#include "vtm/stereo/pyramid_stereo.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/terrain/triangulation.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm::app {

// Largest count of tie points of one station that give its disparity plane.
constexpr std::int32_t kMaxPlaneSamples = 512;

struct PanoramaMapperConfig {
    // Capacities, stated once. The mapper sets the sub-configurations' capacity fields from
    // them (those fields are not read): tiepoints' image size, stations per ring and
    // observations; bundle's stations, points (max_observations / 2) and observations;
    // rectify's and stereo's image size; kriging's max_samples (the sample grid's cells
    // plus max_observations / 2 tie points).
    std::int32_t max_stations = 32;          // 2..64 (bundle::kMaxStationsLimit)
    std::int32_t image_width = 1024;         // every eye's image at most, 16..4094
    std::int32_t image_height = 1024;
    std::int32_t max_observations = 16384;   // tie observations of the whole network, 16..1 << 20
    // Stations per closed ring (a tilt tier's columns): stations i*ring .. (i+1)*ring - 1
    // are tied as one closed panorama; 0: all stations are one ring. 0 or 3..64.
    std::int32_t ring_stations = 0;
    tiepoints::Config tiepoints = defaultTiePoints();
    bundle::BundleConfig bundle{};
    // Dense elevation (stage dense); false: the map is kriged from the tie points alone.
    bool dense_stereo = true;
    rectify::Config rectify{};               // its range limits are replaced by range_*_m
    stereo::PyramidConfig stereo{};          // PyramidStereo's defaults (docs/app.md)
    terrain::TriangulationLimits limits{};   // its range limits are replaced by range_*_m
    // The terrain's range along a left ray: the tie points' intra-stereo band, the
    // rectifier's disparity bounds, the triangulation's limits. 0 < min < max.
    double range_min_m = 1.0;
    double range_max_m = 40.0;
    double sample_cell_m = 0.25;             // the sample grid's cell, (0, 100]
    // A dense point whose range 1-sigma (terrain::TerrainPoint::sigma_range_m) exceeds this
    // is not binned, (0, 100]: the far field of a short rig is left to the tie points.
    double max_point_sigma_m = 0.05;
    // Nor one farther than this from its station's left eye, metres, (0, range_max_m]: the
    // stereo's wrong matches grow with range (docs/app.md has the measurements).
    double dense_range_max_m = 6.0;
    std::int32_t min_cell_points = 3;        // 1..1000000
    // A dense sample whose elevation differs from the tie points' kriged elevation at its
    // position by more than this is dropped (stage krige), metres, 0 (off)..100.
    double dense_gate_m = 0.15;
    double max_cell_spread_m = 0.2;          // highest - lowest in a cell at most, (0, 100]
    // The elevation map: kriging.grid is the site grid (north-west corner, cell, size).
    kriging::KrigingConfig kriging = defaultKriging();
    kriging::OrthophotoConfig orthophoto{};

    // The tie points as the chain evaluation (tests/panorama) runs them: closed rings.
    [[nodiscard]] static tiepoints::Config defaultTiePoints() noexcept {
        tiepoints::Config t;
        t.closed_panorama = true;
        return t;
    }
    // A 20 m square at 0.25 m centred on the site origin, 2 m neighbourhood.
    [[nodiscard]] static kriging::KrigingConfig defaultKriging() noexcept {
        kriging::KrigingConfig k;
        k.grid.cell_m = 0.25;
        k.grid.cols = 80;
        k.grid.rows = 80;
        k.grid.north_edge_m = 10.0;
        k.grid.west_edge_m = -10.0;
        k.search_radius_m = 2.0;
        return k;
    }
    // kOk, or kInvalidConfig naming the field (sub-configurations as their validate()
    // names them).
    [[nodiscard]] Status validate() const noexcept;
};

// What a successful request publishes. Spans and views point into the mapper's memory.
struct PanoramaProducts {
    Span<const NetworkStation> adjusted;        // the stations with their adjusted poses (priors as given)
    Span<const bundle::StationSolution> stations;  // the bundle's solutions (corrections, covariances)
    Span<const TieObservation> observations;    // the whole network's tie observations
    Span<const bundle::PointSolution> tie_points;  // per point id: the adjusted ground position
    Span<const bundle::ObservationResidual> residuals;  // per observation
    Span<const Vec3> samples;                   // what was kriged: dense samples, then tie points (site frame)
    const kriging::KrigedMap* elevation = nullptr;  // elevation and kriging variance per node
    ImageView<const std::uint8_t> orthophoto;   // the elevation grid's size
    ImageView<const std::uint16_t> source;      // per node: 2 * station + eye, kriging::kNoSource
    std::uint32_t points = 0U;                  // tie point ids
    std::int32_t rings = 0;
    tiepoints::Stats tiepoints{};               // summed over the rings
    bundle::BundleResult bundle{};
    std::int32_t dense_points = 0;              // triangulated points, all stations
    std::int32_t dense_stations = 0;            // stations whose stereo gave points
    std::int32_t plane_stations = 0;            // ... of them, searched around their tie points' plane
    std::int32_t dense_samples = 0;             // sample cells kept (after the gate)
    std::int32_t dense_rejected = 0;            // dense samples the tie points' gate dropped
    std::int32_t tie_samples = 0;               // adjusted tie points inside the grid
    kriging::Variogram variogram{};
    kriging::KrigingStats kriging{};
    kriging::OrthophotoStats ortho{};
};

class PanoramaMapper {
public:
    // Arena bytes for this configuration, 0 if it is invalid (docs/app.md has the formula).
    [[nodiscard]] static std::size_t workspaceBytes(const PanoramaMapperConfig& config) noexcept;

    // Validates the config and carves the memory. The clock and the event log are borrowed
    // and must outlive the mapper. kInvalidConfig (config field), kOutOfMemory (arena).
    [[nodiscard]] Status init(const PanoramaMapperConfig& config, Arena& arena, const hal::Clock& clock,
                              hal::EventLog& events) noexcept;

    // One request (see the file comment): stations[i] (calibrated rig, approximate left-eye
    // pose, pointing prior) with images[i]. kNotInitialized before a successful init();
    // kInvalidArgument from stage tiepoints for fewer than 2 or more than max_stations
    // stations ("stations: ..."), images of another count ("images: ..."), a station count
    // that is not a multiple of ring_stations; kSizeMismatch for an eye model larger than
    // image_width x image_height (detail: the station); otherwise the failing stage's
    // Status (the modules' reasons; kNoData from krige when too few samples fell in the
    // grid).
    [[nodiscard]] Status map(Span<const NetworkStation> stations, Span<const StationImages> images) noexcept;

    [[nodiscard]] const PanoramaProducts* products() const noexcept { return published_ ? &products_ : nullptr; }
    [[nodiscard]] const StageLog& stages() const noexcept { return stages_; }
    [[nodiscard]] std::size_t memoryBytes() const noexcept { return memory_bytes_; }

private:
    [[nodiscard]] Status checkInput(Span<const NetworkStation> stations, Span<const StationImages> images) const noexcept;
    [[nodiscard]] Status runTiePoints(Span<const NetworkStation> stations, Span<const StationImages> images) noexcept;
    [[nodiscard]] Status runBundle(Span<const NetworkStation> stations) noexcept;
    [[nodiscard]] Status runDense(Span<const StationImages> images) noexcept;
    [[nodiscard]] Status denseStation(std::size_t s, const StationImages& images) noexcept;
    [[nodiscard]] bool planeOf(std::size_t s, const rectify::RectifiedPair& pair) noexcept;
    [[nodiscard]] Status gateDenseSamples() noexcept;
    [[nodiscard]] Status runKrige() noexcept;
    [[nodiscard]] Status runOrthophoto(Span<const StationImages> images) noexcept;
    Status finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

    PanoramaMapperConfig config_{};
    const hal::Clock* clock_ = nullptr;
    hal::EventLog* events_ = nullptr;
    tiepoints::TiePointExtractor extractor_{};
    bundle::BundleAdjuster adjuster_{};
    rectify::Rectifier rectifier_{};
    stereo::PyramidStereo stereo_{};
    struct SampleCell {                      // the dense points in one cell of the sample grid
        double north_m, east_m, down_m;      // sums
        float lowest_down_m, highest_down_m;
        std::uint32_t count;
    };
    void binPoints(Span<const terrain::TerrainPoint> points, const Vec3& eye_m) noexcept;
    terrain::GridConfig sample_grid_{};
    Span<SampleCell> cells_{};
    kriging::OrdinaryKriging kriging_{};
    NetworkStation* adjusted_ = nullptr;     // max_stations
    TieObservation* observations_ = nullptr; // max_observations
    std::size_t observation_count_ = 0U;
    Vec3* samples_ = nullptr;                // kriging's max_samples
    std::size_t sample_count_ = 0U;
    Vec3* plane_samples_ = nullptr;          // kMaxPlaneSamples
    double plane_scratch_[kMaxPlaneSamples] = {};
    ImageView<std::uint8_t> rect_left_{};
    ImageView<std::uint8_t> rect_right_{};
    ImageView<std::int16_t> surface_{};
    ImageView<std::int16_t> disparity_{};
    ImageView<float> sigma_{};
    Span<terrain::TerrainPoint> points_{};
    ImageView<std::uint8_t> ortho_{};
    ImageView<std::uint16_t> source_{};
    PanoramaProducts products_{};
    StageLog stages_{};
    std::size_t memory_bytes_ = 0U;
    bool initialized_ = false;
    bool published_ = false;
};

}  // namespace vtm::app
