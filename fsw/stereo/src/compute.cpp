// MlStereo::compute: the row stream (see ml_stereo.cpp for the overview).
#include <cstring>

#include "plan.hpp"
#include "window_sums.hpp"
#include "vtm/core/math.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {
namespace {

using detail::Plan;

constexpr std::int32_t kInfCost = 0x7FFFFFFF;

// Everything one compute() touches: the plan, the image size and the workspace.
struct Work {
    Plan p{};
    Config c{};
    std::int32_t w = 0;
    std::int32_t h = 0;
    const std::uint8_t* table = nullptr;
    ImageView<std::uint8_t> left{};   // prefiltered, packed
    ImageView<std::uint8_t> right{};
    std::uint8_t* dtRing = nullptr;
    std::uint8_t* dtRow = nullptr;
    std::int32_t* offset = nullptr;
    std::uint8_t* costRing = nullptr;
    std::uint16_t* colSums = nullptr;
    std::uint16_t* winSums = nullptr;
    std::int32_t* best = nullptr;
    std::int32_t* second = nullptr;
    std::int16_t* bestIndex = nullptr;
    std::int32_t* rlCost = nullptr;
    std::int16_t* rlDisparity = nullptr;
    // The disparity prior (MlStereo::setDisparityPrior), or an empty view: every pixel's
    // search is centred on 0.
    ImageView<const std::int16_t> prior{};
    // The window's shift (setDisparityWindow) in 1/16 px: the search runs on the Config's
    // disparities over the moved right image; every disparity found gets this added.
    std::int32_t shift16 = 0;
};

// The right column on which pixel x's search is centred, clamped to the DT row's padding
// (a centre outside it searches only padding, and decide() calls the pixel kBorder).
std::int32_t searchCentre(const Work& k, const std::int16_t* priorRow, std::int32_t x) {
    if (priorRow == nullptr || priorRow[x] == kNoDisparity) {
        return x;
    }
    const std::int32_t u = x - priorRow[x];
    const std::int32_t lo = -k.p.disparities;
    const std::int32_t hi = k.w - 1 + k.p.disparities;
    return u < lo ? lo : (u > hi ? hi : u);
}

// Pushes template row y' (or a row of zero cost below the image) into ring slot `slot`,
// updating the column sums, and when `emit` the window sums and best disparities of row
// y' - half (window_sums.hpp). With a prior, pixel x reads the DT row around its own
// centre x - prior(x, y').
void pushCostRow(const Work& k, const std::uint8_t* leftRow, std::int32_t y, std::int32_t slot, bool emit) {
    const Plan& p = k.p;
    const std::size_t slotBytes = static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.slotStride);
    const std::int16_t* priorRow = (k.prior.valid() && leftRow != nullptr) ? k.prior.row(y) : nullptr;
    // Slot 0 of pixel x (disparity d_max) lies at column centre - d_max of its bin's row.
    for (std::int32_t x = 0; x < k.w && leftRow != nullptr; ++x) {
        k.offset[x] = (leftRow[x] >> p.binShift) * p.dtStride + p.padLeft + searchCentre(k, priorRow, x) - k.c.d_max;
    }
    const detail::SearchRow row{k.winSums, k.best, k.bestIndex};
    detail::pushCostRow(p, k.w, k.dtRow, leftRow != nullptr ? k.offset : nullptr,
                        k.costRing + static_cast<std::size_t>(slot) * slotBytes, k.colSums, emit ? &row : nullptr);
}

// The window sum of pixel x at disparity index j (of the completed row).
std::int32_t winAt(const Work& k, std::int32_t x, std::int32_t j) {
    return k.winSums[detail::sumIndex(k.p, x, j)];
}

