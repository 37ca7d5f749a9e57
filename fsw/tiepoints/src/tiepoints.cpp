// The tie-point run (tiepoints.hpp): intra-stereo per station, inter-stereo per adjacent pair.
#include "vtm/tiepoints/tiepoints.hpp"

#include "geometry.hpp"
#include "vtm/core/math.hpp"
#include "workspace.hpp"

namespace vtm::tiepoints {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;

std::int32_t imageKey(ImageRef r) noexcept {
    return 2 * static_cast<std::int32_t>(r.station) + (r.eye == Eye::kRight ? 1 : 0);
}

Vec3 upIn(const RigidPose& site_from_cam) noexcept { return site_from_cam.R.transpose() * Vec3(0.0, 0.0, -1.0); }

bool sizeIs(const ImageView<const std::uint8_t>& image, const CameraModel& model) noexcept {
    return image.width() == static_cast<std::int32_t>(model.width_px) &&
           image.height() == static_cast<std::int32_t>(model.height_px);
}

}  // namespace

Span<const TieObservation> TiePointExtractor::observations() const noexcept {
    return Span<const TieObservation>(observations_.data(), static_cast<std::size_t>(observationCount_));
}

Span<const PairCount> TiePointExtractor::pairCounts() const noexcept {
    return Span<const PairCount>(pairs_.data(), static_cast<std::size_t>(pairCount_));
}

void TiePointExtractor::reset() noexcept {
    observationCount_ = 0;
    pairCount_ = 0;
    points_ = 0U;
    for (std::size_t k = 0U; k < pointId_.size(); ++k) {
        pointId_[k] = -1;
        hasStereo_[k] = 0U;
    }
    for (std::size_t k = 0U; k < featureCount_.size(); ++k) {
        featureCount_[k] = 0;
    }
}

Status TiePointExtractor::checkInput(Span<const NetworkStation> stations, Span<const StationImages> images) const noexcept {
    if (stations.empty() || stations.size() > static_cast<std::size_t>(config_.max_stations)) {
        return Status(StatusCode::kInvalidArgument, "stations: count must be 1..max_stations",
                      static_cast<std::int64_t>(stations.size()));
    }
    if (images.size() != stations.size()) {
        return Status(StatusCode::kInvalidArgument, "images: count differs from stations'",
                      static_cast<std::int64_t>(images.size()));
    }
    for (std::size_t s = 0U; s < stations.size(); ++s) {
        const auto detail = static_cast<std::int64_t>(s);
        if (!validateNetworkStation(stations[s]).isOk()) {
            return Status(StatusCode::kInvalidArgument, "stations[i]: invalid (validateNetworkStation)", detail);
        }
        const StationImages& im = images[s];
        if (im.left.data() == nullptr || im.right.data() == nullptr || im.left.width() <= 0 ||
            im.right.width() <= 0 || im.left.height() <= 0 || im.right.height() <= 0) {
            return Status(StatusCode::kInvalidArgument, "images[i]: an empty left or right image", detail);
        }
        if (!sizeIs(im.left, stations[s].rig.model_a) || !sizeIs(im.right, stations[s].rig.model_b)) {
            return Status(StatusCode::kSizeMismatch, "images[i]: size differs from the rig's camera model", detail);
        }
        if (im.left.width() > config_.max_width || im.left.height() > config_.max_height ||
            im.right.width() > config_.max_width || im.right.height() > config_.max_height) {
            return Status(StatusCode::kSizeMismatch, "images[i]: larger than max_width x max_height", detail);
        }
    }
    return Status::ok();
}

Status TiePointExtractor::newPoint(std::uint32_t& id) noexcept {
    if (static_cast<std::size_t>(points_) >= sightingCount_.size()) {
        return Status(StatusCode::kOutOfMemory, "observations: capacity full (max_observations)",
                      config_.max_observations);
    }
    id = points_;
    sightingCount_[id] = 0U;
    ++points_;
    return Status::ok();
}

