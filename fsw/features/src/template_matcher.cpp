// Guided coarse-to-fine NCC matching with a mutual check (template_matcher.hpp).
#include "vtm/features/template_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "vtm/core/math.hpp"

namespace vtm::features {
namespace {

constexpr std::int32_t kMaxCapacityPx = 4096;

// One direction of the search: from image `from` (where the template is) into `to`.
struct Geometry {
    const CameraModel* from = nullptr;
    const CameraModel* to = nullptr;
    Mat3 R_to_from = Mat3::Identity();
    Vec3 t_to_from_m = Vec3::Zero();
    double range_min_m = 1.0;
    double range_max_m = 100.0;
    double margin_px = 0.0;
};

enum class Outcome : std::uint8_t { kFound, kNoRegion, kNoMatch };

struct SearchResult {
    Outcome outcome = Outcome::kNoMatch;
    Vec2 pixel = Vec2::Zero();
    double score = -1.0;
};

struct Pos {
    std::int32_t x;
    std::int32_t y;
};

// Template sums (exact integers) of the window around (ax, ay) in `img`.
struct TemplateSums {
    std::int64_t sum = 0;
    std::int64_t sum_sq = 0;
};

std::int32_t roundToInt(double v) noexcept { return static_cast<std::int32_t>(std::floor(v + 0.5)); }

// Pixel centre convention: level-l pixel i averages level-(l-1) pixels 2i, 2i+1.
double toLevel(double x0, std::int32_t level) noexcept {
    const double scale = static_cast<double>(std::int32_t{1} << level);
    return (x0 + 0.5) / scale - 0.5;
}

bool templateFits(const ImageView<const std::uint8_t>& img, Pos p, std::int32_t half) noexcept {
    return p.x >= half && p.y >= half && p.x < img.width() - half && p.y < img.height() - half;
}

TemplateSums templateSums(const ImageView<const std::uint8_t>& img, Pos a, std::int32_t half) noexcept {
    TemplateSums s;
    for (std::int32_t dy = -half; dy <= half; ++dy) {
        const std::uint8_t* r = img.row(a.y + dy);
        for (std::int32_t dx = -half; dx <= half; ++dx) {
            const std::int64_t v = r[a.x + dx];
            s.sum += v;
            s.sum_sq += v * v;
        }
    }
    return s;
}

// NCC of the template around `a` in `from` with the window around `b` in `to`; both must
// fit. 0 when either window is flat (correlation undefined).
double ncc(const ImageView<const std::uint8_t>& from, Pos a, const TemplateSums& ts,
           const ImageView<const std::uint8_t>& to, Pos b, std::int32_t half) noexcept {
    std::int64_t sb = 0, sbb = 0, sab = 0;
    for (std::int32_t dy = -half; dy <= half; ++dy) {
        const std::uint8_t* ra = from.row(a.y + dy) + a.x;
        const std::uint8_t* rb = to.row(b.y + dy) + b.x;
        for (std::int32_t dx = -half; dx <= half; ++dx) {
            const std::int64_t va = ra[dx];
            const std::int64_t vb = rb[dx];
            sb += vb;
            sbb += vb * vb;
            sab += va * vb;
        }
    }
    const std::int64_t n = static_cast<std::int64_t>(2 * half + 1) * (2 * half + 1);
    const std::int64_t var_a = n * ts.sum_sq - ts.sum * ts.sum;
    const std::int64_t var_b = n * sbb - sb * sb;
    if (var_a <= 0 || var_b <= 0) {
        return 0.0;
    }
    const std::int64_t cov = n * sab - ts.sum * sb;
    return static_cast<double>(cov) / math::sqrt(static_cast<double>(var_a) * static_cast<double>(var_b));
}

// Projection into `to` of the ray through `pixel` of `from`, sampled uniformly in 1/range.
// Returns the number of samples that project (0: no region).
std::int32_t predictPolyline(const Geometry& g, const Vec2& pixel, Vec2 (&poly)[kRaySamples]) noexcept {
    CameraRay ray;
    if (!backProjectPixel(*g.from, pixel, ray).isOk()) {
        return 0;
    }
    const double inv_near = 1.0 / g.range_min_m;
    const double inv_far = 1.0 / g.range_max_m;
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < kRaySamples; ++k) {
        const double f = static_cast<double>(k) / static_cast<double>(kRaySamples - 1);
        const double range_m = 1.0 / (inv_near + (inv_far - inv_near) * f);
        const Vec3 x_from = ray.origin_m + range_m * ray.direction;
        const Vec3 x_to = g.R_to_from * x_from + g.t_to_from_m;
        Vec2 p;
        if (projectPoint(*g.to, x_to, p).isOk() && math::isFinite(p.x()) && math::isFinite(p.y())) {
            poly[n] = p;
            ++n;
        }
    }
    return n;
}

double distanceSqToPolyline(const Vec2& p, const Vec2* poly, std::int32_t n) noexcept {
    double best = (p - poly[0]).squaredNorm();
    for (std::int32_t i = 1; i < n; ++i) {
        const Vec2 d = poly[i] - poly[i - 1];
        const double len2 = d.squaredNorm();
        double s = 0.0;
        if (len2 > 0.0) {
            s = std::clamp((p - poly[i - 1]).dot(d) / len2, 0.0, 1.0);
        }
        const Vec2 q = poly[i - 1] + s * d;
        best = std::min(best, (p - q).squaredNorm());
    }
    return best;
}

// The level-`level` bounding box of the widened polyline, clipped to the positions where
// the template fits in `to`. Empty when lo > hi.
struct Box {
    Pos lo;
    Pos hi;
};
Box regionBox(const Vec2* poly, std::int32_t n, double margin, const ImageView<const std::uint8_t>& to,
              std::int32_t half) noexcept {
    double x0 = poly[0].x(), x1 = x0, y0 = poly[0].y(), y1 = y0;
    for (std::int32_t i = 1; i < n; ++i) {
        x0 = std::min(x0, poly[i].x());
        x1 = std::max(x1, poly[i].x());
        y0 = std::min(y0, poly[i].y());
        y1 = std::max(y1, poly[i].y());
    }
    // Clamp in floating point first: a far projection may not fit an int32.
    const double big = static_cast<double>(kMaxCapacityPx) * 4.0;
    auto clampInt = [big](double v) { return static_cast<std::int32_t>(std::clamp(v, -big, big)); };
    Box b{};
    b.lo.x = std::max(half, clampInt(std::ceil(x0 - margin)));
    b.lo.y = std::max(half, clampInt(std::ceil(y0 - margin)));
    b.hi.x = std::min(to.width() - 1 - half, clampInt(std::floor(x1 + margin)));
    b.hi.y = std::min(to.height() - 1 - half, clampInt(std::floor(y1 + margin)));
    return b;
}

struct Best {
    Pos pos{0, 0};
    double score = -2.0;
    std::int32_t evaluated = 0;
};

// Exhaustive NCC over the region at one level (raster order; the first of equal scores wins).
Best coarseSearch(const ImageView<const std::uint8_t>& from, Pos a, const ImageView<const std::uint8_t>& to,
                  const Vec2* poly, std::int32_t n, double margin, std::int32_t half) noexcept {
    Best best;
    const Box box = regionBox(poly, n, margin, to, half);
    const TemplateSums ts = templateSums(from, a, half);
    const double margin_sq = margin * margin;
    for (std::int32_t y = box.lo.y; y <= box.hi.y && best.evaluated < kMaxCoarseCandidates; ++y) {
        for (std::int32_t x = box.lo.x; x <= box.hi.x && best.evaluated < kMaxCoarseCandidates; ++x) {
            const Vec2 p(static_cast<double>(x), static_cast<double>(y));
            if (distanceSqToPolyline(p, poly, n) > margin_sq) {
                continue;
            }
            const double s = ncc(from, a, ts, to, Pos{x, y}, half);
            ++best.evaluated;
            if (s > best.score) {
                best.score = s;
                best.pos = Pos{x, y};
            }
        }
    }
    return best;
}

// Best NCC within +-radius of `centre` (positions where the template fits in `to`).
Best localSearch(const ImageView<const std::uint8_t>& from, Pos a, const ImageView<const std::uint8_t>& to,
                 Pos centre, std::int32_t radius, std::int32_t half) noexcept {
    Best best;
    const TemplateSums ts = templateSums(from, a, half);
    for (std::int32_t y = centre.y - radius; y <= centre.y + radius; ++y) {
        for (std::int32_t x = centre.x - radius; x <= centre.x + radius; ++x) {
            if (!templateFits(to, Pos{x, y}, half)) {
                continue;
            }
            const double s = ncc(from, a, ts, to, Pos{x, y}, half);
            ++best.evaluated;
            if (s > best.score) {
                best.score = s;
                best.pos = Pos{x, y};
            }
        }
    }
    return best;
}

// Vertex offset of the parabola through (-1, sm), (0, s0), (1, sp), clamped to +-0.5.
double parabolaOffset(double sm, double s0, double sp) noexcept {
    const double curvature = sm - 2.0 * s0 + sp;
    if (!(curvature < 0.0)) {
        return 0.0;
    }
    return std::clamp(0.5 * (sm - sp) / curvature, -0.5, 0.5);
}

// Subpixel position at full resolution around the integer best `b`.
Vec2 subpixel(const ImageView<const std::uint8_t>& from, Pos a, const ImageView<const std::uint8_t>& to, Pos b,
              double s0, std::int32_t half) noexcept {
    const TemplateSums ts = templateSums(from, a, half);
    Vec2 off = Vec2::Zero();
    if (templateFits(to, Pos{b.x - 1, b.y}, half) && templateFits(to, Pos{b.x + 1, b.y}, half)) {
        off.x() = parabolaOffset(ncc(from, a, ts, to, Pos{b.x - 1, b.y}, half), s0,
                                 ncc(from, a, ts, to, Pos{b.x + 1, b.y}, half));
    }
    if (templateFits(to, Pos{b.x, b.y - 1}, half) && templateFits(to, Pos{b.x, b.y + 1}, half)) {
        off.y() = parabolaOffset(ncc(from, a, ts, to, Pos{b.x, b.y - 1}, half), s0,
                                 ncc(from, a, ts, to, Pos{b.x, b.y + 1}, half));
    }
    return Vec2(static_cast<double>(b.x), static_cast<double>(b.y)) + off;
}

Pos levelPos(const Vec2& pixel, std::int32_t level) noexcept {
    return Pos{roundToInt(toLevel(pixel.x(), level)), roundToInt(toLevel(pixel.y(), level))};
}

// The whole search of one point: region, coarse level, refinement, subpixel.
SearchResult search(const TemplateMatcher::Pyramid& from, const TemplateMatcher::Pyramid& to, const Geometry& g,
                    const Vec2& pixel, std::int32_t half) noexcept {
    SearchResult r;
    r.outcome = Outcome::kNoRegion;
    const ImageView<const std::uint8_t>& img = from.level[0];
    if (!(pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= static_cast<double>(img.width()) - 0.5 &&
          pixel.y() <= static_cast<double>(img.height()) - 0.5)) {
        return r;  // outside its image (or NaN): no template
    }
    Vec2 poly[kRaySamples];
    const std::int32_t n = predictPolyline(g, pixel, poly);
    std::int32_t level = std::min(from.levels, to.levels);
    while (level >= 0 && !templateFits(from.level[level], levelPos(pixel, level), half)) {  // bound: <= kMaxPyramidLevels + 1
        --level;
    }
    if (n == 0 || level < 0) {
        return r;
    }
    for (std::int32_t i = 0; i < n; ++i) {
        poly[i] = Vec2(toLevel(poly[i].x(), level), toLevel(poly[i].y(), level));
    }
    const double margin = g.margin_px / static_cast<double>(std::int32_t{1} << level) + 0.5;
    Pos a = levelPos(pixel, level);
    Best best = coarseSearch(from.level[level], a, to.level[level], poly, n, margin, half);
    if (best.evaluated == 0) {
        return r;
    }
    r.outcome = Outcome::kNoMatch;
    for (std::int32_t l = level - 1; l >= 0; --l) {
        const Pos a_fine = levelPos(pixel, l);
        if (!templateFits(from.level[l], a_fine, half)) {
            return r;  // cannot happen: the template fits at a coarser level, so here too
        }
        const Pos predicted{a_fine.x + 2 * (best.pos.x - a.x), a_fine.y + 2 * (best.pos.y - a.y)};
        best = localSearch(from.level[l], a_fine, to.level[l], predicted, kRefineRadius, half);
        if (best.evaluated == 0) {
            return r;
        }
        a = a_fine;
    }
    const Vec2 b = subpixel(from.level[0], a, to.level[0], best.pos, best.score, half);
    r.outcome = Outcome::kFound;
    r.score = best.score;
    // The template was centred on the rounded feature position: carry its fraction over.
    r.pixel = b + (pixel - Vec2(static_cast<double>(a.x), static_cast<double>(a.y)));
    return r;
}

Geometry inverseOf(const Geometry& g) noexcept {
    Geometry inv;
    inv.from = g.to;
    inv.to = g.from;
    inv.R_to_from = g.R_to_from.transpose();
    inv.t_to_from_m = -(inv.R_to_from * g.t_to_from_m);
    // Ranges along B's ray differ from A's by at most the distance between the projection
    // centres (triangle inequality); the lower end is kept away from B's centre.
    CameraRay ray_a, ray_b;
    double baseline_m = 0.0;
    if (backProjectPixel(*g.from, Vec2::Zero(), ray_a).isOk() && backProjectPixel(*g.to, Vec2::Zero(), ray_b).isOk()) {
        baseline_m = (g.R_to_from * ray_a.origin_m + g.t_to_from_m - ray_b.origin_m).norm();
    }
    inv.range_min_m = std::max(g.range_min_m - baseline_m, 0.01 * g.range_min_m);
    inv.range_max_m = g.range_max_m + baseline_m;
    inv.margin_px = g.margin_px;
    return inv;
}

}  // namespace