// Second-best (at least 2 disparities away from the best) per left column, and the best
// disparity per right column over the same sums (the right-to-left search); each only
// when its check is enabled.
// With a prior, the right-to-left search visits every left pixel with a prior and every
// offset, and keeps per right column the least sum of the left pixels that land there.
void searchRightToLeftWithPrior(const Work& k, const std::int16_t* priorRow) {
    const Plan& p = k.p;
    for (std::int32_t j = 0; j < p.disparities; ++j) {  // j outer: ties go to the lowest j, then x
        for (std::int32_t x = 0; x < k.w; ++x) {
            if (priorRow[x] == kNoDisparity) {
                continue;
            }
            const std::int32_t d = priorRow[x] + k.c.d_min + j;
            const std::int32_t xr = x - d;
            if (xr >= 0 && xr < k.w && winAt(k, x, j) < k.rlCost[xr]) {
                k.rlCost[xr] = winAt(k, x, j);
                k.rlDisparity[xr] = static_cast<std::int16_t>(d);
            }
        }
    }
}

void searchRow(const Work& k, const std::int16_t* priorRow) {
    const Plan& p = k.p;
    for (std::int32_t x = 0; x < k.w; ++x) {
        k.second[x] = kInfCost;
        k.rlCost[x] = kInfCost;
        k.rlDisparity[x] = kNoDisparity;
    }
    if (k.c.lr_max_diff_px >= 0 && priorRow != nullptr) {
        searchRightToLeftWithPrior(k, priorRow);
    }
    // Without a prior: per right column the least sum over the left pixels x = xr + d;
    // for one xr, x grows with j, so visiting x in order visits its candidates in order of
    // j, and the strict < keeps the lowest disparity among equal sums. (Within one x every
    // j lands on another xr, so the order of its sums does not matter.)
    for (std::int32_t x = 0; x < k.w && k.c.lr_max_diff_px >= 0 && priorRow == nullptr; ++x) {
        detail::forEachSum(p, k.winSums, x, [&k, x](std::int32_t j, std::int32_t sum) {
            const std::int32_t d = k.c.d_min + j;
            const std::int32_t xr = x - d;
            if (xr >= 0 && xr < k.w && sum < k.rlCost[xr]) {
                k.rlCost[xr] = sum;
                k.rlDisparity[xr] = static_cast<std::int16_t>(d);
            }
        });
    }
    for (std::int32_t x = 0; x < k.w && k.c.uniqueness_percent > 0; ++x) {
        detail::forEachSum(p, k.winSums, x, [&k, x](std::int32_t j, std::int32_t sum) {
            const std::int32_t gap = j - k.bestIndex[x];
            if ((gap > 1 || gap < -1) && sum < k.second[x]) {
                k.second[x] = sum;
            }
        });
    }
}

// Parabola vertex offset through (-1, cm), (0, c0), (1, cp), in 1/16 px, rounded half
// away from zero, clamped to +-8. curvature = cm + cp - 2 c0 > 0. In 32 bits: window sums
// are 0..65535, so |t| <= 65535 * 16 and 2 |t| + den <= 2^21 + 2^18 (no 64-bit division,
// a library call on 32-bit targets; the same quotients).
std::int32_t subpixelOffset16(std::int32_t cm, std::int32_t cp, std::int32_t curvature) {
    const std::int32_t t = (cm - cp) * kDisparityScale;  // offset * 2 curvature
    const std::int32_t den = 2 * curvature;
    const std::int32_t q = (t >= 0) ? (2 * t + den) / (2 * den) : -((-2 * t + den) / (2 * den));
    return q > 8 ? 8 : (q < -8 ? -8 : q);
}

struct Decision {
    Reason reason;
    std::int16_t disparity16;
    float sigma;
};