// Appends one observation and counts the new image pairs it forms with the point's
// earlier sightings.
Status TiePointExtractor::addObservation(ImageRef image, std::uint32_t point, const Vec2& pixel) noexcept {
    if (observationCount_ >= config_.max_observations || sightingCount_[point] >= detail::kMaxSightings) {
        return Status(StatusCode::kOutOfMemory, "observations: capacity full (max_observations)",
                      config_.max_observations);
    }
    TieObservation& o = observations_[static_cast<std::size_t>(observationCount_)];
    o.image = image;
    o.point = point;
    o.pixel_px = pixel;
    ++observationCount_;
    ImageRef* seen = &sightings_[static_cast<std::size_t>(point) * detail::kMaxSightings];
    for (std::uint8_t k = 0U; k < sightingCount_[point]; ++k) {
        ImageRef a = seen[k];
        ImageRef b = image;
        if (imageKey(a) > imageKey(b)) {
            const ImageRef t = a;
            a = b;
            b = t;
        }
        std::int32_t slot = 0;
        for (; slot < pairCount_; ++slot) {
            const PairCount& p = pairs_[static_cast<std::size_t>(slot)];
            if (imageKey(p.a) == imageKey(a) && imageKey(p.b) == imageKey(b)) {
                break;
            }
        }
        if (slot == pairCount_) {
            if (static_cast<std::size_t>(pairCount_) >= pairs_.size()) {
                return Status(StatusCode::kOutOfMemory, "pair counts: capacity full (5 x max_stations)", pairCount_);
            }
            pairs_[static_cast<std::size_t>(slot)] = PairCount{a, b, 0};
            ++pairCount_;
        }
        ++pairs_[static_cast<std::size_t>(slot)].count;
    }
    seen[sightingCount_[point]] = image;
    ++sightingCount_[point];
    return Status::ok();
}

Status TiePointExtractor::run(Span<const NetworkStation> stations, Span<const StationImages> images,
                              Stats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "TiePointExtractor::run: init() first");
    }
    reset();
    Stats st;
    Status status = checkInput(stations, images);
    const auto n = static_cast<std::int32_t>(stations.size());
    for (std::int32_t s = 0; status.isOk() && s < n; ++s) {
        status = intraStation(s, stations[static_cast<std::size_t>(s)], images[static_cast<std::size_t>(s)], st);
    }
    const std::int32_t pairs = (config_.closed_panorama && n > 2) ? n : n - 1;
    for (std::int32_t p = 0; status.isOk() && p < pairs; ++p) {
        status = interPair(p, (p + 1) % n, stations, images, st);
    }
    if (!status.isOk()) {
        reset();
        return status;
    }
    st.points = static_cast<std::int32_t>(points_);
    st.observations = observationCount_;
    if (stats != nullptr) {
        *stats = st;
    }
    return Status::ok();
}

Status TiePointExtractor::intraStation(std::int32_t s, const NetworkStation& station, const StationImages& images,
                                       Stats& stats) noexcept {
    VTM_RETURN_IF_ERROR(detector_.detect(images.left, *detected_));
    if (detected_->count == 0) {
        return Status(StatusCode::kDegenerate, "images[i].left: no texture (no Förstner point)", s);
    }
    stats.features += detected_->count;
    const std::size_t base = static_cast<std::size_t>(s) * static_cast<std::size_t>(config_.detector.max_features);
    for (std::int32_t k = 0; k < detected_->count; ++k) {
        features_[base + static_cast<std::size_t>(k)] = detected_->items[k];
    }
    featureCount_[static_cast<std::size_t>(s)] = detected_->count;

    features::MatchPrediction prediction;
    prediction.pair = station.rig;
    prediction.range_min_m = config_.range_min_m;
    prediction.range_max_m = config_.range_max_m;
    prediction.margin_px = config_.rig_margin_px;
    prediction.surface_normal_a = upIn(station.site_from_a);
    VTM_RETURN_IF_ERROR(matcher_.match(images.left, images.right, *detected_, prediction, *matches_));
    const Span<const features::Match> matches(matches_->items, static_cast<std::size_t>(matches_->count));
    stats.intra_matched += matches_->count;
    VTM_RETURN_IF_ERROR(checkParallax(matches, config_.parallax, keep_));

    const RigidPose right_pose = siteFromEye(station, Eye::kRight);
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        detail::SiteRay ra;
        detail::SiteRay rb;
        Vec3 point = Vec3::Zero();
        if (keep_[k] == 0U) {
            continue;
        }
        ++stats.intra_consistent;
        if (detail::siteRay(station.rig.model_a, station.site_from_a, matches[k].pixel_a, ra) &&
            detail::siteRay(station.rig.model_b, right_pose, matches[k].pixel_b, rb) &&
            detail::midpoint(ra, rb, point)) {
            const std::size_t slot = base + static_cast<std::size_t>(matches[k].feature_index);
            stereo_[slot] = point;
            hasStereo_[slot] = 1U;
        }
    }
    std::int32_t kept = 0;
    VTM_RETURN_IF_ERROR(thinByGrid(matches, config_.intra_grid, images.left.width(), images.left.height(), keep_, kept));
    const auto station_id = static_cast<std::uint16_t>(s);
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        if (keep_[k] == 0U) {
            continue;
        }
        std::uint32_t id = 0U;
        VTM_RETURN_IF_ERROR(newPoint(id));
        pointId_[base + static_cast<std::size_t>(matches[k].feature_index)] = static_cast<std::int32_t>(id);
        VTM_RETURN_IF_ERROR(addObservation(ImageRef{station_id, Eye::kLeft}, id, matches[k].pixel_a));
        VTM_RETURN_IF_ERROR(addObservation(ImageRef{station_id, Eye::kRight}, id, matches[k].pixel_b));
        ++stats.intra_ties;
    }
    return Status::ok();
}

