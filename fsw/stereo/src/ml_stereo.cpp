// Orchestration of the ML matcher: workspace, the row stream, the per-row decision.
//
// The pair streams through once, top to bottom. For every template (left) row y' that
// enters the window: the right image's distance transform for row y' (x pass kept for
// rows y'-r..y'+r in a ring, y pass into one row of costs per intensity bin), then the
// per-pixel cost of every column at every disparity, pushed into a ring of the last
// `window` rows while the window column sums are updated (add the new row, subtract
// the row that left). When row y = y' - h is complete, running sums along each row give
// the window sums, from which the row's disparities are decided.
#include "vtm/stereo/ml_stereo.hpp"

#include "plan.hpp"

namespace vtm::stereo {
namespace {

using detail::Plan;

struct Sizes {
    std::size_t image;      // one prefiltered image
    std::size_t dtRing;     // (2r+1) x-pass rows
    std::size_t dtRow;      // bins * dtStride
    std::size_t costRing;   // window * width * slotStride
    std::size_t sums;       // costStride * slotStride (column sums)
    std::size_t winSums;    // width * slotStride (window sums)
};

Sizes sizesOf(const Config& c, const Plan& p) noexcept {
    const auto w = static_cast<std::size_t>(p.width);
    const auto slot = static_cast<std::size_t>(p.slotStride);
    Sizes s{};
    s.image = w * static_cast<std::size_t>(p.height);
    s.dtRing = static_cast<std::size_t>(2 * p.radius + 1) * static_cast<std::size_t>(p.bins) * w;
    s.dtRow = static_cast<std::size_t>(p.bins) * static_cast<std::size_t>(p.dtStride);
    s.costRing = static_cast<std::size_t>(c.window) * w * slot;
    s.sums = static_cast<std::size_t>(p.costStride) * slot;
    s.winSums = w * slot;
    return s;
}

}  // namespace

std::size_t MlStereo::workspaceBytes(const Config& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const Plan p = detail::makePlan(config);
    const Sizes s = sizesOf(config, p);
    const auto w = static_cast<std::size_t>(p.width);
    // Term by term, in the order init() carves them; blockBytes adds worst-case padding.
    return Arena::blockBytes(256U)                                  // cost table
           + 2U * Arena::blockBytes(s.image)                        // prefiltered left, right
           + Arena::blockBytes(w * sizeof(std::int32_t))            // prefilter column sums
           + Arena::blockBytes(s.dtRing) + Arena::blockBytes(s.dtRow)
           + Arena::blockBytes(w * sizeof(std::int32_t))            // template offsets
           + Arena::blockBytes(s.costRing)
           + Arena::blockBytes(s.sums * sizeof(std::uint16_t))      // column sums
           + Arena::blockBytes(s.winSums * sizeof(std::uint16_t))   // window sums
           + 2U * Arena::blockBytes(w * sizeof(std::int32_t))       // best, second-best cost
           + Arena::blockBytes(w * sizeof(std::int16_t))            // best index
           + Arena::blockBytes(w * sizeof(std::int32_t))            // right-to-left best cost
           + Arena::blockBytes(w * sizeof(std::int16_t));           // right-to-left best disparity
}

Status MlStereo::init(const Config& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const Plan p = detail::makePlan(config);
    const Sizes s = sizesOf(config, p);
    const auto w = static_cast<std::size_t>(p.width);
    costTable_ = arena.allocateArray<std::uint8_t>(256U);
    leftFiltered_ = arena.allocateArray<std::uint8_t>(s.image);
    rightFiltered_ = arena.allocateArray<std::uint8_t>(s.image);
    boxColumns_ = arena.allocateArray<std::int32_t>(w);
    dtRing_ = arena.allocateArray<std::uint8_t>(s.dtRing);
    dtRow_ = arena.allocateArray<std::uint8_t>(s.dtRow);
    templateOffset_ = arena.allocateArray<std::int32_t>(w);
    costRing_ = arena.allocateArray<std::uint8_t>(s.costRing);
    colSums_ = arena.allocateArray<std::uint16_t>(s.sums);
    winSums_ = arena.allocateArray<std::uint16_t>(s.winSums);
    bestCost_ = arena.allocateArray<std::int32_t>(w);
    secondCost_ = arena.allocateArray<std::int32_t>(w);
    bestIndex_ = arena.allocateArray<std::int16_t>(w);
    rlCost_ = arena.allocateArray<std::int32_t>(w);
    rlDisparity_ = arena.allocateArray<std::int16_t>(w);
    if (costTable_.empty() || leftFiltered_.empty() || rightFiltered_.empty() || boxColumns_.empty() ||
        dtRing_.empty() || dtRow_.empty() || templateOffset_.empty() || costRing_.empty() ||
        colSums_.empty() || winSums_.empty() || bestCost_.empty() || secondCost_.empty() ||
        bestIndex_.empty() || rlCost_.empty() || rlDisparity_.empty()) {
        return Status(StatusCode::kOutOfMemory, "MlStereo::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    detail::buildCostTable(config, p, costTable_.data());
    config_ = config;
    window_min_ = config.d_min;
    initialized_ = true;
    return Status::ok();
}

Status MlStereo::setDisparityWindow(std::int32_t d_min) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "MlStereo::setDisparityWindow: init() has not succeeded");
    }
    // d * 16 +- 8 (the subpixel offset) must fit int16 and never be kNoDisparity.
    constexpr std::int32_t kLimit = kMaxDisparityPx;
    const std::int32_t span = config_.d_max - config_.d_min;  // count - 1, 0..1023
    if (d_min < -kLimit || d_min > kLimit || d_min + span > kLimit) {  // the sum only for |d_min| <= 2047
        return Status(StatusCode::kInvalidArgument,
                      "MlStereo::setDisparityWindow: d_min: the window must lie in -2047..2047 px", d_min);
    }
    window_min_ = d_min;
    prior_ = ImageView<const std::int16_t>();
    return Status::ok();
}

Status MlStereo::setDisparityPrior(const ImageView<const std::int16_t>& prior_px) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "MlStereo::setDisparityPrior: init() has not succeeded");
    }
    if (!prior_px.valid()) {
        return Status(StatusCode::kInvalidArgument, "MlStereo::setDisparityPrior: prior_px is empty");
    }
    window_min_ = config_.d_min;
    prior_ = prior_px;
    return Status::ok();
}

}  // namespace vtm::stereo