// The offsets pixel x searches around its centre (its prior, 0 without one): all, or with
// clip_search_to_image those whose right column is inside the image. kValid, or why the
// pixel is not searched (kNoPrior, kBorder, kOutOfRange beyond int16).
struct OffsetRange {
    Reason reason;
    std::int32_t lo;
    std::int32_t hi;
};
OffsetRange offsetRange(const Work& k, std::int32_t x, std::int32_t centre) {
    if (centre == kNoDisparity) {
        return {Reason::kNoPrior, 0, 0};
    }
    const std::int32_t u = x - centre;  // the right column of offset 0
    std::int32_t jLo = 0;
    std::int32_t jHi = k.p.disparities - 1;
    if (k.c.clip_search_to_image) {
        jLo = u - (k.w - 1) - k.c.d_min > 0 ? u - (k.w - 1) - k.c.d_min : 0;
        jHi = u - k.c.d_min < jHi ? u - k.c.d_min : jHi;
        if (jHi - jLo < 2) {
            return {Reason::kBorder, 0, 0};
        }
    } else if (u - k.c.d_min < 0 || u - k.c.d_max > k.w - 1) {
        return {Reason::kBorder, 0, 0};
    }
    if (centre + k.c.d_min < -kMaxDisparityPx || centre + k.c.d_max > kMaxDisparityPx) {
        return {Reason::kOutOfRange, 0, 0};
    }
    return {Reason::kValid, jLo, jHi};
}

// centre: the pixel's prior (0 without one); the search is centre + d_min .. centre + d_max.
Decision decide(const Work& k, std::int32_t x, std::int32_t centre) {
    const Plan& p = k.p;
    constexpr float kInf = static_cast<float>(math::kInfinity);
    const OffsetRange range = offsetRange(k, x, centre);
    if (range.reason != Reason::kValid) {
        return {range.reason, kNoDisparity, kInf};
    }
    const std::int32_t jLo = range.lo;
    const std::int32_t jHi = range.hi;
    const std::int32_t j0 = k.bestIndex[x];
    const std::int32_t c0 = k.best[x];
    if (j0 < jLo || j0 > jHi) {
        return {Reason::kOutOfRange, kNoDisparity, kInf};  // the best lies outside the image
    }
    if (p.disparities >= 3 && (j0 == jLo || j0 == jHi)) {
        // A peak on the boundary: out of range, unless the curve is flat there (ties
        // resolve to the lowest disparity), which is missing texture.
        const std::int32_t inner = winAt(k, x, j0 == jLo ? j0 + 1 : j0 - 1);
        return {inner == c0 ? Reason::kNoTexture : Reason::kOutOfRange, kNoDisparity, kInf};
    }
    const std::int32_t cm = j0 > 0 ? winAt(k, x, j0 - 1) : c0;
    const std::int32_t cp = j0 < p.disparities - 1 ? winAt(k, x, j0 + 1) : c0;
    const std::int32_t curvature = cm + cp - 2 * c0;
    if (curvature < k.c.min_curvature || curvature <= 0) {
        return {Reason::kNoTexture, kNoDisparity, kInf};
    }
    const std::int64_t area = static_cast<std::int64_t>(k.c.window) * k.c.window;
    if (static_cast<std::int64_t>(c0) * 100 > static_cast<std::int64_t>(k.c.max_outlier_percent) * p.maxCost * area) {
        return {Reason::kLowLikelihood, kNoDisparity, kInf};
    }
    if (k.c.uniqueness_percent > 0 && k.second[x] != kInfCost &&
        static_cast<std::int64_t>(k.second[x]) * 100 <= static_cast<std::int64_t>(c0) * (100 + k.c.uniqueness_percent)) {
        return {Reason::kAmbiguous, kNoDisparity, kInf};
    }
    const std::int32_t d0 = centre + k.c.d_min + j0;
    if (k.c.lr_max_diff_px >= 0) {
        const std::int32_t xr = x - d0;
        const std::int32_t back =
            (xr >= 0 && xr < k.w && k.rlDisparity[xr] != kNoDisparity) ? k.rlDisparity[xr] : d0 + 1000;
        const std::int32_t diff = back > d0 ? back - d0 : d0 - back;
        if (diff > k.c.lr_max_diff_px) {
            return {Reason::kLeftRightMismatch, kNoDisparity, kInf};
        }
    }
    const std::int32_t disparity16 = d0 * kDisparityScale + subpixelOffset16(cm, cp, curvature);
    // Log-likelihood L(d) = -cost / costPerNat: sigma^2 = -1 / L'' = costPerNat / curvature.
    const double sigma = math::sqrt(p.costPerNat / static_cast<double>(curvature));
    return {Reason::kValid, static_cast<std::int16_t>(disparity16), static_cast<float>(sigma)};
}

