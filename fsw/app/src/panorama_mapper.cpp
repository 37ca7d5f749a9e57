#include "vtm/app/panorama_mapper.hpp"

#include <cmath>

#include "request_support.hpp"
#include "vtm/core/config_check.hpp"
#include "vtm/core/math.hpp"
#include "vtm/terrain/rectified_geometry.hpp"

namespace vtm::app {
namespace {

using detail::carve;

constexpr std::int32_t kMaxNetworkStations =
    bundle::kMaxStationsLimit < tiepoints::kMaxStations ? bundle::kMaxStationsLimit : tiepoints::kMaxStations;

std::size_t pixelsOf(const PanoramaMapperConfig& c) noexcept {
    return static_cast<std::size_t>(c.image_width) * static_cast<std::size_t>(c.image_height);
}
std::size_t maxTiePoints(const PanoramaMapperConfig& c) noexcept {
    return static_cast<std::size_t>(c.max_observations / 2);
}
std::int32_t ringCapacity(const PanoramaMapperConfig& c) noexcept {
    return c.ring_stations > 0 ? c.ring_stations : c.max_stations;
}

// The sample grid: the elevation grid's extent at sample_cell_m (ceil), the same corner.
terrain::HeightMapConfig sampleGridOf(const PanoramaMapperConfig& c) noexcept {
    terrain::HeightMapConfig m;
    m.reducer = terrain::Reducer::kMean;
    m.grid.north_edge_m = c.kriging.grid.north_edge_m;
    m.grid.west_edge_m = c.kriging.grid.west_edge_m;
    m.grid.cell_m = c.sample_cell_m;
    const double cols = std::ceil(c.kriging.grid.cell_m * c.kriging.grid.cols / c.sample_cell_m - 1e-9);
    const double rows = std::ceil(c.kriging.grid.cell_m * c.kriging.grid.rows / c.sample_cell_m - 1e-9);
    const double limit = static_cast<double>(terrain::kMaxGridSide) + 1.0;  // refused by validate()
    m.grid.cols = static_cast<std::int32_t>(cols < limit ? cols : limit);
    m.grid.rows = static_cast<std::int32_t>(rows < limit ? rows : limit);
    return m;
}
std::size_t sampleCells(const PanoramaMapperConfig& c) noexcept {
    const terrain::HeightMapConfig m = sampleGridOf(c);
    return c.dense_stereo ? static_cast<std::size_t>(m.grid.cols) * static_cast<std::size_t>(m.grid.rows) : 0U;
}

// The sub-configurations with what the mapper states once in them.
tiepoints::Config tiePointsConfigOf(const PanoramaMapperConfig& c) noexcept {
    tiepoints::Config t = c.tiepoints;
    t.max_width = c.image_width;
    t.max_height = c.image_height;
    t.max_stations = ringCapacity(c);
    t.max_observations = c.max_observations;
    t.range_min_m = c.range_min_m;
    t.range_max_m = c.range_max_m;
    return t;
}
bundle::BundleConfig bundleConfigOf(const PanoramaMapperConfig& c) noexcept {
    bundle::BundleConfig b = c.bundle;
    b.max_stations = c.max_stations;
    b.max_points = static_cast<std::int32_t>(maxTiePoints(c));
    b.max_observations = c.max_observations;
    return b;
}
rectify::Config rectifyConfigOf(const PanoramaMapperConfig& c) noexcept {
    rectify::Config r = c.rectify;
    r.max_width = c.image_width;
    r.max_height = c.image_height;
    r.out_width = 0;  // the left eye's size
    r.out_height = 0;
    r.range_min_m = c.range_min_m;
    r.range_max_m = c.range_max_m;
    return r;
}
stereo::PyramidConfig stereoConfigOf(const PanoramaMapperConfig& c) noexcept {
    stereo::PyramidConfig s = c.stereo;
    s.max_width = c.image_width;
    s.max_height = c.image_height;
    return s;
}
terrain::TriangulationLimits limitsOf(const PanoramaMapperConfig& c) noexcept {
    terrain::TriangulationLimits l = c.limits;
    l.min_range_m = c.range_min_m;
    l.max_range_m = c.range_max_m;
    return l;
}
kriging::KrigingConfig krigingConfigOf(const PanoramaMapperConfig& c) noexcept {
    kriging::KrigingConfig k = c.kriging;
    const std::size_t n = sampleCells(c) + maxTiePoints(c);
    const auto limit = static_cast<std::size_t>(kriging::kMaxSamplesLimit) + 1U;  // refused by validate()
    k.max_samples = static_cast<std::int32_t>(n < limit ? n : limit);
    return k;
}

Status validateDense(const PanoramaMapperConfig& c) noexcept {
    VTM_RETURN_IF_ERROR(rectifyConfigOf(c).validate());
    VTM_RETURN_IF_ERROR(stereoConfigOf(c).validate());
    VTM_RETURN_IF_ERROR(limitsOf(c).validate());
    if (!isInRange(c.sample_cell_m, 1e-6, 100.0)) {
        return invalidConfig("sample_cell_m: must be in (0, 100]");
    }
    if (!isInRange(c.max_point_sigma_m, 1e-6, 100.0)) {
        return invalidConfig("max_point_sigma_m: must be in (0, 100]");
    }
    if (!isInRange(c.dense_gate_m, 0.0, 100.0)) {
        return invalidConfig("dense_gate_m: must be 0 (off) or in (0, 100]");
    }
    if (!isInRange(c.dense_range_max_m, 1e-6, c.range_max_m)) {
        return invalidConfig("dense_range_max_m: must be in (0, range_max_m]");
    }
    if (c.min_cell_points < 1 || c.min_cell_points > 1000000) {
        return invalidConfig("min_cell_points: must be 1..1000000", c.min_cell_points);
    }
    if (!isInRange(c.max_cell_spread_m, 1e-6, 100.0)) {
        return invalidConfig("max_cell_spread_m: must be in (0, 100]");
    }
    const terrain::HeightMapConfig m = sampleGridOf(c);
    if (m.grid.cols > terrain::kMaxGridSide || m.grid.rows > terrain::kMaxGridSide) {
        return invalidConfig("sample_cell_m: the elevation grid's extent needs more than 4096 sample cells a side");
    }
    return m.validate();
}

}  // namespace

Status PanoramaMapperConfig::validate() const noexcept {
    if (max_stations < 2 || max_stations > kMaxNetworkStations) {
        return invalidConfig("max_stations: must be 2..64", max_stations);
    }
    if (image_width < 16 || image_width > rectify::kMaxImageSide || image_height < 16 ||
        image_height > rectify::kMaxImageSide) {
        return invalidConfig("image_width/image_height: must be 16..4094", image_width);
    }
    if (max_observations < 16 || max_observations > bundle::kMaxObservationsLimit) {
        return invalidConfig("max_observations: must be 16..1048576", max_observations);
    }
    if (ring_stations != 0 && (ring_stations < 3 || ring_stations > max_stations)) {
        return invalidConfig("ring_stations: must be 0 (one ring) or 3..max_stations", ring_stations);
    }
    if (!math::isFinite(range_min_m) || !math::isFinite(range_max_m) || !(range_min_m > 0.0) ||
        !(range_max_m > range_min_m)) {
        return invalidConfig("range_min_m/range_max_m: need 0 < range_min_m < range_max_m, finite");
    }
    VTM_RETURN_IF_ERROR(tiePointsConfigOf(*this).validate());
    VTM_RETURN_IF_ERROR(bundleConfigOf(*this).validate());
    VTM_RETURN_IF_ERROR(kriging.grid.validate());  // the sample grid follows it
    if (dense_stereo) {
        VTM_RETURN_IF_ERROR(validateDense(*this));
    }
    const kriging::KrigingConfig k = krigingConfigOf(*this);
    if (k.max_samples > kriging::kMaxSamplesLimit) {
        return invalidConfig("kriging: the sample grid's cells plus max_observations / 2 exceed 1048576 samples");
    }
    VTM_RETURN_IF_ERROR(k.validate());
    return orthophoto.validate();
}

std::size_t PanoramaMapper::workspaceBytes(const PanoramaMapperConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const kriging::KrigingConfig k = krigingConfigOf(config);
    const auto nodes = static_cast<std::size_t>(k.grid.cols) * static_cast<std::size_t>(k.grid.rows);
    std::size_t bytes = tiepoints::TiePointExtractor::workspaceBytes(tiePointsConfigOf(config)) +
                        bundle::BundleAdjuster::workspaceBytes(bundleConfigOf(config)) +
                        kriging::OrdinaryKriging::workspaceBytes(k) +
                        Arena::constructBytes<NetworkStation>(static_cast<std::size_t>(config.max_stations)) +
                        Arena::constructBytes<TieObservation>(static_cast<std::size_t>(config.max_observations)) +
                        Arena::constructBytes<Vec3>(static_cast<std::size_t>(k.max_samples))  // kriged samples
                        + Arena::arrayBytes<std::uint8_t>(nodes)                             // orthophoto
                        + Arena::arrayBytes<std::uint16_t>(nodes);                           // its sources
    if (config.dense_stereo) {
        const std::size_t px = pixelsOf(config);
        bytes += rectify::Rectifier::workspaceBytes(rectifyConfigOf(config)) +
                 stereo::PyramidStereo::workspaceBytes(stereoConfigOf(config)) +
                 Arena::arrayBytes<SampleCell>(sampleCells(config)) +
                 Arena::constructBytes<Vec3>(static_cast<std::size_t>(kMaxPlaneSamples))  // a station's plane samples
                 + 2U * Arena::arrayBytes<std::uint8_t>(px)                            // rectified pair
                 + 2U * Arena::arrayBytes<std::int16_t>(px)                            // surface, disparity
                 + Arena::arrayBytes<float>(px)                                        // its sigma
                 + Arena::arrayBytes<terrain::TerrainPoint>(px);                       // one point per pixel
    }
    return bytes;
}

Status PanoramaMapper::init(const PanoramaMapperConfig& config, Arena& arena, const hal::Clock& clock,
                            hal::EventLog& events) noexcept {
    initialized_ = false;
    published_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t before = arena.usedBytes();
    const kriging::KrigingConfig k = krigingConfigOf(config);
    VTM_RETURN_IF_ERROR(extractor_.init(tiePointsConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(adjuster_.init(bundleConfigOf(config), arena));
    VTM_RETURN_IF_ERROR(kriging_.init(k, arena));
    adjusted_ = arena.construct<NetworkStation>(static_cast<std::size_t>(config.max_stations));
    observations_ = arena.construct<TieObservation>(static_cast<std::size_t>(config.max_observations));
    samples_ = arena.construct<Vec3>(static_cast<std::size_t>(k.max_samples));
    ortho_ = carve<std::uint8_t>(arena, k.grid.cols, k.grid.rows);
    source_ = carve<std::uint16_t>(arena, k.grid.cols, k.grid.rows);
    bool ok = adjusted_ != nullptr && observations_ != nullptr && samples_ != nullptr && ortho_.data() != nullptr &&
              source_.data() != nullptr;
    if (ok && config.dense_stereo) {
        VTM_RETURN_IF_ERROR(rectifier_.init(rectifyConfigOf(config), arena));
        VTM_RETURN_IF_ERROR(stereo_.init(stereoConfigOf(config), arena));
        sample_grid_ = sampleGridOf(config).grid;
        cells_ = arena.allocateArray<SampleCell>(sampleCells(config));
        const std::int32_t w = config.image_width;
        const std::int32_t h = config.image_height;
        plane_samples_ = arena.construct<Vec3>(static_cast<std::size_t>(kMaxPlaneSamples));
        rect_left_ = carve<std::uint8_t>(arena, w, h);
        rect_right_ = carve<std::uint8_t>(arena, w, h);
        surface_ = carve<std::int16_t>(arena, w, h);
        disparity_ = carve<std::int16_t>(arena, w, h);
        sigma_ = carve<float>(arena, w, h);
        points_ = arena.allocateArray<terrain::TerrainPoint>(pixelsOf(config));
        ok = !cells_.empty() && plane_samples_ != nullptr && rect_left_.data() != nullptr && rect_right_.data() != nullptr &&
             surface_.data() != nullptr && disparity_.data() != nullptr && sigma_.data() != nullptr && !points_.empty();
    }
    if (!ok) {
        return Status(StatusCode::kOutOfMemory, "PanoramaMapper::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    memory_bytes_ = arena.usedBytes() - before;
    config_ = config;
    clock_ = &clock;
    events_ = &events;
    initialized_ = true;
    return Status::ok();
}

Status PanoramaMapper::finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept {
    return detail::recordStage(stages_, *events_, *clock_, stage, status, quality, t0_ns);
}

Status PanoramaMapper::checkInput(Span<const NetworkStation> stations, Span<const StationImages> images) const noexcept {
    const auto n = static_cast<std::int64_t>(stations.size());
    if (n < 2 || n > config_.max_stations) {
        return Status(StatusCode::kInvalidArgument, "stations: need 2..max_stations", n);
    }
    if (images.size() != stations.size()) {
        return Status(StatusCode::kInvalidArgument, "images: not one StationImages per station",
                      static_cast<std::int64_t>(images.size()));
    }
    if (config_.ring_stations > 0 && n % config_.ring_stations != 0) {
        return Status(StatusCode::kInvalidArgument, "stations: the count is not a multiple of ring_stations", n);
    }
    for (std::size_t s = 0U; s < stations.size(); ++s) {
        const CameraPair& rig = stations[s].rig;
        if (rig.model_a.width_px > config_.image_width || rig.model_a.height_px > config_.image_height ||
            rig.model_b.width_px > config_.image_width || rig.model_b.height_px > config_.image_height) {
            return Status(StatusCode::kSizeMismatch, "stations: an eye's image exceeds image_width x image_height",
                          static_cast<std::int64_t>(s));
        }
    }
    return Status::ok();
}

// Each ring through the extractor; its observations appended with the ring's station and
// point offsets.
Status PanoramaMapper::runTiePoints(Span<const NetworkStation> stations, Span<const StationImages> images) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    PanoramaProducts& p = products_;
    observation_count_ = 0U;
    p.points = 0U;
    p.tiepoints = tiepoints::Stats{};
    Status st = checkInput(stations, images);
    const std::size_t ring = config_.ring_stations > 0 ? static_cast<std::size_t>(config_.ring_stations) : stations.size();
    p.rings = st.isOk() ? static_cast<std::int32_t>(stations.size() / ring) : 0;
    for (std::int32_t r = 0; st.isOk() && r < p.rings; ++r) {
        const std::size_t first = static_cast<std::size_t>(r) * ring;
        tiepoints::Stats stats;
        st = extractor_.run(Span<const NetworkStation>(stations.data() + first, ring),
                            Span<const StationImages>(images.data() + first, ring), &stats);
        const Span<const TieObservation> found = extractor_.observations();
        if (st.isOk() && observation_count_ + found.size() > static_cast<std::size_t>(config_.max_observations)) {
            st = Status(StatusCode::kOutOfMemory, "tiepoints: the rings' observations exceed max_observations",
                        static_cast<std::int64_t>(observation_count_ + found.size()));
        }
        for (std::size_t i = 0U; st.isOk() && i < found.size(); ++i) {
            TieObservation o = found[i];
            o.image.station = static_cast<std::uint16_t>(first + o.image.station);
            o.point = p.points + o.point;
            observations_[observation_count_] = o;
            ++observation_count_;
        }
        if (st.isOk()) {
            p.points += extractor_.pointCount();
            p.tiepoints.features += stats.features;
            p.tiepoints.intra_ties += stats.intra_ties;
            p.tiepoints.inter_ties += stats.inter_ties;
            p.tiepoints.points += stats.points;
            p.tiepoints.observations += stats.observations;
        }
    }
    if (st.isOk() && p.points == 0U) {
        st = Status(StatusCode::kNoData, "tiepoints: no tie point in any ring");
    }
    return finish(Stage::kTiePoints, st, st.isOk() ? static_cast<std::int64_t>(p.points) : 0, t0);
}

Status PanoramaMapper::runBundle(Span<const NetworkStation> stations) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    PanoramaProducts& p = products_;
    p.bundle = bundle::BundleResult{};
    const Status st = adjuster_.adjust(stations, Span<const TieObservation>(observations_, observation_count_), p.points,
                                       p.bundle);
    if (st.isOk()) {
        const Span<const bundle::StationSolution> solved = adjuster_.stations();
        for (std::size_t s = 0U; s < stations.size(); ++s) {
            adjusted_[s] = stations[s];
            adjusted_[s].site_from_a = solved[s].site_from_a;
        }
    }
    const auto milli_px = static_cast<std::int64_t>(std::floor(1000.0 * p.bundle.rms_after_px + 0.5));
    return finish(Stage::kBundle, st, st.isOk() ? milli_px : 0, t0);
}

// The station's adjusted tie points seen in its left image, projected into the rectified
// pair: (x, y, disparity) samples of the plane the coarse search follows. False (no
// surface) with fewer than three or when the fit refuses.
bool PanoramaMapper::planeOf(std::size_t s, const rectify::RectifiedPair& pair) noexcept {
    const RigidPose& pose = adjusted_[s].site_from_a;
    const Span<const bundle::PointSolution> points = adjuster_.points();
    const double fx = pair.model_a.fx_px;
    const double fy = pair.model_a.fy_px;
    const double w = static_cast<double>(pair.model_a.width_px);
    const double h = static_cast<double>(pair.model_a.height_px);
    std::size_t n = 0U;
    for (std::size_t i = 0U; i < observation_count_ && n < static_cast<std::size_t>(kMaxPlaneSamples); ++i) {
        const TieObservation& o = observations_[i];
        if (o.image.station != s || o.image.eye != Eye::kLeft || points[o.point].state != bundle::PointState::kAdjusted) {
            continue;
        }
        const Vec3 in_a = pose.R.transpose() * (points[o.point].position_m - pose.t_m);
        const Vec3 r = pair.R_rect_from_a * (in_a - pair.centre_a_ref_m);
        if (!(r.z() > 1e-3)) {
            continue;
        }
        const double x = fx * r.x() / r.z() + pair.model_a.cx_px;
        const double y = fy * r.y() / r.z() + pair.model_a.cy_px;
        const double xb = fx * (r.x() - pair.centre_b_rect_m.x()) / r.z() + pair.model_b.cx_px;
        if (x < 0.0 || y < 0.0 || x > w - 1.0 || y > h - 1.0) {
            continue;
        }
        plane_samples_[n] = Vec3(x, y, x - xb);
        ++n;
    }
    stereo::DisparityPlane plane;
    if (n < 3U || !stereo::fitDisparityPlane(Span<const Vec3>(plane_samples_, n),
                                             Span<double>(plane_scratch_, static_cast<std::size_t>(kMaxPlaneSamples)),
                                             plane)
                       .isOk()) {
        return false;
    }
    constexpr std::int32_t kLimit = 2047;
    const std::int32_t lo = pair.d_min > -kLimit ? pair.d_min : -kLimit;
    const std::int32_t hi = pair.d_max < kLimit ? pair.d_max : kLimit;
    return lo <= hi && stereo::fillDisparityPlane(plane, lo, hi, surface_).isOk();
}

// One station: rectify the calibrated pair, dense disparities, points with the adjusted
// pose, into the sample grid.
Status PanoramaMapper::denseStation(std::size_t s, const StationImages& images) noexcept {
    PanoramaProducts& p = products_;
    rectify::RectifyInput in;
    in.pair = adjusted_[s].rig;
    rectify::RectifiedPair pair;
    VTM_RETURN_IF_ERROR(rectifier_.compute(in, pair));
    const std::int32_t w = pair.model_a.width_px;
    const std::int32_t h = pair.model_a.height_px;
    const ImageView<std::uint8_t> left(rect_left_.data(), w, h);
    const ImageView<std::uint8_t> right(rect_right_.data(), w, h);
    VTM_RETURN_IF_ERROR(rectifier_.remap(rectify::Rectifier::Side::kA, images.left, left));
    VTM_RETURN_IF_ERROR(rectifier_.remap(rectify::Rectifier::Side::kB, images.right, right));
    terrain::RectifiedGeometry geometry;
    VTM_RETURN_IF_ERROR(terrain::rectifiedGeometry(pair, adjusted_[s].site_from_a, geometry));
    surface_ = ImageView<std::int16_t>(surface_.data(), w, h);
    const bool plane = planeOf(s, pair);
    p.plane_stations += plane ? 1 : 0;
    const ImageView<std::int16_t> disparity(disparity_.data(), w, h);
    const ImageView<float> sigma(sigma_.data(), w, h);
    const stereo::DisparityOutput out{disparity, sigma, {}};
    VTM_RETURN_IF_ERROR(stereo_.compute(left, right, plane ? ImageView<const std::int16_t>(surface_)
                                                           : ImageView<const std::int16_t>(),
                                        pair.d_min, pair.d_max, out));
    terrain::TriangulationStats stats;
    VTM_RETURN_IF_ERROR(terrain::triangulate(geometry, limitsOf(config_), disparity, sigma, points_, stats));
    p.dense_points += stats.points;
    p.dense_stations += stats.points > 0 ? 1 : 0;
    binPoints(Span<const terrain::TerrainPoint>(points_.data(), static_cast<std::size_t>(stats.points)),
              geometry.left_centre_site_m);
    return Status::ok();
}

// Sums per sample cell (points outside the grid, too uncertain or too far are left out).
void PanoramaMapper::binPoints(Span<const terrain::TerrainPoint> points, const Vec3& eye_m) noexcept {
    const terrain::GridConfig& g = sample_grid_;
    const double max_range2 = config_.dense_range_max_m * config_.dense_range_max_m;
    for (std::size_t i = 0U; i < points.size(); ++i) {
        const terrain::TerrainPoint& q = points[i];
        const double col = std::floor((static_cast<double>(q.y_m) - g.west_edge_m) / g.cell_m);
        const double row = std::floor((g.north_edge_m - static_cast<double>(q.x_m)) / g.cell_m);
        if (!(col >= 0.0 && col < g.cols && row >= 0.0 && row < g.rows) ||
            !(static_cast<double>(q.sigma_range_m) <= config_.max_point_sigma_m) ||
            !((Vec3(q.x_m, q.y_m, q.z_m) - eye_m).squaredNorm() <= max_range2)) {
            continue;  // also NaN
        }
        SampleCell& c = cells_[static_cast<std::size_t>(row) * static_cast<std::size_t>(g.cols) +
                               static_cast<std::size_t>(col)];
        c.north_m += static_cast<double>(q.x_m);
        c.east_m += static_cast<double>(q.y_m);
        c.down_m += static_cast<double>(q.z_m);
        c.lowest_down_m = c.count == 0U || q.z_m > c.lowest_down_m ? q.z_m : c.lowest_down_m;
        c.highest_down_m = c.count == 0U || q.z_m < c.highest_down_m ? q.z_m : c.highest_down_m;
        ++c.count;
    }
}

// Every station into the sample grid; the cells that pass become samples.
Status PanoramaMapper::runDense(Span<const StationImages> images) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    PanoramaProducts& p = products_;
    for (std::size_t i = 0U; i < cells_.size(); ++i) {
        cells_[i] = SampleCell{0.0, 0.0, 0.0, 0.0F, 0.0F, 0U};
    }
    Status st = Status::ok();
    for (std::size_t s = 0U; st.isOk() && s < images.size(); ++s) {
        st = denseStation(s, images[s]);
    }
    const auto min_points = static_cast<std::uint32_t>(config_.min_cell_points);
    for (std::size_t i = 0U; st.isOk() && i < cells_.size(); ++i) {
        const SampleCell& c = cells_[i];
        const double spread = static_cast<double>(c.lowest_down_m) - static_cast<double>(c.highest_down_m);
        if (c.count < min_points || !(spread <= config_.max_cell_spread_m)) {
            continue;
        }
        const double n = static_cast<double>(c.count);
        samples_[sample_count_] = Vec3(c.north_m / n, c.east_m / n, c.down_m / n);
        ++sample_count_;
    }
    p.dense_samples = static_cast<std::int32_t>(sample_count_);
    return finish(Stage::kDense, st, st.isOk() ? p.dense_samples : 0, t0);
}

// The dense samples checked against the tie points (dense_gate_m): the tie points kriged
// alone (their own variogram) at each dense sample; one that differs by more than the gate
// is dropped (a wrong match, e.g. sky matched near). A sample without a tie point within
// the search radius is kept. The kept samples and the tie points are compacted in place.
Status PanoramaMapper::gateDenseSamples() noexcept {
    PanoramaProducts& p = products_;
    const auto dense = static_cast<std::size_t>(p.dense_samples);
    const auto ties = static_cast<std::size_t>(p.tie_samples);
    if (config_.dense_gate_m <= 0.0 || dense == 0U || ties < static_cast<std::size_t>(config_.kriging.min_samples)) {
        return Status::ok();
    }
    VTM_RETURN_IF_ERROR(kriging_.setSamples(Span<const Vec3>(samples_ + dense, ties)));
    kriging::Variogram v;
    VTM_RETURN_IF_ERROR(kriging_.fitVariogram(v));
    std::size_t kept = 0U;
    for (std::size_t i = 0U; i < dense; ++i) {
        kriging::NodeEstimate e;
        VTM_RETURN_IF_ERROR(kriging_.estimateAt(samples_[i].x(), samples_[i].y(), v, e));
        if (e.reason == kriging::NodeReason::kEstimated && !(std::fabs(-samples_[i].z() - e.elevation_m) <= config_.dense_gate_m)) {
            continue;
        }
        samples_[kept] = samples_[i];
        ++kept;
    }
    for (std::size_t i = 0U; i < ties; ++i) {
        samples_[kept + i] = samples_[dense + i];
    }
    p.dense_rejected = static_cast<std::int32_t>(dense - kept);
    p.dense_samples = static_cast<std::int32_t>(kept);
    sample_count_ = kept + ties;
    return Status::ok();
}

// The adjusted tie points inside the grid join the samples; the variogram fitted to them;
// every node kriged.
Status PanoramaMapper::runKrige() noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    PanoramaProducts& p = products_;
    const terrain::GridConfig& g = config_.kriging.grid;
    const double south = g.north_edge_m - g.cell_m * g.rows;
    const double east = g.west_edge_m + g.cell_m * g.cols;
    const Span<const bundle::PointSolution> points = adjuster_.points();
    for (std::size_t i = 0U; i < points.size(); ++i) {
        const Vec3& x = points[i].position_m;
        if (points[i].state == bundle::PointState::kAdjusted && x.x() < g.north_edge_m && x.x() >= south &&
            x.y() >= g.west_edge_m && x.y() < east) {
            samples_[sample_count_] = x;
            ++sample_count_;
        }
    }
    p.tie_samples = static_cast<std::int32_t>(sample_count_) - p.dense_samples;
    p.kriging = kriging::KrigingStats{};
    Status st = gateDenseSamples();
    if (st.isOk()) {
        st = kriging_.setSamples(Span<const Vec3>(samples_, sample_count_));
    }
    if (st.isOk()) {
        st = kriging_.fitVariogram(p.variogram);
    }
    if (st.isOk()) {
        st = kriging_.krigeGrid(p.variogram, &p.kriging);
    }
    return finish(Stage::kKrige, st, st.isOk() ? p.kriging.estimated : 0, t0);
}

Status PanoramaMapper::runOrthophoto(Span<const StationImages> images) noexcept {
    const std::uint64_t t0 = clock_->monotonicNs();
    PanoramaProducts& p = products_;
    p.ortho = kriging::OrthophotoStats{};
    const Status st = kriging::buildOrthophoto(config_.orthophoto, kriging_.map().grid(), kriging_.map().elevations(),
                                               Span<const NetworkStation>(adjusted_, images.size()), images, ortho_,
                                               source_, &p.ortho);
    return finish(Stage::kOrthophoto, st, st.isOk() ? p.ortho.filled : 0, t0);
}

Status PanoramaMapper::map(Span<const NetworkStation> stations, Span<const StationImages> images) noexcept {
    published_ = false;
    stages_.clear();
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PanoramaMapper::map: init() has not succeeded");
    }
    PanoramaProducts& p = products_;
    p.dense_points = 0;
    p.dense_stations = 0;
    p.plane_stations = 0;
    p.dense_samples = 0;
    p.dense_rejected = 0;
    p.tie_samples = 0;
    sample_count_ = 0U;
    VTM_RETURN_IF_ERROR(runTiePoints(stations, images));
    VTM_RETURN_IF_ERROR(runBundle(stations));
    if (config_.dense_stereo) {
        VTM_RETURN_IF_ERROR(runDense(images));
    }
    VTM_RETURN_IF_ERROR(runKrige());
    VTM_RETURN_IF_ERROR(runOrthophoto(images));
    p.adjusted = Span<const NetworkStation>(adjusted_, stations.size());
    p.stations = adjuster_.stations();
    p.observations = Span<const TieObservation>(observations_, observation_count_);
    p.tie_points = adjuster_.points();
    p.residuals = adjuster_.residuals();
    p.samples = Span<const Vec3>(samples_, sample_count_);
    p.elevation = &kriging_.map();
    p.orthophoto = ortho_;
    p.source = source_;
    published_ = true;
    return Status::ok();
}

}  // namespace vtm::app
