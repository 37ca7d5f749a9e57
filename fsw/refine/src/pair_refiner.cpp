#include "vtm/refine/pair_refiner.hpp"
#include "vtm/core/config_check.hpp"

#include <cmath>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/math.hpp"
#include "vtm/features/visibility.hpp"

namespace vtm::refine {
namespace {

constexpr std::int32_t kMaxSide = 4096;
// Tolerance of the prior rotation's orthonormality: the motion refiner's.
constexpr double kRotationTolerance = 1e-6;
constexpr double kDegPerRad = 180.0 / math::kPi;
constexpr std::size_t kMatches = static_cast<std::size_t>(features::kMaxFeatures);

Status badRequest(const char* reason, std::int64_t value = 0) noexcept {
    return Status(StatusCode::kInvalidArgument, reason, value);
}

std::size_t pixelsOf(const Config& c) noexcept {
    return static_cast<std::size_t>(c.max_width) * static_cast<std::size_t>(c.max_height);
}

Status checkImage(const ImageView<const std::uint8_t>& image, const CameraModel& model, const Config& c,
                  const char* empty_reason, const char* capacity_reason, const char* model_reason) noexcept {
    if (image.data() == nullptr || image.width() <= 0 || image.height() <= 0) {
        return badRequest(empty_reason);
    }
    if (image.width() > c.max_width || image.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, capacity_reason, image.width());
    }
    if (image.width() != model.width_px || image.height() != model.height_px) {
        return Status(StatusCode::kSizeMismatch, model_reason, model.width_px);
    }
    return Status::ok();
}

}  // namespace

features::DetectorConfig Config::detectorConfig() const noexcept {
    return detector.withCapacity(max_width, max_height);
}

features::MatcherConfig Config::matcherConfig() const noexcept {
    return matcher.withCapacity(max_width, max_height);
}

Status Config::validate() const noexcept {
    if (max_width < 1 || max_width > kMaxSide || max_height < 1 || max_height > kMaxSide) {
        return invalidConfig("refine.max_width/max_height: must be 1..4096", max_width);
    }
    VTM_RETURN_IF_ERROR(detectorConfig().validate());
    VTM_RETURN_IF_ERROR(matcherConfig().validate());
    VTM_RETURN_IF_ERROR(motion.validate());
    if (!isInRange(match_margin_px, 0.0, 1000.0)) {
        return invalidConfig("refine.match_margin_px: must be 0..1000");
    }
    if (!isInRange(visibility_margin_px, 0.0, 1000.0)) {
        return invalidConfig("refine.visibility_margin_px: must be 0..1000");
    }
    if (!(max_rotation_sigma_deg == 0.0 || isInRange(max_rotation_sigma_deg, 0.01, 10.0))) {
        return invalidConfig("refine.max_rotation_sigma_deg: must be 0 (off) or 0.01..10");
    }
    return Status::ok();
}

std::size_t PairRefiner::workspaceBytes(const Config& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    return features::ForstnerDetector::workspaceBytes(config.detectorConfig())  // each module's own plan
           + features::TemplateMatcher::workspaceBytes(config.matcherConfig()) +
           Arena::arrayBytes<std::uint8_t>(pixelsOf(config))  // visibility mask
           + Arena::constructBytes<motion::MotionRefiner>(1U) + Arena::constructBytes<features::FeatureSet>(1U) +
           Arena::constructBytes<features::MatchSet>(1U) + 2U * Arena::constructBytes<Vec2>(kMatches)  // matched pixels a, b
           + Arena::arrayBytes<std::uint8_t>(kMatches)                            // inlier flags
           + Arena::arrayBytes<double>(kMatches);                                 // refined ranges
}