void emitRow(const Work& k, std::int32_t y, const DisparityOutput& out, StereoStats* stats) {
    const std::int16_t* priorRow = k.prior.valid() ? k.prior.row(y) : nullptr;
    searchRow(k, priorRow);
    std::int16_t* disp = out.disparity_px16.row(y);
    float* sigma = out.sigma_px.valid() ? out.sigma_px.row(y) : nullptr;
    std::uint8_t* reason = out.reason.valid() ? out.reason.row(y) : nullptr;
    for (std::int32_t x = 0; x < k.w; ++x) {
        const Decision dec = decide(k, x, priorRow != nullptr ? std::int32_t{priorRow[x]} : 0);
        disp[x] = dec.reason == Reason::kValid
                      ? static_cast<std::int16_t>(static_cast<std::int32_t>(dec.disparity16) + k.shift16)
                      : dec.disparity16;
        if (sigma != nullptr) {
            sigma[x] = dec.sigma;
        }
        if (reason != nullptr) {
            reason[x] = static_cast<std::uint8_t>(dec.reason);
        }
        if (stats != nullptr) {
            ++stats->reason_counts[static_cast<std::int32_t>(dec.reason)];
        }
    }
}


Status checkInputs(const Config& c, const ImageView<const std::uint8_t>& left,
                   const ImageView<const std::uint8_t>& right, const ImageView<const std::int16_t>& prior,
                   const DisparityOutput& out) {
    if (!left.valid() || !right.valid()) {
        return Status(StatusCode::kInvalidArgument, "MlStereo::compute: left or right image is empty");
    }
    if (!right.sameSize(left.width(), left.height())) {
        return Status(StatusCode::kSizeMismatch, "MlStereo::compute: left and right sizes differ", right.width());
    }
    if (left.width() > c.max_width || left.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, "MlStereo::compute: image larger than max_width x max_height",
                      left.width() > c.max_width ? left.width() : left.height());
    }
    if (!out.disparity_px16.valid() || !out.disparity_px16.sameSize(left.width(), left.height())) {
        return Status(StatusCode::kSizeMismatch, "MlStereo::compute: disparity output must match the image size");
    }
    if (prior.valid() && !prior.sameSize(left.width(), left.height())) {
        return Status(StatusCode::kSizeMismatch, "MlStereo::compute: the disparity prior must match the image size",
                      prior.width());
    }
    if ((out.sigma_px.data() != nullptr && !out.sigma_px.sameSize(left.width(), left.height())) ||
        (out.reason.data() != nullptr && !out.reason.sameSize(left.width(), left.height()))) {
        return Status(StatusCode::kSizeMismatch, "MlStereo::compute: sigma/reason output must match the image size");
    }
    return Status::ok();
}

void prefilterInto(const Config& c, const ImageView<const std::uint8_t>& in, std::int32_t* columns,
                   const ImageView<std::uint8_t>& out) {
    if (c.prefilter == Prefilter::kLocalMeanRemoved) {
        detail::removeLocalMean(in, c.prefilter_window, columns, out);
    } else {
        (void)copyImage(in, out);  // sizes were checked by checkInputs
    }
}

// moved(u) = in(u - shift), 0 where u - shift is outside the image: the right image in
// the window's coordinates (setDisparityWindow).
void moveColumns(const ImageView<const std::uint8_t>& in, std::int32_t shift, const ImageView<std::uint8_t>& moved) {
    const std::int32_t w = in.width();
    for (std::int32_t y = 0; y < in.height(); ++y) {
        const std::uint8_t* src = in.row(y);
        std::uint8_t* dst = moved.row(y);
        for (std::int32_t u = 0; u < w; ++u) {
            const std::int32_t x = u - shift;
            dst[u] = (x >= 0 && x < w) ? src[x] : 0U;
        }
    }
}