Status MatcherConfig::validate() const noexcept {
    if (max_width < 1 || max_width > kMaxCapacityPx) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.max_width: must be 1..4096", max_width);
    }
    if (max_height < 1 || max_height > kMaxCapacityPx) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.max_height: must be 1..4096", max_height);
    }
    if (template_window < 3 || template_window > 31 || (template_window % 2) == 0) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.template_window: must be odd, 3..31",
                      template_window);
    }
    if (pyramid_levels < 0 || pyramid_levels > kMaxPyramidLevels) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.pyramid_levels: must be 0..4", pyramid_levels);
    }
    if (!(min_score >= -1.f && min_score <= 1.f)) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.min_score: must be in [-1, 1]");
    }
    if (!(mutual_tolerance_px > 0.f && mutual_tolerance_px < 1.0e6f)) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.mutual_tolerance_px: must be > 0 and finite");
    }
    return Status::ok();
}

namespace {
std::size_t pyramidBytes(const MatcherConfig& c) noexcept {
    std::size_t total = 0U;
    std::size_t w = static_cast<std::size_t>(c.max_width);
    std::size_t h = static_cast<std::size_t>(c.max_height);
    for (std::int32_t l = 1; l <= c.pyramid_levels; ++l) {
        w /= 2U;
        h /= 2U;
        total += w * h;
    }
    return total;
}
}  // namespace