void TiePointExtractor::buildMap(std::int32_t i, std::int32_t j, Span<const NetworkStation> stations) noexcept {
    const Vec3 centre = 0.5 * (stations[static_cast<std::size_t>(i)].site_from_a.t_m +
                               stations[static_cast<std::size_t>(j)].site_from_a.t_m);
    terrain::GridConfig g;
    g.cell_m = config_.map_cell_m;
    g.cols = config_.map_side;
    g.rows = config_.map_side;
    const double half = 0.5 * config_.map_cell_m * static_cast<double>(config_.map_side);
    g.north_edge_m = centre.x() + half;
    g.west_edge_m = centre.y() - half;
    (void)map_.setGrid(g);  // the init grid's size: cannot be refused
    const std::int32_t stations_of_pair[2] = {i, j};
    for (const std::int32_t s : stations_of_pair) {
        const std::size_t base = static_cast<std::size_t>(s) * static_cast<std::size_t>(config_.detector.max_features);
        for (std::int32_t k = 0; k < featureCount_[static_cast<std::size_t>(s)]; ++k) {
            if (hasStereo_[base + static_cast<std::size_t>(k)] != 0U) {
                (void)map_.add(stereo_[base + static_cast<std::size_t>(k)]);  // initialised: cannot fail
            }
        }
    }
}

// Ground point of feature k of station i: its stereo point, else its left ray cast onto the map.
bool TiePointExtractor::groundOf(std::int32_t i, std::int32_t k, const NetworkStation& station,
                                 Vec3& site_m) const noexcept {
    const std::size_t slot = static_cast<std::size_t>(i) * static_cast<std::size_t>(config_.detector.max_features) +
                             static_cast<std::size_t>(k);
    if (hasStereo_[slot] != 0U) {
        site_m = stereo_[slot];
        return true;
    }
    detail::SiteRay ray;
    double range = 0.0;
    if (!detail::siteRay(station.rig.model_a, station.site_from_a, features_[slot].pixel, ray) ||
        !detail::castOnMap(map_, ray, config_.range_min_m, config_.range_max_m, config_.ray_steps,
                           config_.map_fill_radius, range)) {
        return false;
    }
    site_m = ray.origin + range * ray.direction;
    return true;
}

Status TiePointExtractor::interPair(std::int32_t i, std::int32_t j, Span<const NetworkStation> stations,
                                    Span<const StationImages> images, Stats& stats) noexcept {
    buildMap(i, j, stations);
    VTM_RETURN_IF_ERROR(interEye(i, j, Eye::kLeft, stations, images, stats));
    return interEye(i, j, Eye::kRight, stations, images, stats);
}

