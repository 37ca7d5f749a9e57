// PyramidStereo: the coarse search, the prior, the full-resolution search (see the header).
#include "vtm/core/config_check.hpp"
#include "vtm/stereo/pyramid_stereo.hpp"

#include "vtm/core/image_pyramid.hpp"

namespace vtm::stereo {
namespace {

// Floor and ceiling of a / b for b > 0.
std::int32_t floorDiv(std::int32_t a, std::int32_t b) noexcept {
    const std::int32_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}
std::int32_t ceilDiv(std::int32_t a, std::int32_t b) noexcept { return -floorDiv(-a, b); }

std::int32_t clampIndex(std::int32_t i, std::int32_t n) noexcept { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

// Pixels of levels 1..L of a max_width x max_height image (each level halves the last).
std::size_t levelPixels(const PyramidConfig& c) noexcept {
    std::size_t n = 0U;
    std::int32_t w = c.max_width;
    std::int32_t h = c.max_height;
    for (std::int32_t l = 1; l <= c.levels; ++l) {
        w /= 2;
        h /= 2;
        n += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    }
    return n;
}

std::int32_t coarseSize(std::int32_t full, std::int32_t levels) noexcept {
    std::int32_t v = full;
    for (std::int32_t l = 0; l < levels; ++l) {
        v /= 2;
    }
    return v;
}

// Rounded a / b, halves away from zero, b > 0.
std::int64_t roundDiv(std::int64_t a, std::int64_t b) noexcept {
    return a >= 0 ? (2 * a + b) / (2 * b) : -((-2 * a + b) / (2 * b));
}

}  // namespace

Status PyramidConfig::validate() const noexcept {
    if (levels < 1 || levels > 3) {
        return invalidConfig("levels: must be 1..3", levels);
    }
    if (coarse_disparities < 3 || coarse_disparities > 1024) {
        return invalidConfig("coarse_disparities: must be 3..1024", coarse_disparities);
    }
    if (coarse_window < 3 || coarse_window > 31 || coarse_window % 2 == 0) {
        return invalidConfig("coarse_window: must be odd, 3..31 px", coarse_window);
    }
    if (coarse_lr_max_diff_px < -1 || coarse_lr_max_diff_px > 16) {
        return invalidConfig("coarse_lr_max_diff_px: must be -1..16", coarse_lr_max_diff_px);
    }
    if (fine_radius_px < 1 || fine_radius_px > 64) {
        return invalidConfig("fine_radius_px: must be 1..64", fine_radius_px);
    }
    if (fill_reach_px < 0 || fill_reach_px > 64) {
        return invalidConfig("fill_reach_px: must be 0..64 coarse px", fill_reach_px);
    }
    if (coarseSize(max_width, levels) < 8 || coarseSize(max_height, levels) < 8) {
        return invalidConfig("levels: the coarse level of max_width x max_height must be at least 8 x 8 px", levels);
    }
    VTM_RETURN_IF_ERROR(fineConfig().validate());
    return coarseConfig().validate();
}

Config PyramidConfig::coarseConfig() const noexcept {
    Config c = matcher;
    c.max_width = coarseSize(max_width, levels);
    c.max_height = coarseSize(max_height, levels);
    c.d_min = 0;
    c.d_max = coarse_disparities - 1;
    c.window = coarse_window;
    c.lr_max_diff_px = coarse_lr_max_diff_px;
    c.uniqueness_percent = 0;
    c.clip_search_to_image = true;
    return c;
}

Config PyramidConfig::fineConfig() const noexcept {
    Config c = matcher;
    c.max_width = max_width;
    c.max_height = max_height;
    c.d_min = -fine_radius_px;
    c.d_max = fine_radius_px;
    c.uniqueness_percent = 0;
    c.clip_search_to_image = true;
    return c;
}

std::size_t PyramidStereo::workspaceBytes(const PyramidConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t full = static_cast<std::size_t>(config.max_width) * static_cast<std::size_t>(config.max_height);
    const std::size_t coarse = static_cast<std::size_t>(coarseSize(config.max_width, config.levels)) *
                               static_cast<std::size_t>(coarseSize(config.max_height, config.levels));
    return MlStereo::workspaceBytes(config.coarseConfig()) + MlStereo::workspaceBytes(config.fineConfig()) +
           2U * Arena::blockBytes(levelPixels(config))                       // left, right levels
           + 2U * Arena::blockBytes(coarse * sizeof(std::int16_t))           // coarse disparity, prior
           + Arena::blockBytes(static_cast<std::size_t>(coarseSize(config.max_width, config.levels)) * sizeof(std::int16_t))  // line scratch
           + Arena::blockBytes(full * sizeof(std::int16_t));                 // prior
}

Status PyramidStereo::init(const PyramidConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const Status out_of_memory(StatusCode::kOutOfMemory, "PyramidStereo::init: arena smaller than workspaceBytes(config)",
                               static_cast<std::int64_t>(workspaceBytes(config)));
    if (!coarse_.init(config.coarseConfig(), arena).isOk() || !fine_.init(config.fineConfig(), arena).isOk()) {
        return out_of_memory;  // the configurations were validated: only the arena can fail
    }
    const std::size_t full = static_cast<std::size_t>(config.max_width) * static_cast<std::size_t>(config.max_height);
    const std::int32_t cw = coarseSize(config.max_width, config.levels);
    const std::int32_t ch = coarseSize(config.max_height, config.levels);
    leftLevels_ = arena.allocateArray<std::uint8_t>(levelPixels(config));
    rightLevels_ = arena.allocateArray<std::uint8_t>(levelPixels(config));
    coarseDisparity_ = arena.allocateArray<std::int16_t>(static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch));
    coarsePrior_ = arena.allocateArray<std::int16_t>(static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch));
    rowScratch_ = arena.allocateArray<std::int16_t>(static_cast<std::size_t>(coarseSize(config.max_width, config.levels)));
    prior_ = arena.allocateArray<std::int16_t>(full);
    if (leftLevels_.empty() || rightLevels_.empty() || coarseDisparity_.empty() || coarsePrior_.empty() ||
        rowScratch_.empty() ||
        prior_.empty()) {
        return out_of_memory;
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

// Halves both images `levels` times into the level buffers; the last level is the coarse pair.
Status PyramidStereo::buildLevels(const ImageView<const std::uint8_t>& left,
                                  const ImageView<const std::uint8_t>& right) noexcept {
    ImageView<const std::uint8_t> srcL = left;
    ImageView<const std::uint8_t> srcR = right;
    std::size_t offset = 0U;
    for (std::int32_t l = 1; l <= config_.levels; ++l) {
        const std::int32_t w = srcL.width() / 2;
        const std::int32_t h = srcL.height() / 2;
        const ImageView<std::uint8_t> dstL(leftLevels_.data() + offset, w, h);
        const ImageView<std::uint8_t> dstR(rightLevels_.data() + offset, w, h);
        VTM_RETURN_IF_ERROR(halveImage(srcL, dstL));
        VTM_RETURN_IF_ERROR(halveImage(srcR, dstR));
        offset += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        srcL = dstL;
        srcR = dstR;
        coarseLeft_ = dstL;
        coarseRight_ = dstR;
    }
    return Status::ok();
}

namespace {

// Fills the holes of one row of n values (a copy of the row as it was is kept in
// `scratch`): each takes the smaller (farther) of the nearest valid values within `reach`
// on either side. Returns the values filled.
std::int32_t fillRow(std::int16_t* row, std::int32_t n, std::int32_t reach, std::int16_t* scratch) noexcept {
    for (std::int32_t i = 0; i < n; ++i) {
        scratch[i] = row[i];
    }
    std::int32_t filled = 0;
    for (std::int32_t i = 0; i < n; ++i) {
        if (scratch[i] != kNoDisparity) {
            continue;
        }
        std::int16_t best = kNoDisparity;
        for (std::int32_t k = 1; k <= reach && best == kNoDisparity; ++k) {
            const std::int16_t lo = i - k >= 0 ? scratch[i - k] : kNoDisparity;
            const std::int16_t hi = i + k < n ? scratch[i + k] : kNoDisparity;
            if (lo != kNoDisparity && (hi == kNoDisparity || lo < hi)) {
                best = lo;
            } else if (hi != kNoDisparity) {
                best = hi;
            }
        }
        if (best != kNoDisparity) {
            row[i] = best;
            ++filled;
        }
    }
    return filled;
}

}  // namespace

// Coarse holes are filled along the rows (fillRow: the farther of the nearest valid
// values within fill_reach_px). Filling the columns too was measured: no gain.
void PyramidStereo::fillCoarseHoles(const ImageView<std::int16_t>& coarse, PyramidStats& stats) noexcept {
    const std::int32_t reach = config_.fill_reach_px;
    if (reach == 0) {
        return;
    }
    for (std::int32_t y = 0; y < coarse.height(); ++y) {
        stats.coarse_filled += fillRow(coarse.row(y), coarse.width(), reach, rowScratch_.data());
    }
}

// Bilinear interpolation of the coarse disparities (1/16 coarse px) over the valid ones of
// the four around each full-resolution pixel, scaled to whole full-resolution pixels.
// Coarse pixel i's centre is full-resolution column s i + (s - 1) / 2, s = 2^levels.
void PyramidStereo::interpolatePrior(const ImageView<const std::int16_t>& coarse, std::int32_t width,
                                     std::int32_t height, PyramidStats& stats) noexcept {
    const std::int32_t s = 1 << config_.levels;
    const std::int32_t two_s = 2 * s;
    const std::int32_t cw = coarse.width();
    const std::int32_t ch = coarse.height();
    for (std::int32_t y = 0; y < height; ++y) {
        const std::int32_t ny = 2 * y - s + 1;  // 2 s times the coarse row coordinate
        const std::int32_t iy = floorDiv(ny, two_s);
        const std::int32_t fy = ny - iy * two_s;
        const std::int16_t* r0 = coarse.row(clampIndex(iy, ch));
        const std::int16_t* r1 = coarse.row(clampIndex(iy + 1, ch));
        std::int16_t* out = prior_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        for (std::int32_t x = 0; x < width; ++x) {
            const std::int32_t nx = 2 * x - s + 1;
            const std::int32_t ix = floorDiv(nx, two_s);
            const std::int32_t fx = nx - ix * two_s;
            const std::int32_t x0 = clampIndex(ix, cw);
            const std::int32_t x1 = clampIndex(ix + 1, cw);
            const std::int16_t v[4] = {r0[x0], r0[x1], r1[x0], r1[x1]};
            const std::int32_t wgt[4] = {(two_s - fx) * (two_s - fy), fx * (two_s - fy), (two_s - fx) * fy, fx * fy};
            std::int64_t acc = 0;
            std::int64_t wsum = 0;
            for (std::int32_t i = 0; i < 4; ++i) {
                if (v[i] != kNoDisparity && wgt[i] > 0) {
                    acc += static_cast<std::int64_t>(wgt[i]) * v[i];
                    wsum += wgt[i];
                }
            }
            if (wsum == 0) {
                out[x] = kNoDisparity;
                continue;
            }
            const std::int64_t px = roundDiv(acc * s, wsum * kDisparityScale);
            out[x] = static_cast<std::int16_t>(px > 4095 ? 4095 : (px < -4095 ? -4095 : px));
            ++stats.prior_pixels;
        }
    }
}

// The coarse search: with a surface, around it (its value at each coarse pixel's centre,
// over s, clamped to the range); without, the window centred on the range.
Status PyramidStereo::searchCoarse(const ImageView<const std::int16_t>& surface, std::int32_t d_min,
                                   std::int32_t d_max, const ImageView<std::int16_t>& coarse,
                                   PyramidStats& st) noexcept {
    const std::int32_t s = 1 << config_.levels;
    const std::int32_t n = config_.coarse_disparities;
    if (!surface.valid()) {
        const std::int32_t lo = floorDiv(d_min, s) - 1;
        const std::int32_t hi = ceilDiv(d_max, s) + 1;
        if (hi - lo + 1 > n) {
            return Status(StatusCode::kInvalidArgument,
                          "PyramidStereo::compute: d_min..d_max wider than the coarse search covers",
                          static_cast<std::int64_t>(d_max) - d_min + 1);
        }
        const std::int32_t spare = n - (hi - lo + 1);
        VTM_RETURN_IF_ERROR(coarse_.setDisparityWindow(lo - spare / 2));
        st.coarse_d_min = coarse_.windowMin();
        st.coarse_d_max = coarse_.windowMax();
        return coarse_.compute(coarseLeft_, coarseRight_, DisparityOutput{coarse, {}, {}}, &st.coarse);
    }
    // The window's first disparity per coarse pixel: centred on the surface (MlStereo
    // marks the pixels whose window would leave int16 as kOutOfRange).
    const ImageView<std::int16_t> firsts(coarsePrior_.data(), coarse.width(), coarse.height());
    st.coarse_d_min = 32767;
    st.coarse_d_max = -32767;
    for (std::int32_t y = 0; y < coarse.height(); ++y) {
        const std::int16_t* src = surface.row(s * y + s / 2);
        std::int16_t* dst = firsts.row(y);
        for (std::int32_t x = 0; x < coarse.width(); ++x) {
            const std::int16_t v = src[s * x + s / 2];
            if (v == kNoDisparity) {
                dst[x] = kNoDisparity;
                continue;
            }
            const std::int32_t first = floorDiv(v, s) - n / 2;
            dst[x] = static_cast<std::int16_t>(first);
            st.coarse_d_min = first < st.coarse_d_min ? first : st.coarse_d_min;
            st.coarse_d_max = first + n - 1 > st.coarse_d_max ? first + n - 1 : st.coarse_d_max;
        }
    }
    VTM_RETURN_IF_ERROR(coarse_.setDisparityPrior(firsts));  // offsets 0..n-1 from `first`
    const Status status = coarse_.compute(coarseLeft_, coarseRight_, DisparityOutput{coarse, {}, {}}, &st.coarse);
    coarse_.clearDisparityPrior();  // the view is coarsePrior_: not to be read by a later plain search
    return status;
}

Status PyramidStereo::compute(const ImageView<const std::uint8_t>& left, const ImageView<const std::uint8_t>& right,
                              const ImageView<const std::int16_t>& surface, std::int32_t d_min, std::int32_t d_max,
                              const DisparityOutput& out, PyramidStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PyramidStereo::compute: init() has not succeeded");
    }
    if (!left.valid() || !right.valid() || !right.sameSize(left.width(), left.height())) {
        return Status(StatusCode::kSizeMismatch, "PyramidStereo::compute: left and right must be valid and the same size");
    }
    if (left.width() > config_.max_width || left.height() > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "PyramidStereo::compute: image larger than max_width x max_height",
                      left.width() > config_.max_width ? left.width() : left.height());
    }
    if (surface.valid() && !surface.sameSize(left.width(), left.height())) {
        return Status(StatusCode::kSizeMismatch, "PyramidStereo::compute: surface must match the image size",
                      surface.width());
    }
    const std::int32_t cw = coarseSize(left.width(), config_.levels);
    const std::int32_t ch = coarseSize(left.height(), config_.levels);
    if (cw < 8 || ch < 8) {
        return Status(StatusCode::kSizeMismatch, "PyramidStereo::compute: the coarse level is smaller than 8 x 8 px",
                      cw < ch ? cw : ch);
    }
    if (d_max < d_min) {
        return Status(StatusCode::kInvalidArgument, "PyramidStereo::compute: d_max is below d_min", d_max);
    }
    PyramidStats local{};
    PyramidStats& st = stats != nullptr ? *stats : local;
    st = PyramidStats{};
    VTM_RETURN_IF_ERROR(buildLevels(left, right));
    const ImageView<std::int16_t> coarse(coarseDisparity_.data(), cw, ch);
    VTM_RETURN_IF_ERROR(searchCoarse(surface, d_min, d_max, coarse, st));
    fillCoarseHoles(coarse, st);
    interpolatePrior(coarse, left.width(), left.height(), st);
    priorView_ = ImageView<const std::int16_t>(prior_.data(), left.width(), left.height());
    VTM_RETURN_IF_ERROR(fine_.setDisparityPrior(priorView_));
    return fine_.compute(left, right, out, &st.fine);
}

}  // namespace vtm::stereo
