// Förstner operator: strength map, local maxima spread over a grid, subpixel location.
#include "vtm/features/forstner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "feature_limits.hpp"
#include "tensor_det.hpp"

namespace vtm::features {
namespace {

using detail::kMaxCapacityPx;
constexpr std::int32_t kMaxGrid = 64;
constexpr std::int32_t kMaxPerCell = 64;

std::size_t slotCount(const DetectorConfig& c) noexcept {
    return static_cast<std::size_t>(c.grid_cols) * static_cast<std::size_t>(c.grid_rows) *
           static_cast<std::size_t>(c.per_cell);
}

std::size_t idx(std::int32_t x, std::int32_t y, std::int32_t width) noexcept {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
}

// The part of the image features may come from: inside the border and, with a mask,
// where it is nonzero; its bounding box and the best w in it. The strength threshold is
// relative to that w and the spreading grid spans that box, so a small shared view (a wide
// baseline sees A's far field only) still gets grid_cols x grid_rows cells of features and
// is not starved by a strong near field it cannot match. Empty: x1 < x0.
struct AllowedPart {
    float best_w = 0.f;
    std::int32_t x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};
AllowedPart allowedPart(const Span<float>& w, std::int32_t width, std::int32_t height, std::int32_t border,
                        const ImageView<const std::uint8_t>& mask) noexcept {
    AllowedPart p;
    p.x0 = width;
    p.y0 = height;
    for (std::int32_t y = border; y < height - border; ++y) {
        const std::uint8_t* m = mask.data() != nullptr ? mask.row(y) : nullptr;
        for (std::int32_t x = border; x < width - border; ++x) {
            if (m != nullptr && m[x] == 0U) {
                continue;
            }
            p.best_w = std::max(p.best_w, w[idx(x, y, width)]);
            p.x0 = std::min(p.x0, x);
            p.x1 = std::max(p.x1, x);
            p.y0 = std::min(p.y0, y);
            p.y1 = std::max(p.y1, y);
        }
    }
    return p;
}

// Gradient products of pixel (x, y) (1 <= x < W-1, 1 <= y < H-1): Sobel derivatives (8x the
// gradient), whose direction is closer to the true edge normal than a plain central
// difference's, which matters for the point estimate at rotated edges.
struct Products {
    std::int32_t xx, yy, xy;
};
Products productsAt(const std::uint8_t* u, const std::uint8_t* m, const std::uint8_t* d, std::int32_t x) noexcept {
    auto v = [](const std::uint8_t* r, std::int32_t i) { return static_cast<std::int32_t>(r[i]); };
    const std::int32_t gx = (v(u, x + 1) - v(u, x - 1)) + 2 * (v(m, x + 1) - v(m, x - 1)) + (v(d, x + 1) - v(d, x - 1));
    const std::int32_t gy = (v(d, x - 1) - v(u, x - 1)) + 2 * (v(d, x) - v(u, x)) + (v(d, x + 1) - v(u, x + 1));
    return Products{gx * gx, gy * gy, gx * gy};
}

// The column sums of the gradient products over rows: adds row `in`'s products at every
// x of 1..width-2 and, when out >= 1, subtracts row `out`'s.
struct ColumnSums {
    std::int32_t* xx;
    std::int32_t* yy;
    std::int32_t* xy;
};
void slideColumns(const ImageView<const std::uint8_t>& img, std::int32_t in, std::int32_t out,
                  const ColumnSums& c) noexcept {
    const std::uint8_t* iu = img.row(in - 1);
    const std::uint8_t* im = img.row(in);
    const std::uint8_t* id = img.row(in + 1);
    const std::int32_t width = img.width();
    if (out < 1) {
        for (std::int32_t x = 1; x < width - 1; ++x) {
            const Products p = productsAt(iu, im, id, x);
            c.xx[x] += p.xx;
            c.yy[x] += p.yy;
            c.xy[x] += p.xy;
        }
        return;
    }
    const std::uint8_t* ou = img.row(out - 1);
    const std::uint8_t* om = img.row(out);
    const std::uint8_t* od = img.row(out + 1);
    for (std::int32_t x = 1; x < width - 1; ++x) {
        const Products p = productsAt(iu, im, id, x);
        const Products q = productsAt(ou, om, od, x);
        c.xx[x] += p.xx - q.xx;  // int32 wraps nowhere: every sum stays below 2^31
        c.yy[x] += p.yy - q.yy;
        c.xy[x] += p.xy - q.xy;
    }
}

// Strict total order for the cap: larger w first, then row, then column.
bool strongerThan(const ForstnerDetector::Candidate& a, const ForstnerDetector::Candidate& b) noexcept {
    if (a.w != b.w) {
        return a.w > b.w;
    }
    return (a.y != b.y) ? (a.y < b.y) : (a.x < b.x);
}

}  // namespace

Status DetectorConfig::validate() const noexcept {
    if (max_width < 1 || max_width > kMaxCapacityPx) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.max_width: must be 1..4096", max_width);
    }
    if (max_height < 1 || max_height > kMaxCapacityPx) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.max_height: must be 1..4096", max_height);
    }
    if (window < 3 || window > 31 || (window % 2) == 0) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.window: must be odd, 3..31", window);
    }
    if (!(min_roundness > 0.f && min_roundness <= 1.f)) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.min_roundness: must be in (0, 1]");
    }
    if (grid_cols < 1 || grid_cols > kMaxGrid) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.grid_cols: must be 1..64", grid_cols);
    }
    if (grid_rows < 1 || grid_rows > kMaxGrid) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.grid_rows: must be 1..64", grid_rows);
    }
    if (per_cell < 1 || per_cell > kMaxPerCell) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.per_cell: must be 1..64", per_cell);
    }
    if (border_px < window / 2 + 2 || border_px > kMaxCapacityPx) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.border_px: must be >= window / 2 + 2",
                      border_px);
    }
    if (!(min_strength_ratio >= 0.f && min_strength_ratio <= 1.f)) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.min_strength_ratio: must be in [0, 1]");
    }
    if (!(min_separation_px >= 0.0F) || !(min_separation_px <= 16.0F)) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.min_separation_px: must be 0..16");
    }
    if (max_features < 1 || max_features > kMaxFeatures) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.max_features: must be 1..kMaxFeatures (1024)",
                      max_features);
    }
    if (subpixel != Subpixel::kQuadraticFit && subpixel != Subpixel::kEdgeIntersection) {
        return Status(StatusCode::kInvalidConfig, "DetectorConfig.subpixel: unknown method",
                      static_cast<std::int64_t>(subpixel));
    }
    return Status::ok();
}