Status TiePointExtractor::interEye(std::int32_t i, std::int32_t j, Eye eye, Span<const NetworkStation> stations,
                                   Span<const StationImages> images, Stats& stats) noexcept {
    VTM_RETURN_IF_ERROR(searchEye(i, j, eye, stations, images, stats));
    const Span<const features::Match> matches(matches_->items, static_cast<std::size_t>(matches_->count));
    stats.inter_matched += matches_->count;
    ParallaxStats ps;
    VTM_RETURN_IF_ERROR(checkParallax(matches, config_.parallax, keep_, &ps));
    stats.inter_consistent += ps.consistent;
    std::int32_t kept = 0;
    const ImageView<const std::uint8_t>& image_a = images[static_cast<std::size_t>(i)].left;
    VTM_RETURN_IF_ERROR(thinByGrid(matches, config_.inter_grid, image_a.width(), image_a.height(), keep_, kept));
    const std::size_t base = static_cast<std::size_t>(i) * static_cast<std::size_t>(config_.detector.max_features);
    for (std::size_t k = 0U; k < matches.size(); ++k) {
        if (keep_[k] == 0U) {
            continue;
        }
        const std::size_t slot = base + static_cast<std::size_t>(matches[k].feature_index);
        if (pointId_[slot] < 0) {
            std::uint32_t id = 0U;
            VTM_RETURN_IF_ERROR(newPoint(id));
            pointId_[slot] = static_cast<std::int32_t>(id);
            VTM_RETURN_IF_ERROR(addObservation(ImageRef{static_cast<std::uint16_t>(i), Eye::kLeft}, id,
                                               matches[k].pixel_a));
        }
        VTM_RETURN_IF_ERROR(addObservation(ImageRef{static_cast<std::uint16_t>(j), eye},
                                           static_cast<std::uint32_t>(pointId_[slot]), matches[k].pixel_b));
        ++stats.inter_ties;
    }
    return Status::ok();
}

// Guided NCC search of every Förstner point of i's left image in eye `eye` of j, one point
// at a time (each has its own range band and margin) against pyramids built once; the
// matches go to matches_ (feature_index = the point's index in station i).
Status TiePointExtractor::searchEye(std::int32_t i, std::int32_t j, Eye eye, Span<const NetworkStation> stations,
                                    Span<const StationImages> images, Stats& stats) noexcept {
    const NetworkStation& si = stations[static_cast<std::size_t>(i)];
    const NetworkStation& sj = stations[static_cast<std::size_t>(j)];
    const ImageView<const std::uint8_t>& image_a = images[static_cast<std::size_t>(i)].left;
    const ImageView<const std::uint8_t>& image_b =
        eye == Eye::kLeft ? images[static_cast<std::size_t>(j)].left : images[static_cast<std::size_t>(j)].right;
    const CameraModel& model_b = modelOfEye(sj, eye);
    const RigidPose pose_b = siteFromEye(sj, eye);
    const double ppr = detail::pixelsPerRadian(model_b);
    const double border = 0.5 * static_cast<double>(config_.matcher.template_window) + 1.0;
    features::MatchPrediction prediction;
    prediction.pair.model_a = si.rig.model_a;
    prediction.pair.model_b = model_b;
    prediction.pair.b_from_a = relativePose(si.site_from_a, pose_b);
    prediction.surface_normal_a = upIn(si.site_from_a);
    const std::size_t base = static_cast<std::size_t>(i) * static_cast<std::size_t>(config_.detector.max_features);
    matches_->count = 0;
    VTM_RETURN_IF_ERROR(matcher_.prepare(image_a, image_b));  // the pyramids, once per image pair
    for (std::int32_t k = 0; k < featureCount_[static_cast<std::size_t>(i)]; ++k) {
        Vec3 ground = Vec3::Zero();
        Vec2 predicted = Vec2::Zero();
        if (!groundOf(i, k, si, ground)) {
            ++stats.inter_no_ground;
            continue;
        }
        if (!detail::projectInside(model_b, pose_b, ground, border, predicted)) {
            continue;
        }
        ++stats.inter_predicted;
        const double range = (ground - si.site_from_a.t_m).norm();
        prediction.range_min_m = range / (1.0 + config_.range_band_fraction);
        prediction.range_max_m = range * (1.0 + config_.range_band_fraction);
        prediction.margin_px =
            config_.sigma_multiplier * kSqrt2 * (config_.pointing_sigma_rad + config_.position_sigma_m / range) * ppr;
        single_->items[0] = features_[base + static_cast<std::size_t>(k)];
        single_->count = 1;
        VTM_RETURN_IF_ERROR(matcher_.matchPrepared(*single_, prediction, *found_));
        if (found_->count == 1) {
            matches_->items[matches_->count] = found_->items[0];
            matches_->items[matches_->count].feature_index = k;
            ++matches_->count;
        }
    }
    return Status::ok();
}

}  // namespace vtm::tiepoints
