// Configuration checks, the workspace formula and init() of the entropy registration.
#include "vtm/core/config_check.hpp"
#include "vtm/entropy/registration.hpp"

#include "equalise.hpp"

#include <cmath>

namespace vtm::entropy {
namespace {

bool inUnitInterval(double v, bool zeroAllowed) noexcept {
    return std::isfinite(v) && v <= 1.0 && (zeroAllowed ? v >= 0.0 : v > 0.0);
}

// The entropy configuration the registration runs: the capacity is the registration's.
EntropyConfig entropyOf(const RegistrationConfig& c) noexcept {
    EntropyConfig e = c.entropy;
    e.max_width = c.max_width;
    e.max_height = c.max_height;
    return e;
}

// Pixels of one pyramid: level l holds (max_width >> l) x (max_height >> l).
std::size_t pyramidPixels(const RegistrationConfig& c) noexcept {
    std::size_t n = 0U;
    for (std::int32_t l = 0; l < c.levels; ++l) {
        n += static_cast<std::size_t>(c.max_width >> l) * static_cast<std::size_t>(c.max_height >> l);
    }
    return n;
}

// Pixels of the warped coarse level: image 1's coarse grid widened by the shift margin.
std::size_t warpPixels(const RegistrationConfig& c) noexcept {
    const std::int32_t margin = (c.max_shift_steps - 1) / 2;
    const std::int32_t coarse = c.levels - 1;
    return static_cast<std::size_t>((c.max_width >> coarse) + 2 * margin) *
           static_cast<std::size_t>((c.max_height >> coarse) + 2 * margin);
}

std::size_t imagePixels(const RegistrationConfig& c) noexcept {
    return static_cast<std::size_t>(c.max_width) * static_cast<std::size_t>(c.max_height);
}

// Coarse shifts scored per rotation and scale.
std::size_t shiftCount(const RegistrationConfig& c) noexcept {
    return static_cast<std::size_t>(c.max_shift_steps) * static_cast<std::size_t>(c.max_shift_steps);
}

}  // namespace

Status RegistrationConfig::validate() const noexcept {
    if (max_width < 16 || max_width > 4096) {
        return invalidConfig("registration.max_width: must be 16..4096 px", max_width);
    }
    if (max_height < 16 || max_height > 4096) {
        return invalidConfig("registration.max_height: must be 16..4096 px", max_height);
    }
    VTM_RETURN_IF_ERROR(entropyOf(*this).validate());
    if (representation != Representation::kEntropy && representation != Representation::kIntensity) {
        return invalidConfig("registration.representation: unknown value (kEntropy or kIntensity)",
                       static_cast<std::int64_t>(representation));
    }
    if (fill_max_grey < -1 || fill_max_grey > 254) {
        return invalidConfig("registration.fill_max_grey: must be -1 (none) .. 254", fill_max_grey);
    }
    static_assert(kMaxEqualiseRadius <= detail::kMaxRankRadius, "the local rank's counts bound the radius");
    if (equalise_radius_px < 0 || equalise_radius_px > kMaxEqualiseRadius) {
        return invalidConfig("registration.equalise_radius_px: must be 0 (whole image) .. 63", equalise_radius_px);
    }
    if (levels < 1 || levels > kMaxLevels) {
        return invalidConfig("registration.levels: must be 1..6", levels);
    }
    if ((max_width >> (levels - 1)) < 8 || (max_height >> (levels - 1)) < 8) {
        return invalidConfig("registration.levels: the coarse level of max_width x max_height is below 8 px", levels);
    }
    if (max_angle_steps < 1 || max_angle_steps > 1024) {
        return invalidConfig("registration.max_angle_steps: must be 1..1024", max_angle_steps);
    }
    if (max_scale_steps < 1 || max_scale_steps > 256) {
        return invalidConfig("registration.max_scale_steps: must be 1..256", max_scale_steps);
    }
    if (max_shift_steps < 1 || max_shift_steps > 129 || (max_shift_steps % 2) != 1) {
        return invalidConfig("registration.max_shift_steps: must be odd, 1..129", max_shift_steps);
    }
    if (candidates < 1 || candidates > kMaxCandidates) {
        return invalidConfig("registration.candidates: must be 1..16", candidates);
    }
    if (refine_rounds < 1 || refine_rounds > 64) {
        return invalidConfig("registration.refine_rounds: must be 1..64", refine_rounds);
    }
    if (!inUnitInterval(min_overlap, false)) {
        return invalidConfig("registration.min_overlap: must be in (0, 1] (fraction of image 1)", 0);
    }
    if (!inUnitInterval(min_ncc, true)) {
        return invalidConfig("registration.min_ncc: must be in [0, 1]", 0);
    }
    if (!inUnitInterval(max_peak_ratio, false)) {
        return invalidConfig("registration.max_peak_ratio: must be in (0, 1]", 0);
    }
    return Status::ok();
}

std::size_t EntropyRegistration::workspaceBytes(const RegistrationConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    // Term by term, in the order init() carves them.
    return LocalEntropy::workspaceBytes(entropyOf(config))                  // entropy histograms, table
           + 2U * Arena::arrayBytes<std::uint8_t>(pyramidPixels(config))    // pyramids of images 1 and 2
           + 2U * Arena::arrayBytes<std::uint8_t>(pyramidPixels(config))    // their data masks
           + Arena::arrayBytes<std::uint8_t>(imagePixels(config))           // equalised image
           + Arena::arrayBytes<std::uint16_t>(detail::kRankCounts)          // local rank's counts
           + Arena::arrayBytes<std::int16_t>(warpPixels(config))            // warped coarse level
           + Arena::arrayBytes<double>(shiftCount(config));                 // scores of the coarse shifts
}

Status EntropyRegistration::init(const RegistrationConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const Status entropy = entropy_.init(entropyOf(config), arena);
    if (entropy.code() == StatusCode::kOutOfMemory) {
        return Status(StatusCode::kOutOfMemory,
                      "EntropyRegistration::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    VTM_RETURN_IF_ERROR(entropy);
    pyramid1_ = arena.allocateArray<std::uint8_t>(pyramidPixels(config));
    pyramid2_ = arena.allocateArray<std::uint8_t>(pyramidPixels(config));
    maskPyramid1_ = arena.allocateArray<std::uint8_t>(pyramidPixels(config));
    maskPyramid2_ = arena.allocateArray<std::uint8_t>(pyramidPixels(config));
    scratch_ = arena.allocateArray<std::uint8_t>(imagePixels(config));
    rankCounts_ = arena.allocateArray<std::uint16_t>(detail::kRankCounts);
    warp_ = arena.allocateArray<std::int16_t>(warpPixels(config));
    shiftScores_ = arena.allocateArray<double>(shiftCount(config));
    if (pyramid1_.empty() || pyramid2_.empty() || maskPyramid1_.empty() || maskPyramid2_.empty() || scratch_.empty() || rankCounts_.empty() || warp_.empty() || shiftScores_.empty()) {
        return Status(StatusCode::kOutOfMemory,
                      "EntropyRegistration::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    for (std::int32_t l = 0; l < kMaxLevels; ++l) {
        levels1_[l] = ImageView<std::uint8_t>();
        levels2_[l] = ImageView<std::uint8_t>();
        masks1_[l] = ImageView<std::uint8_t>();
        masks2_[l] = ImageView<std::uint8_t>();
    }
    candidateCount_ = 0;
    initialized_ = true;
    return Status::ok();
}

}  // namespace vtm::entropy