Status PairRefiner::init(const Config& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    VTM_RETURN_IF_ERROR(detector_.init(config.detectorConfig(), arena));
    VTM_RETURN_IF_ERROR(matcher_.init(config.matcherConfig(), arena));
    const Span<std::uint8_t> mask = arena.allocateArray<std::uint8_t>(pixelsOf(config));
    refiner_ = arena.construct<motion::MotionRefiner>(1U);
    features_ = arena.construct<features::FeatureSet>(1U);
    matches_ = arena.construct<features::MatchSet>(1U);
    Vec2* pa = arena.construct<Vec2>(kMatches);
    Vec2* pb = arena.construct<Vec2>(kMatches);
    inliers_ = arena.allocateArray<std::uint8_t>(kMatches);
    ranges_ = arena.allocateArray<double>(kMatches);
    if (mask.empty() || refiner_ == nullptr || features_ == nullptr || matches_ == nullptr || pa == nullptr ||
        pb == nullptr || inliers_.empty() || ranges_.empty()) {
        return Status(StatusCode::kOutOfMemory, "PairRefiner::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    visible_ = ImageView<std::uint8_t>(mask.data(), config.max_width, config.max_height);
    pixels_a_ = Span<Vec2>(pa, kMatches);
    pixels_b_ = Span<Vec2>(pb, kMatches);
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

Status PairRefiner::checkRequest(const Request& request) const noexcept {
    VTM_RETURN_IF_ERROR(checkRigidPose(request.prior.b_from_a, kRotationTolerance,
                                       "Request.prior.b_from_a: R not a rotation (within 1e-6) or t_m not finite"));
    if (request.prior.b_from_a.t_m.dot(request.prior.b_from_a.t_m) == 0.0) {
        return badRequest("Request.prior.b_from_a.t_m: zero baseline (direction undefined)");
    }
    VTM_RETURN_IF_ERROR(validateCameraModel(request.prior.model_a));
    VTM_RETURN_IF_ERROR(validateCameraModel(request.prior.model_b));
    if (!isInRange(request.rotation_sigma_rad, 0.0, math::kPi)) {
        return badRequest("Request.rotation_sigma_rad: must be 0 (none) .. pi, finite");
    }
    if (!(math::isFinite(request.range_min_m) && request.range_min_m > 0.0 && request.range_min_m < request.range_max_m &&
          request.range_max_m <= 1e7)) {
        return badRequest("Request.range_min_m/range_max_m: need 0 < range_min_m < range_max_m <= 1e7 m");
    }
    VTM_RETURN_IF_ERROR(checkImage(request.image_a, request.prior.model_a, config_, "Request.image_a: empty",
                                   "Request.image_a: larger than refine.max_width/max_height",
                                   "Request.image_a: size differs from prior.model_a"));
    VTM_RETURN_IF_ERROR(checkImage(request.image_b, request.prior.model_b, config_, "Request.image_b: empty",
                                   "Request.image_b: larger than refine.max_width/max_height",
                                   "Request.image_b: size differs from prior.model_b"));
    if (request.scene == Scene::kGround) {
        const double n2 = request.up_a.dot(request.up_a);
        if (!(math::isFinite(n2) && n2 > 0.25 && n2 < 4.0)) {
            return badRequest("Request.up_a: the ground scene needs a finite unit vector (norm 0.5..2)");
        }
        if (!(math::isFinite(request.camera_height_m) && request.camera_height_m > 0.0)) {
            return badRequest("Request.camera_height_m: the ground scene needs a height > 0, finite");
        }
    } else if (request.scene != Scene::kGeneral) {
        return badRequest("Request.scene: neither kGround nor kGeneral", static_cast<std::int64_t>(request.scene));
    }
    return Status::ok();
}

// Step 1 (ground scene): A's part that B sees, into the mask; the general scene has none.
Status PairRefiner::maskVisible(const Request& request, const features::MatchPrediction& prediction,
                                Result& result, ImageView<const std::uint8_t>& mask) const noexcept {
    const std::int32_t w = request.image_a.width();
    const std::int32_t h = request.image_a.height();
    if (request.scene != Scene::kGround) {
        result.visible_px = static_cast<std::int64_t>(w) * static_cast<std::int64_t>(h);
        mask = ImageView<const std::uint8_t>();
        return Status::ok();
    }
    features::VisibilityPrior prior;
    prior.up_a = request.up_a;
    prior.camera_height_m = request.camera_height_m;
    prior.margin_px = config_.visibility_margin_px;
    const ImageView<std::uint8_t> visible(visible_.data(), w, h);
    VTM_RETURN_IF_ERROR(features::predictVisibility(prediction, prior, visible, result.visible_px));
    if (result.visible_px == 0) {
        return Status(StatusCode::kDegenerate, "refine: the prior pose says image B sees none of image A");
    }
    mask = visible;
    return Status::ok();
}

// Step 4: the motion from the prior on the matches, and the refined pair.
Status PairRefiner::refineMotion(const Request& request, Result& result) noexcept {
    const std::size_t n = result.pixels_a.size();
    motion::MotionInput input;
    input.pair = request.prior;
    input.pixels_a = result.pixels_a;
    input.pixels_b = result.pixels_b;
    motion::Config mc = config_.motion;
    mc.range_min_m = request.range_min_m;
    mc.range_max_m = request.range_max_m;
    mc.rotation_prior_sigma_rad = request.rotation_sigma_rad;
    VTM_RETURN_IF_ERROR(refiner_->refine(input, mc, result.motion, Span<std::uint8_t>(inliers_.data(), n),
                                         Span<double>(ranges_.data(), n)));
    const motion::MotionResult& m = result.motion;
    result.refined.b_from_a.R = m.R_b_from_a;
    result.refined.b_from_a.t_m = m.t_b_from_a_m;
    result.rotation_change_deg = kDegPerRad * motion::rotationAngleRad(m.R_b_from_a, request.prior.b_from_a.R);
    result.direction_change_deg =
        kDegPerRad * motion::directionAngleRad(m.t_b_from_a_m, request.prior.b_from_a.t_m);
    const double sigma_deg = kDegPerRad * m.rotation_sigma_rad;
    if (config_.max_rotation_sigma_deg > 0.0 && !(sigma_deg <= config_.max_rotation_sigma_deg)) {
        return Status(StatusCode::kDegenerate,
                      "refine: the refined rotation is too uncertain (1-sigma above max_rotation_sigma_deg; "
                      "detail: millidegrees)",
                      math::isFinite(sigma_deg) && sigma_deg < 1e6
                          ? static_cast<std::int64_t>(std::floor(sigma_deg * 1000.0 + 0.5))
                          : -1);
    }
    return Status::ok();
}

Status PairRefiner::refine(const Request& request, Result& result) noexcept {
    result = Result{};
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PairRefiner::refine: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkRequest(request));
    result.refined = request.prior;
    features::MatchPrediction prediction;
    prediction.pair = request.prior;
    prediction.range_min_m = request.range_min_m;
    prediction.range_max_m = request.range_max_m;
    prediction.margin_px = config_.match_margin_px;
    // The ground plane for the template warp, or fronto-parallel (zero).
    prediction.surface_normal_a = request.scene == Scene::kGround ? request.up_a : Vec3::Zero();

    // 1. Visibility (ground scene): A's part that B sees.
    ImageView<const std::uint8_t> mask{};
    VTM_RETURN_IF_ERROR(maskVisible(request, prediction, result, mask));

    // 2. Features of A (inside the visible part).
    VTM_RETURN_IF_ERROR(detector_.detect(request.image_a, *features_, &result.detection, mask));
    result.features = Span<const features::Feature>(features_->items, static_cast<std::size_t>(features_->count));

    // 3. Guided matching into B.
    VTM_RETURN_IF_ERROR(
        matcher_.match(request.image_a, request.image_b, *features_, prediction, *matches_, &result.matching));
    const auto n = static_cast<std::size_t>(matches_->count);
    for (std::size_t i = 0U; i < n; ++i) {
        pixels_a_[i] = matches_->items[i].pixel_a;
        pixels_b_[i] = matches_->items[i].pixel_b;
    }
    result.matches = Span<const features::Match>(matches_->items, n);
    result.pixels_a = Span<const Vec2>(pixels_a_.data(), n);
    result.pixels_b = Span<const Vec2>(pixels_b_.data(), n);
    result.inliers = Span<const std::uint8_t>(inliers_.data(), n);
    result.ranges_m = Span<const double>(ranges_.data(), n);

    // 4. The motion from the prior on the matches.
    return refineMotion(request, result);
}

}  // namespace vtm::refine