std::size_t TemplateMatcher::workspaceBytes(const MatcherConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t bytes = pyramidBytes(config);
    // Pyramid levels 1..L of A, then of B (one block each; an empty block still pads).
    return 2U * Arena::blockBytes(bytes == 0U ? 1U : bytes);
}

Status TemplateMatcher::init(const MatcherConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t bytes = pyramidBytes(config);
    storageA_ = arena.allocateArray<std::uint8_t>(bytes == 0U ? 1U : bytes);
    storageB_ = arena.allocateArray<std::uint8_t>(bytes == 0U ? 1U : bytes);
    if (storageA_.empty() || storageB_.empty()) {
        return Status(StatusCode::kOutOfMemory, "TemplateMatcher::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

// 2x2 box average (rounded) per level; odd last rows/columns are dropped. A level is
// usable only if it still holds a template.
void TemplateMatcher::buildPyramid(const ImageView<const std::uint8_t>& image, Span<std::uint8_t> storage,
                                   Pyramid& pyramid) const noexcept {
    pyramid.level[0] = image;
    pyramid.levels = 0;
    std::size_t offset = 0U;
    for (std::int32_t l = 1; l <= config_.pyramid_levels; ++l) {
        const ImageView<const std::uint8_t>& src = pyramid.level[l - 1];
        const std::int32_t w = src.width() / 2;
        const std::int32_t h = src.height() / 2;
        if (w < config_.template_window || h < config_.template_window) {
            break;
        }
        std::uint8_t* dst = storage.data() + offset;
        for (std::int32_t y = 0; y < h; ++y) {
            const std::uint8_t* r0 = src.row(2 * y);
            const std::uint8_t* r1 = src.row(2 * y + 1);
            for (std::int32_t x = 0; x < w; ++x) {
                const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(x) * 2;
                const std::uint32_t s = static_cast<std::uint32_t>(r0[i]) + r0[i + 1] + r1[i] + r1[i + 1];
                dst[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
                    static_cast<std::uint8_t>((s + 2U) >> 2U);
            }
        }
        pyramid.level[l] = ImageView<const std::uint8_t>(dst, w, h);
        pyramid.levels = l;
        offset += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    }
}

namespace {
Status checkInputs(const MatcherConfig& c, const ImageView<const std::uint8_t>& image_a,
                   const ImageView<const std::uint8_t>& image_b, const FeatureSet& features_a,
                   const MatchPrediction& p) noexcept {
    if (!image_a.valid()) {
        return Status(StatusCode::kInvalidArgument, "TemplateMatcher::match: image_a is empty or malformed");
    }
    if (!image_b.valid()) {
        return Status(StatusCode::kInvalidArgument, "TemplateMatcher::match: image_b is empty or malformed");
    }
    if (image_a.width() > c.max_width || image_a.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, "TemplateMatcher::match: image_a exceeds max_width x max_height",
                      image_a.width());
    }
    if (image_b.width() > c.max_width || image_b.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, "TemplateMatcher::match: image_b exceeds max_width x max_height",
                      image_b.width());
    }
    if (p.model_a == nullptr || p.model_b == nullptr) {
        return Status(StatusCode::kInvalidArgument, "MatchPrediction: model_a or model_b is null");
    }
    if (p.model_a->width_px != image_a.width() || p.model_a->height_px != image_a.height()) {
        return Status(StatusCode::kSizeMismatch, "MatchPrediction.model_a: size differs from image_a",
                      p.model_a->width_px);
    }
    if (p.model_b->width_px != image_b.width() || p.model_b->height_px != image_b.height()) {
        return Status(StatusCode::kSizeMismatch, "MatchPrediction.model_b: size differs from image_b",
                      p.model_b->width_px);
    }
    if (!(math::isFinite(p.range_min_m) && math::isFinite(p.range_max_m) && p.range_min_m > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "MatchPrediction.range_min_m: must be > 0 and finite");
    }
    if (!(p.range_min_m < p.range_max_m)) {
        return Status(StatusCode::kInvalidArgument, "MatchPrediction.range_max_m: must exceed range_min_m");
    }
    if (!(math::isFinite(p.margin_px) && p.margin_px >= 0.0)) {
        return Status(StatusCode::kInvalidArgument, "MatchPrediction.margin_px: must be >= 0 and finite");
    }
    if (features_a.count < 0 || features_a.count > kMaxFeatures) {
        return Status(StatusCode::kInvalidArgument, "features_a.count: must be 0..kMaxFeatures", features_a.count);
    }
    return Status::ok();
}
}  // namespace

Status TemplateMatcher::match(const ImageView<const std::uint8_t>& image_a,
                              const ImageView<const std::uint8_t>& image_b, const FeatureSet& features_a,
                              const MatchPrediction& prediction, MatchSet& out, MatchStats* stats) noexcept {
    out.count = 0;
    MatchStats st;
    if (stats != nullptr) {
        *stats = st;
    }
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "TemplateMatcher::match: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkInputs(config_, image_a, image_b, features_a, prediction));
    Pyramid pa, pb;
    buildPyramid(image_a, storageA_, pa);
    buildPyramid(image_b, storageB_, pb);
    Geometry forward;
    forward.from = prediction.model_a;
    forward.to = prediction.model_b;
    forward.R_to_from = prediction.R_b_from_a;
    forward.t_to_from_m = prediction.t_b_from_a_m;
    forward.range_min_m = prediction.range_min_m;
    forward.range_max_m = prediction.range_max_m;
    forward.margin_px = prediction.margin_px;
    const Geometry backward = inverseOf(forward);
    const std::int32_t half = config_.template_window / 2;
    const auto tolerance = static_cast<double>(config_.mutual_tolerance_px);
    for (std::int32_t i = 0; i < features_a.count; ++i) {
        const Vec2& pixel_a = features_a.items[i].pixel;
        ++st.attempted;
        const SearchResult fwd = search(pa, pb, forward, pixel_a, half);
        if (fwd.outcome == Outcome::kNoRegion) {
            ++st.no_region;
            continue;
        }
        if (fwd.outcome != Outcome::kFound || fwd.score < static_cast<double>(config_.min_score)) {
            ++st.low_score;
            continue;
        }
        const SearchResult back = search(pb, pa, backward, fwd.pixel, half);
        if (back.outcome != Outcome::kFound || (back.pixel - pixel_a).norm() > tolerance) {
            ++st.not_mutual;
            continue;
        }
        Match& m = out.items[out.count];
        m.pixel_a = pixel_a;
        m.pixel_b = fwd.pixel;
        m.score = static_cast<float>(fwd.score);
        m.feature_index = i;
        ++out.count;
        ++st.matched;
    }
    if (stats != nullptr) {
        *stats = st;
    }
    return Status::ok();
}

}  // namespace vtm::features