std::size_t ForstnerDetector::workspaceBytes(const DetectorConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t pixels = static_cast<std::size_t>(config.max_width) * static_cast<std::size_t>(config.max_height);
    const std::size_t slots = slotCount(config);
    const std::size_t cells = static_cast<std::size_t>(config.grid_cols) * static_cast<std::size_t>(config.grid_rows);
    // In the order init() carves them.
    return 2U * Arena::blockBytes(pixels * sizeof(float))                                     // w, q maps
           + Arena::blockBytes(3U * static_cast<std::size_t>(config.max_width) * sizeof(std::int32_t))  // column sums
           + Arena::blockBytes(slots * sizeof(Candidate))                                     // cell slots
           + Arena::blockBytes(cells * sizeof(std::int32_t))                                  // cell counts
           + Arena::blockBytes(slots * sizeof(std::int32_t))                                  // rank
           + Arena::blockBytes(slots);                                                        // keep flags
}

Status ForstnerDetector::init(const DetectorConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t pixels = static_cast<std::size_t>(config.max_width) * static_cast<std::size_t>(config.max_height);
    const std::size_t slots = slotCount(config);
    const std::size_t cells = static_cast<std::size_t>(config.grid_cols) * static_cast<std::size_t>(config.grid_rows);
    w_ = arena.allocateArray<float>(pixels);
    q_ = arena.allocateArray<float>(pixels);
    columns_ = arena.allocateArray<std::int32_t>(3U * static_cast<std::size_t>(config.max_width));
    cells_ = arena.allocateArray<Candidate>(slots);
    cellCount_ = arena.allocateArray<std::int32_t>(cells);
    rank_ = arena.allocateArray<std::int32_t>(slots);
    keep_ = arena.allocateArray<std::uint8_t>(slots);
    if (w_.empty() || q_.empty() || columns_.empty() || cells_.empty() || cellCount_.empty() || rank_.empty() ||
        keep_.empty()) {
        return Status(StatusCode::kOutOfMemory, "ForstnerDetector::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

// w and q for every pixel whose whole window of gradients lies inside the image (0
// elsewhere). Column sums of the gradient products run down the image (add the row
// entering the window, subtract the row leaving it); a running sum along each row gives
// the box sums. All integer: exact.
void ForstnerDetector::computeStrength(const ImageView<const std::uint8_t>& image) noexcept {
    const std::int32_t width = image.width();
    const std::int32_t height = image.height();
    const std::int32_t h = config_.window / 2;
    std::fill(w_.data(), w_.data() + idx(0, height, width), 0.f);
    std::fill(q_.data(), q_.data() + idx(0, height, width), 0.f);
    std::int32_t* cxx = columns_.data();
    std::int32_t* cyy = cxx + width;
    std::int32_t* cxy = cyy + width;
    std::fill(columns_.data(), columns_.data() + 3U * static_cast<std::size_t>(width), 0);
    const ColumnSums columns{cxx, cyy, cxy};
    for (std::int32_t y = 1; y <= 2 * h; ++y) {
        slideColumns(image, y, 0, columns);
    }
    for (std::int32_t y = h + 1; y <= height - 2 - h; ++y) {
        slideColumns(image, y + h, y - h - 1, columns);
        std::int32_t sxx = 0, syy = 0, sxy = 0;
        for (std::int32_t x = 1; x <= 2 * h; ++x) {
            sxx += cxx[x];
            syy += cyy[x];
            sxy += cxy[x];
        }
        for (std::int32_t x = h + 1; x <= width - 2 - h; ++x) {
            sxx += cxx[x + h];
            syy += cyy[x + h];
            sxy += cxy[x + h];
            const double trd = static_cast<double>(sxx) + static_cast<double>(syy);  // exact: < 2^32
            const double det = detail::tensorDeterminant(sxx, syy, sxy);
            if (trd > 0.0 && det > 0.0) {  // IEEE division of the two
                w_[idx(x, y, width)] = static_cast<float>(det / trd);
                q_[idx(x, y, width)] = static_cast<float>(4.0 * det / (trd * trd));
            }
            sxx -= cxx[x - h];
            syy -= cyy[x - h];
            sxy -= cxy[x - h];
        }
    }
}

// Local maxima of w inside the border that pass the thresholds, each inserted into its
// grid cell's list (sorted by w; an equal w keeps the earlier position first). Plateaus:
// a pixel must beat its earlier (raster order) neighbours strictly and equal or beat the
// later ones, so exactly one pixel of a flat maximum survives. Returns the candidate count.
std::int32_t ForstnerDetector::selectCandidates(std::int32_t width, std::int32_t height,
                                                const ImageView<const std::uint8_t>& mask) noexcept {
    const bool masked = mask.data() != nullptr;
    const AllowedPart part = allowedPart(w_, width, height, config_.border_px, mask);
    best_w_ = part.best_w;
    std::fill(cellCount_.data(), cellCount_.data() + cellCount_.size(), 0);
    if (part.x1 < part.x0 || part.y1 < part.y0) {
        return 0;  // nothing allowed: an empty mask
    }
    // Without a mask the grid is the whole image's (cells at the border are partly empty).
    const std::int32_t gx0 = masked ? part.x0 : 0;
    const std::int32_t gy0 = masked ? part.y0 : 0;
    const std::int64_t span_x = masked ? part.x1 - part.x0 + 1 : width;
    const std::int64_t span_y = masked ? part.y1 - part.y0 + 1 : height;
    const float threshold = config_.min_strength_ratio * part.best_w;
    std::int32_t candidates = 0;
    for (std::int32_t y = part.y0; y <= part.y1; ++y) {
        for (std::int32_t x = part.x0; x <= part.x1; ++x) {
            const float w = w_[idx(x, y, width)];
            if (!(w > 0.f) || w < threshold || q_[idx(x, y, width)] < config_.min_roundness ||
                (masked && mask.row(y)[x] == 0U)) {
                continue;
            }
            const float* up = &w_[idx(x, y - 1, width)];
            const float* mid = &w_[idx(x, y, width)];
            const float* down = &w_[idx(x, y + 1, width)];
            const bool earlier = w > up[-1] && w > up[0] && w > up[1] && w > mid[-1];
            const bool later = w >= mid[1] && w >= down[-1] && w >= down[0] && w >= down[1];
            if (!earlier || !later) {
                continue;
            }
            ++candidates;
            const auto cx = static_cast<std::int32_t>(static_cast<std::int64_t>(x - gx0) * config_.grid_cols / span_x);
            const auto cy = static_cast<std::int32_t>(static_cast<std::int64_t>(y - gy0) * config_.grid_rows / span_y);
            const std::size_t cell = static_cast<std::size_t>(cy) * static_cast<std::size_t>(config_.grid_cols) + static_cast<std::size_t>(cx);
            Candidate* slots = &cells_[cell * static_cast<std::size_t>(config_.per_cell)];
            std::int32_t& n = cellCount_[cell];
            std::int32_t pos = n;
            while (pos > 0 && slots[pos - 1].w < w) {  // bound: per_cell iterations
                --pos;
            }
            if (pos >= config_.per_cell) {
                continue;
            }
            const std::int32_t last = std::min(n, config_.per_cell - 1);
            for (std::int32_t k = last; k > pos; --k) {
                slots[k] = slots[k - 1];
            }
            slots[pos] = Candidate{w, q_[idx(x, y, width)], x, y};
            n = std::min(n + 1, config_.per_cell);
        }
    }
    return candidates;
}

// Spread candidates -> at most max_features (the strongest overall), written in cell order.
void ForstnerDetector::emitFeatures(FeatureSet& out) noexcept {
    const std::int32_t cells = config_.grid_cols * config_.grid_rows;
    const std::int32_t per = config_.per_cell;
    std::int32_t total = 0;
    for (std::int32_t c = 0; c < cells; ++c) {
        for (std::int32_t k = 0; k < cellCount_[static_cast<std::size_t>(c)]; ++k) {
            rank_[static_cast<std::size_t>(total)] = c * per + k;
            ++total;
        }
    }
    std::fill(keep_.data(), keep_.data() + keep_.size(), std::uint8_t{0});
    const std::int32_t kept = std::min(total, config_.max_features);
    if (total > kept) {
        const Candidate* slots = cells_.data();
        // Heap-based partial sort: no allocation, no recursion; strict total order, so the
        // selected set does not depend on the algorithm.
        std::partial_sort(rank_.data(), rank_.data() + kept, rank_.data() + total,
                          [slots](std::int32_t a, std::int32_t b) { return strongerThan(slots[a], slots[b]); });
    }
    for (std::int32_t i = 0; i < kept; ++i) {
        keep_[static_cast<std::size_t>(rank_[static_cast<std::size_t>(i)])] = 1U;
    }
    out.count = 0;
    for (std::int32_t c = 0; c < cells; ++c) {
        for (std::int32_t k = 0; k < cellCount_[static_cast<std::size_t>(c)]; ++k) {
            const std::size_t slot = static_cast<std::size_t>(c) * static_cast<std::size_t>(per) + static_cast<std::size_t>(k);
            if (keep_[slot] == 0U) {
                continue;
            }
            const Candidate& cand = cells_[slot];
            Feature& f = out.items[out.count];
            f.pixel = Vec2(static_cast<double>(cand.x), static_cast<double>(cand.y));
            f.strength = cand.w;
            f.roundness = cand.q;
            ++out.count;
        }
    }
}

// Removes every feature that lies closer than min_separation_px to a stronger one (ties: the
// earlier one stays), keeping the order of the rest. O(n^2) with n <= kMaxFeatures.
void ForstnerDetector::dropDuplicates(FeatureSet& out, float min_separation_px) noexcept {
    const double limit2 = static_cast<double>(min_separation_px) * static_cast<double>(min_separation_px);
    if (!(limit2 > 0.0)) {
        return;
    }
    bool duplicate[kMaxFeatures] = {};
    for (std::int32_t i = 0; i < out.count; ++i) {
        const Feature& f = out.items[i];
        for (std::int32_t j = 0; j < out.count && !duplicate[i]; ++j) {
            const Feature& g = out.items[j];
            const bool stronger = g.strength > f.strength || (g.strength == f.strength && j < i);
            duplicate[i] = j != i && stronger && (g.pixel - f.pixel).squaredNorm() < limit2;
        }
    }
    std::int32_t kept = 0;
    for (std::int32_t i = 0; i < out.count; ++i) {
        if (!duplicate[i]) {
            out.items[kept] = out.items[i];
            ++kept;
        }
    }
    out.count = kept;
}

// Offset of the vertex of the quadratic through w's 3x3 neighbourhood, each axis clamped to
// +-0.5 px (0 where the fit has no maximum).
Vec2 ForstnerDetector::quadraticOffset(std::int32_t x, std::int32_t y, std::int32_t width) const noexcept {
    auto at = [&](std::int32_t dx, std::int32_t dy) { return static_cast<double>(w_[idx(x + dx, y + dy, width)]); };
    const double c = at(0, 0);
    const double gx = 0.5 * (at(1, 0) - at(-1, 0));
    const double gy = 0.5 * (at(0, 1) - at(0, -1));
    const double hxx = at(1, 0) - 2.0 * c + at(-1, 0);
    const double hyy = at(0, 1) - 2.0 * c + at(0, -1);
    const double hxy = 0.25 * (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1));
    const double det = hxx * hyy - hxy * hxy;
    Vec2 off = Vec2::Zero();
    if (hxx < 0.0 && det > 0.0) {  // negative definite: a maximum
        off.x() = -(hyy * gx - hxy * gy) / det;
        off.y() = -(hxx * gy - hxy * gx) / det;
    }
    off.x() = std::clamp(off.x(), -0.5, 0.5);
    off.y() = std::clamp(off.y(), -0.5, 0.5);
    return off;
}

// Förstner's point: minimises sum over the window of (g_i . (p - p_i))^2, i.e. the point
// nearest to every edge line through the window's pixels: N p = sum g g^T p_i. The window
// is re-centred on the rounded estimate (at most kPointIterations times), because the
// estimate is best when the corner sits in the middle of the window; the result must stay
// within window/2 of the maximum of w, else the quadratic fit is used.
Vec2 ForstnerDetector::subpixelOffset(const ImageView<const std::uint8_t>& image, std::int32_t x, std::int32_t y,
                                      std::int32_t width) const noexcept {
    if (config_.subpixel == Subpixel::kQuadraticFit) {
        return quadraticOffset(x, y, width);
    }
    constexpr std::int32_t kPointIterations = 3;
    const std::int32_t h = config_.window / 2;
    std::int32_t cx = x, cy = y;
    Vec2 point(static_cast<double>(x), static_cast<double>(y));
    bool found = false;
    for (std::int32_t it = 0; it < kPointIterations; ++it) {
        Vec2 off;
        if (!pointEstimate(image, cx, cy, off) || std::fabs(off.x()) > static_cast<double>(h) ||
            std::fabs(off.y()) > static_cast<double>(h)) {
            break;
        }
        point = Vec2(static_cast<double>(cx), static_cast<double>(cy)) + off;
        found = true;
        const auto nx = static_cast<std::int32_t>(std::floor(point.x() + 0.5));
        const auto ny = static_cast<std::int32_t>(std::floor(point.y() + 0.5));
        if ((nx == cx && ny == cy) || std::abs(nx - x) > h || std::abs(ny - y) > h) {
            break;
        }
        cx = nx;
        cy = ny;
    }
    Vec2 offset = point - Vec2(static_cast<double>(x), static_cast<double>(y));
    if (!found || std::fabs(offset.x()) > static_cast<double>(h) || std::fabs(offset.y()) > static_cast<double>(h)) {
        return quadraticOffset(x, y, width);
    }
    return offset;
}

// One point estimate with the window centred on (x, y); false when N is singular.
bool ForstnerDetector::pointEstimate(const ImageView<const std::uint8_t>& image, std::int32_t x, std::int32_t y,
                                     Vec2& offset) const noexcept {
    const std::int32_t h = config_.window / 2;
    std::int64_t nxx = 0, nyy = 0, nxy = 0, bx = 0, by = 0;
    for (std::int32_t dy = -h; dy <= h; ++dy) {
        const std::uint8_t* u = image.row(y + dy - 1);
        const std::uint8_t* m = image.row(y + dy);
        const std::uint8_t* d = image.row(y + dy + 1);
        for (std::int32_t dx = -h; dx <= h; ++dx) {
            const Products p = productsAt(u, m, d, x + dx);
            nxx += p.xx;
            nyy += p.yy;
            nxy += p.xy;
            bx += static_cast<std::int64_t>(p.xx) * dx + static_cast<std::int64_t>(p.xy) * dy;
            by += static_cast<std::int64_t>(p.xy) * dx + static_cast<std::int64_t>(p.yy) * dy;
        }
    }
    const double det = static_cast<double>(nxx * nyy - nxy * nxy);
    if (!(det > 0.0)) {
        return false;
    }
    const auto dxx = static_cast<double>(nxx), dyy = static_cast<double>(nyy), dxy = static_cast<double>(nxy);
    const auto dbx = static_cast<double>(bx), dby = static_cast<double>(by);
    offset = Vec2((dyy * dbx - dxy * dby) / det, (dxx * dby - dxy * dbx) / det);
    return true;
}

Status ForstnerDetector::detect(const ImageView<const std::uint8_t>& image, FeatureSet& out,
                                DetectorStats* stats, const ImageView<const std::uint8_t>& mask) noexcept {
    out.count = 0;
    if (stats != nullptr) {
        *stats = DetectorStats{};
    }
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "ForstnerDetector::detect: init() has not succeeded");
    }
    if (!image.valid()) {
        return Status(StatusCode::kInvalidArgument, "ForstnerDetector::detect: image is empty or malformed");
    }
    if (image.width() > config_.max_width || image.height() > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "ForstnerDetector::detect: image exceeds max_width x max_height",
                      image.width() > config_.max_width ? image.width() : image.height());
    }
    const std::int32_t min_side = 2 * config_.border_px + 3;
    if (image.width() < min_side || image.height() < min_side) {
        return Status(StatusCode::kSizeMismatch, "ForstnerDetector::detect: image smaller than 2 * border_px + 3",
                      image.width() < min_side ? image.width() : image.height());
    }
    if (mask.data() != nullptr && (mask.width() != image.width() || mask.height() != image.height())) {
        return Status(StatusCode::kSizeMismatch, "ForstnerDetector::detect: mask is not the image's size",
                      mask.width());
    }
    computeStrength(image);
    const std::int32_t candidates = selectCandidates(image.width(), image.height(), mask);
    emitFeatures(out);
    for (std::int32_t i = 0; i < out.count; ++i) {
        Feature& f = out.items[i];
        const auto x = static_cast<std::int32_t>(f.pixel.x());
        const auto y = static_cast<std::int32_t>(f.pixel.y());
        f.pixel += subpixelOffset(image, x, y, image.width());
    }
    dropDuplicates(out, config_.min_separation_px);
    if (stats != nullptr) {
        stats->candidates = candidates;
        stats->kept = out.count;
    }
    return Status::ok();
}

}  // namespace vtm::features
