// Tie points of a panorama (paper §3; docs/tiepoints.md): the image measurements the bundle
// adjustment (fsw/bundle) adjusts the stations' pointing with.
//
// Input: the stations (vtm/core/image_network.hpp: the calibrated rig and the APPROXIMATE
// pose of each left camera) and each station's left and right images. Adjacent stations
// are consecutive indices (i, i + 1), and (last, 0) with closed_panorama.
//
// Intra-stereo, per station (left vs right eye):
//  1. Förstner points in the left image (features::ForstnerDetector).
//  2. NCC matching into the right image along the epipolar band the calibrated rig
//     predicts for ranges [range_min_m, range_max_m], widened by rig_margin_px
//     (features::TemplateMatcher: coarse to fine, subpixel peak, affine refinement,
//     mutual check), templates warped for the level ground seen from the approximate pose.
//  3. Parallax consistency (verify.hpp: robust local plane of the parallax).
//  4. Grid thinning (verify.hpp): each intra_grid cell of the left image keeps its best
//     (highest NCC) point. Each survivor is a tie point with two observations.
//  Every consistent match (thinned or not) is triangulated (midpoint of the two rays, the
//  station's approximate pose) and kept as a "stereo point" of the station.
// Inter-stereo, per adjacent pair (i, j) and each eye e of j:
//  1. Coarse elevation map: the stereo points of i and j binned into a map_side x
//     map_side grid of map_cell_m (terrain::HeightMap, mean), centred between the two
//     stations; an empty cell reads the mean of the filled cells within map_fill_radius.
//  2. For each Förstner point of i's left image: its ground point (its own stereo point,
//     else its left ray cast onto the elevation map), projected through (j, e)'s
//     approximate pose; a point predicted outside (j, e)'s image is not tried.
//  3. NCC search (TemplateMatcher, one point at a time) along the left ray for ranges
//     [r / (1 + range_band_fraction), r (1 + range_band_fraction)] around the ground
//     point's range r, widened by the pointing uncertainty:
//         margin_px = sigma_multiplier * sqrt(2) * (pointing_sigma_rad + position_sigma_m / r)
//                     * (pixels per radian at (j, e)'s image centre)
//     (sqrt(2): both stations' poses are uncertain).
//  4. The same parallax check and grid thinning (inter_grid, over i's left image).
//  A survivor that is already an intra tie point keeps its id; otherwise it gets a new id
//  and an observation in i's left image (shared by both eyes of j).
// Output: TieObservation records (point ids 0 .. pointCount() - 1, every point seen in
// at least two images), the count of tie points linking each image pair (pairCounts()),
// and the statistics. Memory: workspaceBytes(config) carved at init(); run() does not
// allocate. Deterministic: fixed orders and vtm::math only.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/forstner.hpp"
#include "vtm/features/template_matcher.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/tiepoints/verify.hpp"

namespace vtm::tiepoints {

constexpr std::int32_t kMaxStations = 64;

// The number of tie points seen in both images a and b (a before b in the table order).
struct PairCount {
    ImageRef a{};
    ImageRef b{};
    std::int32_t count = 0;
};

struct Config {
    std::int32_t max_width = 1024, max_height = 1024;  // image capacity, 1..4096 (detector and matcher follow)
    std::int32_t max_stations = 8;                     // 1..kMaxStations
    std::int32_t max_observations = 8192;              // output capacity, 1..1 << 20
    features::DetectorConfig detector{};               // its max_width/max_height are replaced by the above
    features::MatcherConfig matcher{};                 // likewise
    // Intra-stereo band: ranges along the left ray, 0 < min < max, and the calibration's
    // uncertainty around the epipolar line (0..50 px).
    double range_min_m = 1.0, range_max_m = 60.0;
    double rig_margin_px = 2.0;
    ParallaxConfig parallax{};
    ThinningConfig intra_grid{};
    ThinningConfig inter_grid{};
    // Inter-stereo.
    bool closed_panorama = false;                 // also pair (last, 0)
    double pointing_sigma_rad = 0.0087266462599716478;  // 0.5 deg, per station, (0, 0.2]
    double position_sigma_m = 0.02;               // per station, [0, 1]
    double sigma_multiplier = 3.0;                // [1, 10]
    double range_band_fraction = 0.25;            // (0, 4]
    double map_cell_m = 0.5;                      // (0, 100]
    std::int32_t map_side = 64;                   // cells, 4..512
    std::int32_t map_fill_radius = 2;             // cells, 0..16
    std::int32_t ray_steps = 128;                 // samples of a left ray over the range band, 8..4096
    [[nodiscard]] features::DetectorConfig detectorConfig() const noexcept;
    [[nodiscard]] features::MatcherConfig matcherConfig() const noexcept;
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

struct Stats {
    std::int32_t features = 0;               // Förstner points, all stations
    std::int32_t intra_matched = 0;          // NCC matches left -> right
    std::int32_t intra_consistent = 0;       // ... that passed the parallax check
    std::int32_t intra_ties = 0;             // ... kept by the grid
    std::int32_t inter_predicted = 0;        // (point, partner image) predictions inside the partner image
    std::int32_t inter_no_ground = 0;        // points whose ray found no ground on the map
    std::int32_t inter_matched = 0;
    std::int32_t inter_consistent = 0;
    std::int32_t inter_ties = 0;             // observations added in partner images
    std::int32_t points = 0;
    std::int32_t observations = 0;
};

class TiePointExtractor {
public:
    [[nodiscard]] static std::size_t workspaceBytes(const Config& config) noexcept;
    // kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const Config& config, Arena& arena) noexcept;
    // Refusals (the output then holds nothing): kNotInitialized; kInvalidArgument:
    // stations.size() outside 1..max_stations or images.size() != stations.size()
    // ("stations: ..."), a station failing validateNetworkStation ("stations[i]: invalid",
    // detail i), an empty image; kSizeMismatch: an image whose size differs from its
    // eye's model or exceeds the capacity (detail = station index); kDegenerate: a left
    // image with no Förstner point ("images[i].left: no texture", detail i);
    // kOutOfMemory: more observations than max_observations ("observations: capacity
    // full"). A station pair without ties is not a refusal: its count is 0.
    [[nodiscard]] Status run(Span<const NetworkStation> stations, Span<const StationImages> images,
                             Stats* stats = nullptr) noexcept;