// The row stream: x pass of the right image ahead by r rows, y pass per template row,
// costs into the ring, and every row decided as soon as its window is complete.
void streamRows(const Work& k, const DisparityOutput& out, StereoStats* stats) {
    const Plan& p = k.p;
    const std::size_t ringRow = static_cast<std::size_t>(p.bins) * static_cast<std::size_t>(p.width);
    const std::int32_t slots = 2 * p.radius + 1;
    std::int32_t nextX = 0;  // next right row for the x pass
    for (std::int32_t yIn = 0; yIn < k.h + p.half; ++yIn) {
        if (yIn < k.h) {
            const std::int32_t need = (yIn + p.radius < k.h) ? yIn + p.radius : k.h - 1;
            for (; nextX <= need; ++nextX) {  // at most r + 1 rows per template row
                detail::distanceTransformRowX(p, k.right.row(nextX), k.w,
                                              k.dtRing + static_cast<std::size_t>(nextX % slots) * ringRow);
            }
            std::uint8_t binUsed[64] = {};
            const std::uint8_t* templateRow = k.left.row(yIn);
            for (std::int32_t x = 0; x < k.w; ++x) {
                binUsed[templateRow[x] >> p.binShift] = 1U;
            }
            detail::distanceTransformRowY(p, detail::RowGeometry{yIn, k.h, k.w, binUsed}, k.dtRing, k.table,
                                          k.dtRow);
        }
        pushCostRow(k, yIn < k.h ? k.left.row(yIn) : nullptr, yIn, yIn % (2 * p.half + 1), yIn >= p.half);
        if (yIn >= p.half) {
            emitRow(k, yIn - p.half, out, stats);
        }
    }
}

}  // namespace

Status MlStereo::compute(const ImageView<const std::uint8_t>& left, const ImageView<const std::uint8_t>& right,
                         const DisparityOutput& out, StereoStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "MlStereo::compute: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkInputs(config_, left, right, prior_, out));
    const std::int32_t w = left.width();
    const std::int32_t h = left.height();
    Work k{detail::makePlan(config_), config_, w, h, costTable_.data(),
           ImageView<std::uint8_t>(leftFiltered_.data(), w, h), ImageView<std::uint8_t>(rightFiltered_.data(), w, h),
           dtRing_.data(), dtRow_.data(), templateOffset_.data(), costRing_.data(), colSums_.data(),
           winSums_.data(), bestCost_.data(), secondCost_.data(), bestIndex_.data(), rlCost_.data(),
           rlDisparity_.data(), prior_};
    const std::int32_t shift = window_min_ - config_.d_min;
    k.shift16 = shift * kDisparityScale;
    if (shift == 0) {
        prefilterInto(config_, right, boxColumns_.data(), k.right);
    } else if (config_.prefilter == Prefilter::kNone) {
        moveColumns(right, shift, k.right);
    } else {
        // The moved right image is staged in the left image's buffer, which is filled next.
        moveColumns(right, shift, k.left);
        prefilterInto(config_, k.left, boxColumns_.data(), k.right);
    }
    prefilterInto(config_, left, boxColumns_.data(), k.left);
    // Columns of the DT cost row outside the right image stay at the outlier cost for the
    // whole pair (the y pass writes only inside); unused bins' stale rows are never read.
    std::memset(dtRow_.data(), k.p.maxCost, dtRow_.size());
    std::memset(costRing_.data(), 0, costRing_.size());
    std::memset(colSums_.data(), 0, colSums_.size() * sizeof(std::uint16_t));
    if (stats != nullptr) {
        *stats = StereoStats{};
    }
    streamRows(k, out, stats);
    if (stats != nullptr) {
        stats->valid_pixels = stats->reason_counts[static_cast<std::int32_t>(Reason::kValid)];
    }
    return Status::ok();
}

}  // namespace vtm::stereo