    [[nodiscard]] Span<const TieObservation> observations() const noexcept;
    [[nodiscard]] std::uint32_t pointCount() const noexcept { return points_; }
    [[nodiscard]] Span<const PairCount> pairCounts() const noexcept;
    [[nodiscard]] const Config& config() const noexcept { return config_; }

private:
    [[nodiscard]] Status checkInput(Span<const NetworkStation> stations, Span<const StationImages> images) const noexcept;
    [[nodiscard]] Status intraStation(std::int32_t s, const NetworkStation& station, const StationImages& images,
                                      Stats& stats) noexcept;
    [[nodiscard]] Status interPair(std::int32_t i, std::int32_t j, Span<const NetworkStation> stations,
                                   Span<const StationImages> images, Stats& stats) noexcept;
    [[nodiscard]] Status interEye(std::int32_t i, std::int32_t j, Eye eye, Span<const NetworkStation> stations,
                                  Span<const StationImages> images, Stats& stats) noexcept;
    [[nodiscard]] Status searchEye(std::int32_t i, std::int32_t j, Eye eye, Span<const NetworkStation> stations,
                                   Span<const StationImages> images, Stats& stats) noexcept;
    void buildMap(std::int32_t i, std::int32_t j, Span<const NetworkStation> stations) noexcept;
    [[nodiscard]] bool groundOf(std::int32_t i, std::int32_t k, const NetworkStation& station, Vec3& site_m) const noexcept;
    [[nodiscard]] Status addObservation(ImageRef image, std::uint32_t point, const Vec2& pixel) noexcept;
    [[nodiscard]] Status newPoint(std::uint32_t& id) noexcept;
    void reset() noexcept;

    Config config_{};
    bool initialized_ = false;
    features::ForstnerDetector detector_{};
    features::TemplateMatcher matcher_{};
    terrain::HeightMap map_{};
    features::FeatureSet* detected_ = nullptr; // one image's Förstner points
    features::FeatureSet* single_ = nullptr;   // one feature (inter search)
    features::MatchSet* found_ = nullptr;      // one search's result
    features::MatchSet* matches_ = nullptr;    // the matches under verification
    Span<std::uint8_t> keep_{};                // per match of matches_
    // Per station, max_features slots each (index = station * max_features + feature):
    Span<features::Feature> features_{};
    Span<std::int32_t> featureCount_{};        // per station
    Span<std::int32_t> pointId_{};             // tie point id or -1
    Span<Vec3> stereo_{};                      // triangulated site point (valid when hasStereo_)
    Span<std::uint8_t> hasStereo_{};
    Span<TieObservation> observations_{};
    std::int32_t observationCount_ = 0;
    Span<ImageRef> sightings_{};               // per point, kMaxSightings images (workspace.hpp)
    Span<std::uint8_t> sightingCount_{};
    Span<PairCount> pairs_{};
    std::int32_t pairCount_ = 0;
    std::uint32_t points_ = 0U;
};

}  // namespace vtm::tiepoints
