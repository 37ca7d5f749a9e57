// Guided coarse-to-fine NCC matching with a mutual check (template_matcher.hpp).
#include "vtm/features/template_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "bilinear.hpp"
#include "feature_limits.hpp"
#include "floor_int.hpp"
#include "polyline.hpp"
#include "template_ncc.hpp"
#include "vtm/core/image_pyramid.hpp"
#include "vtm/core/math.hpp"

namespace vtm::features {
namespace detail {
// A feature's forward search as the verification step needs it (TemplateMatcher::forward_).
struct ForwardMatch {
    Vec2 pixel = Vec2::Zero();  // in B, subpixel
    double score = -1.0;
    Affine2 warp{};             // the winning template's warp
    bool passed = false;        // found, with score >= min_score
    bool verify = false;        // passed, and among the max_verified best scores
};
}  // namespace detail

namespace {

using detail::kMaxCapacityPx;
using detail::kMaxWarpArea;
using detail::kMaxWarpEntry;
using detail::kWeightOne;
using detail::kWeightShift;
using detail::ncc;
using detail::nearestVertex;
static_assert(kRaySamples <= detail::kMaxPolylineVertices, "the ray's polyline must fit PolylineScan");
using detail::Pos;
using detail::Template;
// Step along the plane for the finite-difference Jacobians, relative to the range (the
// projection is smooth: only the ratio of the two Jacobians matters).
constexpr double kPlaneStepRel = 0.01;

using detail::Affine2;  // local affine map of pixel offsets (bilinear.hpp)

Vec2 apply(const Affine2& m, const Vec2& v) noexcept {
    return Vec2(m.a * v.x() + m.b * v.y(), m.c * v.x() + m.d * v.y());
}

bool invert(const Affine2& m, Affine2& inv) noexcept {
    const double det = m.a * m.d - m.b * m.c;
    if (!(std::fabs(det) > 1.0e-12)) {
        return false;
    }
    inv = Affine2{m.d / det, -m.b / det, -m.c / det, m.a / det};
    return true;
}

// One direction of the search: from image `from` (where the template is) into `to`.
struct Geometry {
    const CameraModel* from = nullptr;
    const CameraModel* to = nullptr;
    Mat3 R_to_from = Mat3::Identity();
    Vec3 t_to_from_m = Vec3::Zero();
    double range_min_m = 1.0;
    double range_max_m = 100.0;
    double margin_px = 0.0;
    Vec3 normal_from = Vec3::Zero();  // unit terrain normal in `from`'s frame; zero = unknown
    // `to`'s viewing axis (the ray through its image centre) in its own frame: depths
    // along it parametrise the ray's image (see RaySegment).
    Vec3 to_centre_m = Vec3::Zero();
    Vec3 to_axis = Vec3::UnitZ();
};

// Sets g.to_centre_m / g.to_axis from g.to's model.
void setAxis(Geometry& g) noexcept {
    CameraRay ray;
    const Vec2 centre(0.5 * (static_cast<double>(g.to->width_px) - 1.0), 0.5 * (static_cast<double>(g.to->height_px) - 1.0));
    if (backProjectPixel(*g.to, centre, ray).isOk()) {
        g.to_centre_m = ray.origin_m;
        g.to_axis = ray.direction;
    }
}

enum class Outcome : std::uint8_t { kFound, kNoRegion, kNoMatch };

struct SearchResult {
    Outcome outcome = Outcome::kNoMatch;
    Vec2 pixel = Vec2::Zero();
    double score = -1.0;
    Affine2 warp{};  // the warp of the template that won at full resolution
};

using detail::roundToInt;

// Pixel centre convention: level-l pixel i averages level-(l-1) pixels 2i, 2i+1.
double toLevel(double x0, std::int32_t level) noexcept {
    const double scale = static_cast<double>(std::int32_t{1} << level);
    return (x0 + 0.5) / scale - 0.5;
}
double fromLevel(double xl, std::int32_t level) noexcept {
    const double scale = static_cast<double>(std::int32_t{1} << level);
    return (xl + 0.5) * scale - 0.5;
}
Vec2 toLevel(const Vec2& p, std::int32_t level) noexcept { return Vec2(toLevel(p.x(), level), toLevel(p.y(), level)); }
Vec2 fromLevel(const Vec2& p, std::int32_t level) noexcept {
    return Vec2(fromLevel(p.x(), level), fromLevel(p.y(), level));
}
Vec2 toVec(Pos p) noexcept { return Vec2(static_cast<double>(p.x), static_cast<double>(p.y)); }

bool templateFits(const ImageView<const std::uint8_t>& img, Pos p, std::int32_t half) noexcept {
    return p.x >= half && p.y >= half && p.x < img.width() - half && p.y < img.height() - half;
}

// Template T(u) = img(centre + inv u) for u on the window grid (bilinear). With inv the
// identity every sample falls on a pixel: T is the plain window, scaled by kWeightOne.
Template buildTemplate(const ImageView<const std::uint8_t>& img, Pos centre, const Affine2& inv, std::int32_t half,
                       std::uint16_t* dst) noexcept {
    Template t;
    t.values = dst;
    detail::sampleQuantisedGrid(img, static_cast<double>(centre.x), static_cast<double>(centre.y), inv, half, dst);
    detail::setTemplateSums(t, half);
    return t;
}

// Local affine map from `from`-pixel offsets to `to`-pixel offsets induced by the plane
// with normal `n` through x_from: M = J_to J_from^-1, the Jacobians by projecting x_from
// and x_from + s e1, x_from + s e2 (e1, e2 spanning the plane) into both cameras.
bool planeAffine(const Geometry& g, const Vec3& x_from, const Vec3& n, double range_m, Affine2& m) noexcept {
    const Vec3 an = n.cwiseAbs();
    const Vec3 axis = (an.x() <= an.y() && an.x() <= an.z()) ? Vec3::UnitX()
                                                               : (an.y() <= an.z() ? Vec3::UnitY() : Vec3::UnitZ());
    const Vec3 e1 = n.cross(axis).normalized();
    const Vec3 e2 = n.normalized().cross(e1);
    const double s = kPlaneStepRel * range_m;
    const Vec3 pts[3] = {x_from, x_from + s * e1, x_from + s * e2};
    Vec2 pf[3], pt[3];
    for (std::int32_t i = 0; i < 3; ++i) {
        if (!projectPoint(*g.from, pts[i], pf[i]).isOk() ||
            !projectPoint(*g.to, g.R_to_from * pts[i] + g.t_to_from_m, pt[i]).isOk()) {
            return false;
        }
    }
    const Affine2 j_from{pf[1].x() - pf[0].x(), pf[2].x() - pf[0].x(), pf[1].y() - pf[0].y(), pf[2].y() - pf[0].y()};
    const Affine2 j_to{pt[1].x() - pt[0].x(), pt[2].x() - pt[0].x(), pt[1].y() - pt[0].y(), pt[2].y() - pt[0].y()};
    Affine2 j_from_inv;
    if (!invert(j_from, j_from_inv)) {
        return false;
    }
    m.a = j_to.a * j_from_inv.a + j_to.b * j_from_inv.c;
    m.b = j_to.a * j_from_inv.b + j_to.b * j_from_inv.d;
    m.c = j_to.c * j_from_inv.a + j_to.d * j_from_inv.c;
    m.d = j_to.c * j_from_inv.b + j_to.d * j_from_inv.d;
    const double det = m.a * m.d - m.b * m.c;  // < 0: the cameras see opposite sides
    const double biggest = std::max(std::max(std::fabs(m.a), std::fabs(m.b)), std::max(std::fabs(m.c), std::fabs(m.d)));
    return det >= 1.0 / kMaxWarpArea && det <= kMaxWarpArea && biggest <= kMaxWarpEntry;
}

// The warp at one ray sample for hypothesis `hyp`: 0 = the terrain plane if a normal is
// known (else hypothesis 1), 1 = the plane perpendicular to the ray (fronto-parallel);
// a plane whose warp is unusable falls back to the next, the last to the identity.
Affine2 sampleWarp(const Geometry& g, const Vec3& ray_dir, const Vec3& x_from, double range_m,
                   std::int32_t hyp) noexcept {
    Affine2 m;
    if (hyp == 0 && !g.normal_from.isZero(0.0) && planeAffine(g, x_from, g.normal_from, range_m, m)) {
        return m;
    }
    if (planeAffine(g, x_from, -ray_dir, range_m, m)) {
        return m;
    }
    return Affine2{};
}

// A's ray projected into `to`, at kRaySamples points spread evenly along its image
// (inside the image widened by the margin), with the warp at each. Samples that do not
// project are dropped.
// With a terrain normal two warps per sample are tried (kWarpHypotheses): the terrain
// plane and the fronto-parallel plane; the one with the higher NCC wins. Index of
// hypothesis h at sample k: h * kRaySamples + k.
constexpr std::int32_t kWarpHypotheses = 2;
constexpr std::size_t kBankRefineSlot = std::size_t{kWarpHypotheses} * std::size_t{kRaySamples};  // last bank slot
struct RaySamples {
    Vec2 pixel[kRaySamples];                       // projections into `to`, full resolution
    Affine2 warp[kWarpHypotheses * kRaySamples];   // from-offsets -> to-offsets at that sample
    Affine2 unwarp[kWarpHypotheses * kRaySamples];
    std::int32_t n = 0;
    std::int32_t hypotheses = 1;
};

// The ray segment X(r) = origin + r dir, r in [r0, r1], with the depths d0, d1 of its
// ends along `to`'s axis (both > 0). Its image is (for a pinhole, exactly) a straight
// segment along which the pixel moves linearly in tau: r(tau) = beta / alpha with
// alpha = (1-tau)/d0 + tau/d1, beta = (1-tau) r0/d0 + tau r1/d1 (the point of the chord
// between the two ends' depth-normalised images, pulled back onto the ray).
struct RaySegment {
    Vec3 origin_m = Vec3::Zero();
    Vec3 dir = Vec3::UnitZ();
    double r0 = 0.0, r1 = 0.0, d0 = 1.0, d1 = 1.0;
};

double rangeAtTau(const RaySegment& s, double tau) noexcept {
    const double alpha = (1.0 - tau) / s.d0 + tau / s.d1;
    const double beta = (1.0 - tau) * s.r0 / s.d0 + tau * s.r1 / s.d1;
    return beta / alpha;
}

// The part of [range_min, range_max] of the ray through `pixel` that lies in front of
// `to` (depth along its axis at least 1e-3 range_min). False when there is none.
bool raySegment(const Geometry& g, const Vec2& pixel, RaySegment& seg) noexcept {
    CameraRay ray;
    if (!backProjectPixel(*g.from, pixel, ray).isOk()) {
        return false;
    }
    seg.origin_m = ray.origin_m;
    seg.dir = ray.direction;
    const double k0 = g.to_axis.dot(g.R_to_from * ray.origin_m + g.t_to_from_m - g.to_centre_m);
    const double k1 = g.to_axis.dot(g.R_to_from * ray.direction);
    const double eps = 1.0e-3 * g.range_min_m;
    seg.r0 = g.range_min_m;
    seg.r1 = g.range_max_m;
    if (k1 > 0.0) {
        seg.r0 = std::max(seg.r0, (eps - k0) / k1);
    } else if (k1 < 0.0) {
        seg.r1 = std::min(seg.r1, (k0 - eps) / -k1);
    } else if (k0 < eps) {
        return false;
    }
    seg.d0 = k0 + seg.r0 * k1;
    seg.d1 = k0 + seg.r1 * k1;
    return seg.r0 < seg.r1 && seg.d0 > 0.0 && seg.d1 > 0.0;
}

bool projectAt(const Geometry& g, const RaySegment& seg, double tau, Vec3& x_from, double& range_m,
               Vec2& p) noexcept {
    range_m = rangeAtTau(seg, tau);
    x_from = seg.origin_m + range_m * seg.dir;
    return projectPoint(*g.to, g.R_to_from * x_from + g.t_to_from_m, p).isOk() && math::isFinite(p.x()) &&
           math::isFinite(p.y());
}

// Whether the segment p..q meets the rectangle [lo, hi] (Liang-Barsky clipping).
bool segmentMeetsBox(const Vec2& p, const Vec2& q, const Vec2& lo, const Vec2& hi) noexcept {
    double t0 = 0.0, t1 = 1.0;
    const double d[2] = {q.x() - p.x(), q.y() - p.y()};
    const double start[2] = {p.x(), p.y()};
    const double lows[2] = {lo.x(), lo.y()};
    const double highs[2] = {hi.x(), hi.y()};
    for (std::int32_t i = 0; i < 2; ++i) {
        if (d[i] == 0.0) {
            if (start[i] < lows[i] || start[i] > highs[i]) {
                return false;
            }
            continue;
        }
        const double ta = (lows[i] - start[i]) / d[i];
        const double tb = (highs[i] - start[i]) / d[i];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
}

// The tau interval whose image meets `to`'s image widened by margin_px + 1: a scan of
// kPreSamples + 1 points (a piece between two points that project counts when its chord
// meets the widened image). False when no part of the ray is seen there.
constexpr std::int32_t kPreSamples = 128;
bool visibleTau(const Geometry& g, const RaySegment& seg, double& tau_lo, double& tau_hi) noexcept {
    const double m = g.margin_px + 1.0;
    const Vec2 lo(-m, -m);
    const Vec2 hi(static_cast<double>(g.to->width_px) - 1.0 + m, static_cast<double>(g.to->height_px) - 1.0 + m);
    std::int32_t first = -1, last = -1;
    bool prev_ok = false;
    Vec2 prev = Vec2::Zero();
    for (std::int32_t i = 0; i <= kPreSamples; ++i) {
        Vec3 x;
        double r = 0.0;
        Vec2 p;
        const bool ok = projectAt(g, seg, static_cast<double>(i) / kPreSamples, x, r, p);
        if (ok && (segmentMeetsBox(prev_ok ? prev : p, p, lo, hi))) {
            first = (first < 0) ? (prev_ok ? i - 1 : i) : first;
            last = i;
        }
        prev_ok = ok;
        prev = p;
    }
    if (first < 0) {
        return false;
    }
    tau_lo = static_cast<double>(first) / kPreSamples;
    tau_hi = static_cast<double>(last) / kPreSamples;
    return true;
}

void predictSamples(const Geometry& g, const Vec2& pixel, RaySamples& rs) noexcept {
    rs.n = 0;
    rs.hypotheses = g.normal_from.isZero(0.0) ? 1 : kWarpHypotheses;
    RaySegment seg;
    double tau_lo = 0.0, tau_hi = 0.0;
    if (!raySegment(g, pixel, seg) || !visibleTau(g, seg, tau_lo, tau_hi)) {
        return;
    }
    for (std::int32_t k = 0; k < kRaySamples; ++k) {
        const double f = static_cast<double>(k) / static_cast<double>(kRaySamples - 1);
        Vec3 x_from;
        double range_m = 0.0;
        Vec2 p;
        if (!projectAt(g, seg, tau_lo + (tau_hi - tau_lo) * f, x_from, range_m, p)) {
            continue;
        }
        for (std::int32_t h = 0; h < rs.hypotheses; ++h) {
            const std::int32_t w_index = h * kRaySamples + rs.n;  // < kWarpHypotheses * kRaySamples
            const auto w = static_cast<std::size_t>(w_index);
            rs.warp[w] = sampleWarp(g, seg.dir, x_from, range_m, h);
            if (!invert(rs.warp[w], rs.unwarp[w])) {
                rs.warp[w] = Affine2{};  // cannot happen: sampleWarp returns an invertible map
                rs.unwarp[w] = Affine2{};
            }
        }
        rs.pixel[rs.n] = p;
        ++rs.n;
    }
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

// Smallest stride s >= 1 for which the box's s-grid holds at most kMaxCoarseCandidates
// positions (the whole region is always covered; only its sampling gets sparser).
std::int32_t regionStride(const Box& box) noexcept {
    const std::int64_t w = box.hi.x - box.lo.x + 1;
    const std::int64_t h = box.hi.y - box.lo.y + 1;
    std::int64_t s = 1;
    while (((w + s - 1) / s) * ((h + s - 1) / s) > kMaxCoarseCandidates) {  // bound: s <= max(w, h) <= 4 * 4096
        ++s;
    }
    return static_cast<std::int32_t>(s);
}

struct Best {
    Pos pos{0, 0};
    double score = -2.0;
    std::int32_t evaluated = 0;
    std::int32_t sample = 0;  // ray sample whose template scored best
    std::int32_t stride = 1;  // grid step of the search (coarse level)
};

// Scratch of one search: the template of every ray sample at the coarse level (built on
// first use) and one slot for the refinement levels.
struct TemplateBank {
    std::uint16_t* storage = nullptr;  // (kWarpHypotheses * kRaySamples + 1) * window^2 values
    std::size_t stride = 0U;           // window^2
    std::int32_t half = 0;             // template half width (window / 2)
    detail::PolylineScan* scan = nullptr;  // the matcher's (arena)
    std::uint32_t* column_sum = nullptr;     // max_width each (arena): the coarse search's
    std::uint32_t* column_sum_sq = nullptr;  // column sums (detail::ColumnSums)
    float* float_storage = nullptr;  // kWarpHypotheses * kRaySamples * window^2: the coarse ones as floats
    Template coarse[kWarpHypotheses * kRaySamples];
    bool built[kWarpHypotheses * kRaySamples] = {};
    bool float_made[kWarpHypotheses * kRaySamples] = {};  // its float copy too (float_storage)
};

struct LevelView {
    const ImageView<const std::uint8_t>* from;
    const ImageView<const std::uint8_t>* to;
    Pos a;              // template centre in `from` (rounded feature position)
    std::int32_t half;  // template half width
    const ImageView<const float>* to_float;  // `to` as floats (Pyramid::coarse_float), or nullptr
};

// The first and last positions of the box's s-grid on the current row that lie in the
// scan's span (PolylineScan::span: no other position can be within); first > last: none.
void gridSpan(const detail::PolylineScan& scan, const Box& box, std::int32_t step, std::int32_t& first,
              std::int32_t& last) noexcept {
    first = 0;
    last = -1;
    double lo = 0.0, hi = 0.0;
    scan.span(lo, hi);
    // math::floor: no libm call per row on the 750; ceil(lo) = -floor(-lo).
    const double a = std::max(static_cast<double>(box.lo.x), -math::floor(-lo));  // -inf: the box
    const double b = std::min(static_cast<double>(box.hi.x), math::floor(hi));
    if (!(lo <= hi) || !(a <= b)) {
        return;
    }
    const std::int32_t offset = static_cast<std::int32_t>(a) - box.lo.x;  // >= 0
    first = box.lo.x + ((offset + step - 1) / step) * step;             // rounded up onto the grid
    last = static_cast<std::int32_t>(b);
}

// One position of the coarse search with the templates of its ray sample (built on
// first use): the window's sums (from `columns` when given, else from its own pass) and
// its products with each hypothesis's template; the square root only where the score may
// beat the best (detail::nccIfAbove: the same best). Keeps the first of equal scores.
struct Candidate {
    Pos at;
    std::int32_t vertex;  // the ray sample nearest to it
};
void scorePosition(const LevelView& v, const RaySamples& rs, TemplateBank& bank, detail::ColumnSums* columns,
                   Candidate c, Best& best) noexcept {
    const Pos at = c.at;
    const std::int32_t vertex = c.vertex;
    const Template* templates[kWarpHypotheses];
    for (std::int32_t h = 0; h < rs.hypotheses; ++h) {
        const std::size_t k = static_cast<std::size_t>(h) * std::size_t{kRaySamples} + static_cast<std::size_t>(vertex);
        if (!bank.built[k]) {
            bank.coarse[k] = buildTemplate(*v.from, v.a, rs.unwarp[k], v.half, bank.storage + k * bank.stride);
            bank.built[k] = true;
        }
        templates[h] = &bank.coarse[k];
    }
    double cross[kWarpHypotheses] = {};
    detail::WindowStats window;
    if (columns != nullptr) {
        window = detail::windowFromColumns(*columns, at.x, v.half);
        detail::crossSums(templates, rs.hypotheses, *v.to, at, v.half, cross);
    } else {
        window = detail::windowAndCrossSums(templates, rs.hypotheses, *v.to, at, v.half, cross);
    }
    for (std::int32_t h = 0; h < rs.hypotheses; ++h) {
        const double s = detail::nccIfAbove(*templates[h], window, cross[h], v.half, best.score);
        if (s > best.score) {
            best.score = s;
            best.pos = at;
            best.sample = h * kRaySamples + vertex;
        }
    }
}

// Consecutive positions of a row, first.at and the next count - 1 to its right, that share
// their ray sample (first.vertex): their products in one pass from the float level
// (detail::crossSumsFloatRun), then each scored in order as scorePosition would.
struct Run {
    Candidate first{};
    std::int32_t count = 0;
};
void scoreRun(const LevelView& v, const RaySamples& rs, TemplateBank& bank, detail::ColumnSums& columns,
              const Run& run, Best& best) noexcept {
    const Template* templates[kWarpHypotheses];
    const float* floats[kWarpHypotheses];
    for (std::int32_t h = 0; h < rs.hypotheses; ++h) {
        const std::size_t k =
            static_cast<std::size_t>(h) * std::size_t{kRaySamples} + static_cast<std::size_t>(run.first.vertex);
        if (!bank.built[k]) {
            bank.coarse[k] = buildTemplate(*v.from, v.a, rs.unwarp[k], v.half, bank.storage + k * bank.stride);
            bank.built[k] = true;
        }
        float* f = bank.float_storage + k * bank.stride;
        if (!bank.float_made[k]) {
            detail::toFloats(bank.coarse[k].values, static_cast<std::int32_t>(bank.stride), f);
            bank.float_made[k] = true;
        }
        templates[h] = &bank.coarse[k];
        floats[h] = f;
    }
    double cross[detail::kMaxRun * kWarpHypotheses] = {};
    // A local copy: the stores to `columns` below could alias v.half, which would be read
    // (and converted to double) again at every position.
    const std::int32_t half = v.half;
    detail::crossSumsFloatRun(floats, rs.hypotheses, *v.to_float, run.first.at, run.count, half, cross);
    for (std::int32_t k = 0; k < run.count; ++k) {
        const Candidate c{Pos{run.first.at.x + k, run.first.at.y}, run.first.vertex};
        const detail::WindowStats window = detail::windowFromColumns(columns, c.at.x, half);
        for (std::int32_t h = 0; h < rs.hypotheses; ++h) {  // as scorePosition
            const double score = detail::nccIfAbove(*templates[h], window, cross[k * rs.hypotheses + h], half, best.score);
            if (score > best.score) {
                best.score = score;
                best.pos = c.at;
                best.sample = h * kRaySamples + c.vertex;
            }
        }
    }
}

// Adds c to the run, scoring the run first when c cannot join it (another sample, not
// next to it, or the run full).
void extendRun(const LevelView& v, const RaySamples& rs, TemplateBank& bank, detail::ColumnSums& columns, Candidate c,
               Run& run, Best& best) noexcept {
    if (run.count > 0 && (c.vertex != run.first.vertex || c.at.x != run.first.at.x + run.count ||
                          c.at.y != run.first.at.y || run.count == detail::kMaxRun)) {
        scoreRun(v, rs, bank, columns, run, best);
        run.count = 0;
    }
    if (run.count == 0) {
        run.first = c;
    }
    ++run.count;
}

// NCC over the region at one level, on the stride regionStride() gives (raster order;
// the first of equal scores wins). Each position uses the template of its nearest sample.
Best coarseSearch(const LevelView& v, const RaySamples& rs, const Vec2* poly, double margin,
                  TemplateBank& bank) noexcept {
    Best best;
    const Box box = regionBox(poly, rs.n, margin, *v.to, v.half);
    if (box.lo.x > box.hi.x || box.lo.y > box.hi.y) {
        return best;
    }
    const std::int32_t step = regionStride(box);
    // detail::withinPolyline / nearestVertex, row by row (the same answers).
    detail::PolylineScan& scan = *bank.scan;
    scan.set(poly, rs.n, margin * margin);
    // On the unit grid the window's own sums come from column sums slid down row by row
    // (the same integers as a pass over the window); a strided grid sums each window.
    const bool slide = step == 1;
    const bool runs = detail::kFloatProducts && slide && v.to_float != nullptr;  // constant false elsewhere
    detail::ColumnSums columns{bank.column_sum, bank.column_sum_sq, box.lo.x - v.half, box.hi.x + v.half, 0};
    for (std::int32_t y = box.lo.y; y <= box.hi.y; y += step) {
        scan.row(static_cast<double>(y));
        if (slide) {
            if (y == box.lo.y) {
                detail::setColumnSums(columns, *v.to, y, v.half);
            } else {
                detail::slideColumnSums(columns, *v.to, v.half);
            }
        }
        std::int32_t x_first = 0, x_last = -1;
        gridSpan(scan, box, step, x_first, x_last);
        Run run;  // with the float level: positions wait in runs that share their templates
        for (std::int32_t x = x_first; x <= x_last; x += step) {
            const auto xd = static_cast<double>(x);
            if (!scan.within(xd)) {
                continue;
            }
            const Candidate c{Pos{x, y}, scan.nearest(xd)};
            // cppcheck-suppress knownConditionTrueFalse ; false where detail::kFloatProducts is (x86-64)
            if (runs) {
                extendRun(v, rs, bank, columns, c, run, best);
            } else {
                scorePosition(v, rs, bank, slide ? &columns : nullptr, c, best);
            }
            ++best.evaluated;
        }
        if (run.count > 0) {
            scoreRun(v, rs, bank, columns, run, best);  // before the column sums slide
        }
    }
    best.stride = step;
    return best;
}

// Best NCC of template t within +-radius of `centre` (positions where it fits in `to`).
Best localSearch(const Template& t, const ImageView<const std::uint8_t>& to, Pos centre, std::int32_t radius,
                 std::int32_t half) noexcept {
    Best best;
    for (std::int32_t y = centre.y - radius; y <= centre.y + radius; ++y) {
        for (std::int32_t x = centre.x - radius; x <= centre.x + radius; ++x) {
            if (!templateFits(to, Pos{x, y}, half)) {
                continue;
            }
            ++best.evaluated;
            const Template* one[1] = {&t};
            double cross = 0.0;
            const detail::WindowStats window = detail::windowAndCrossSums(one, 1, to, Pos{x, y}, half, &cross);
            const double s = detail::nccIfAbove(t, window, cross, half, best.score);
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

// Subpixel position at full resolution around the integer best `b`: a 2D quadratic
// through the 3x3 NCC neighbourhood (with the cross term: a warped template gives a
// tilted, elongated peak, which separate parabolas in x and y would locate with a bias),
// its vertex clamped to +-0.5 px; separate parabolas when the quadratic has no maximum or
// the neighbourhood leaves the image.
Vec2 subpixel(const Template& t, const ImageView<const std::uint8_t>& to, Pos b, double s0,
              std::int32_t half) noexcept {
    if (!templateFits(to, Pos{b.x - 1, b.y - 1}, half) || !templateFits(to, Pos{b.x + 1, b.y + 1}, half)) {
        return toVec(b);
    }
    double s[3][3];
    for (std::int32_t dy = -1; dy <= 1; ++dy) {
        for (std::int32_t dx = -1; dx <= 1; ++dx) {
            s[dy + 1][dx + 1] = (dx == 0 && dy == 0) ? s0 : ncc(t, to, Pos{b.x + dx, b.y + dy}, half);
        }
    }
    const double gx = 0.5 * (s[1][2] - s[1][0]);
    const double gy = 0.5 * (s[2][1] - s[0][1]);
    const double hxx = s[1][2] - 2.0 * s0 + s[1][0];
    const double hyy = s[2][1] - 2.0 * s0 + s[0][1];
    const double hxy = 0.25 * (s[2][2] - s[0][2] - s[2][0] + s[0][0]);
    const double det = hxx * hyy - hxy * hxy;
    Vec2 off(parabolaOffset(s[1][0], s0, s[1][2]), parabolaOffset(s[0][1], s0, s[2][1]));
    if (hxx < 0.0 && det > 0.0) {  // negative definite: a maximum
        off.x() = std::clamp(-(hyy * gx - hxy * gy) / det, -0.5, 0.5);
        off.y() = std::clamp(-(hxx * gy - hxy * gx) / det, -0.5, 0.5);
    }
    return toVec(b) + off;
}

Pos levelPos(const Vec2& pixel, std::int32_t level) noexcept {
    return Pos{roundToInt(toLevel(pixel.x(), level)), roundToInt(toLevel(pixel.y(), level))};
}

// The coarsest level (<= both pyramids' depth) where the template fits around `pixel`.
std::int32_t coarseLevel(const TemplateMatcher::Pyramid& from, const TemplateMatcher::Pyramid& to, const Vec2& pixel,
                         std::int32_t half) noexcept {
    std::int32_t level = std::min(from.levels, to.levels);
    while (level >= 0 && !templateFits(from.level[level], levelPos(pixel, level), half)) {  // bound: <= kMaxPyramidLevels + 1
        --level;
    }
    return level;
}

// State carried from level to level: where the feature itself lies in `to` (level
// coordinates, subpixel) and the score there.
struct Estimate {
    Vec2 feature_to = Vec2::Zero();
    double score = -2.0;
    Affine2 warp{};
    bool ok = false;
};

// Search at level l with the template of the ray sample nearest to the estimate (warp
// hypothesis `hyp`), within `radius` of it; at level 0 the result is subpixel.
struct RefineStep {
    std::int32_t level;
    std::int32_t radius;
    std::int32_t hyp;
};
Estimate refineAt(const TemplateMatcher::Pyramid& from, const TemplateMatcher::Pyramid& to, const RaySamples& rs,
                  const Vec2& pixel, const RefineStep& step, const Vec2& feature_to_l, std::int32_t half,
                  TemplateBank& bank) noexcept {
    const std::int32_t l = step.level;
    Estimate e;
    const Pos a = levelPos(pixel, l);
    if (!templateFits(from.level[l], a, half)) {
        return e;  // cannot happen: the template fits at a coarser level, so here too
    }
    const std::int32_t k_index =
        step.hyp * kRaySamples + nearestVertex(fromLevel(feature_to_l, l), rs.pixel, rs.n);
    const auto k = static_cast<std::size_t>(k_index);
    const Vec2 frac = toLevel(pixel, l) - toVec(a);  // feature minus template centre, level l
    const Vec2 centre_to = feature_to_l - apply(rs.warp[k], frac);
    const Pos predicted{roundToInt(centre_to.x()), roundToInt(centre_to.y())};
    const Template t = buildTemplate(from.level[l], a, rs.unwarp[k], half,
                                     bank.storage + kBankRefineSlot * bank.stride);
    const Best best = localSearch(t, to.level[l], predicted, step.radius, half);
    if (best.evaluated == 0) {
        return e;
    }
    const Vec2 b = (l == 0) ? subpixel(t, to.level[0], best.pos, best.score, half) : toVec(best.pos);
    e.feature_to = b + apply(rs.warp[k], frac);
    e.score = best.score;
    e.warp = rs.warp[k];
    e.ok = true;
    return e;
}

// The whole search of one point: region, coarse level, refinement, subpixel.
// Six arguments (plus the hidden result pointer) so that every one travels in a register
// on x86-64: a seventh would be pushed, which -fstack-usage reports as a dynamic frame.
SearchResult search(const TemplateMatcher::Pyramid& from, const TemplateMatcher::Pyramid& to, const Geometry& g,
                    const Vec2& pixel, TemplateBank& bank) noexcept {
    const std::int32_t half = bank.half;
    SearchResult r;
    r.outcome = Outcome::kNoRegion;
    const ImageView<const std::uint8_t>& img = from.level[0];
    if (!(pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= static_cast<double>(img.width()) - 0.5 &&
          pixel.y() <= static_cast<double>(img.height()) - 0.5)) {
        return r;  // outside its image (or NaN): no template
    }
    RaySamples rs;
    predictSamples(g, pixel, rs);
    const std::int32_t level = coarseLevel(from, to, pixel, half);
    if (rs.n == 0 || level < 0) {
        return r;
    }
    Vec2 poly[kRaySamples];
    for (std::int32_t i = 0; i < rs.n; ++i) {
        poly[i] = toLevel(rs.pixel[i], level);
    }
    for (std::size_t k = 0; k < std::size_t{kWarpHypotheses} * std::size_t{kRaySamples}; ++k) {
        bank.built[k] = false;
        bank.float_made[k] = false;
    }
    const double margin = g.margin_px / static_cast<double>(std::int32_t{1} << level) + 0.5;
    const LevelView v{&from.level[level], &to.level[level], levelPos(pixel, level), half,
                      level == to.float_level ? &to.coarse_float : nullptr};
    const Best coarse = coarseSearch(v, rs, poly, margin, bank);
    if (coarse.evaluated == 0) {
        return r;
    }
    r.outcome = Outcome::kNoMatch;
    Estimate e;
    e.feature_to = toVec(coarse.pos) + apply(rs.warp[coarse.sample], toLevel(pixel, level) - toVec(v.a));
    // At the coarse level itself: closes the gaps of a strided search (radius = stride),
    // or (radius 0) re-scores with the template of the sample nearest to the feature.
    for (std::int32_t l = level; l >= 0; --l) {
        const bool top = l == level;
        const Vec2 predicted = top ? e.feature_to : Vec2(2.0 * e.feature_to.x() + 0.5, 2.0 * e.feature_to.y() + 0.5);
        const RefineStep step{l, top ? (coarse.stride > 1 ? coarse.stride : 0) : kRefineRadius,
                              coarse.sample / kRaySamples};
        e = refineAt(from, to, rs, pixel, step, predicted, half, bank);
        if (!e.ok) {
            return r;
        }
    }
    r.outcome = Outcome::kFound;
    r.score = e.score;
    r.pixel = e.feature_to;
    r.warp = e.warp;
    return r;
}

Geometry inverseOf(const Geometry& g) noexcept {
    Geometry inv;
    inv.from = g.to;
    inv.to = g.from;
    inv.R_to_from = g.R_to_from.transpose();
    inv.t_to_from_m = -(inv.R_to_from * g.t_to_from_m);
    inv.normal_from = g.R_to_from * g.normal_from;
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
    if (max_verified < 1 || max_verified > kMaxFeatures) {
        return Status(StatusCode::kInvalidConfig, "MatcherConfig.max_verified: must be 1..kMaxFeatures", max_verified);
    }
    if (refine_affine) {
        VTM_RETURN_IF_ERROR(affine.validate());
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
// Template bank: kWarpHypotheses * kRaySamples coarse templates + 1 refinement template,
// window^2 values each.
std::size_t bankValues(const MatcherConfig& c) noexcept {
    const auto w = static_cast<std::size_t>(c.template_window);
    return static_cast<std::size_t>(kWarpHypotheses * kRaySamples + 1) * w * w;
}
// The coarsest level as floats (Pyramid::coarse_float), per pyramid (when plansFloats()).
std::size_t floatLevelValues(const MatcherConfig& c) noexcept {
    return (static_cast<std::size_t>(c.max_width) >> c.pyramid_levels) *
           (static_cast<std::size_t>(c.max_height) >> c.pyramid_levels);
}
// The coarse templates as floats: kWarpHypotheses * kRaySamples of window^2.
std::size_t floatBankValues(const MatcherConfig& c) noexcept {
    const auto w = static_cast<std::size_t>(c.template_window);
    return static_cast<std::size_t>(kWarpHypotheses * kRaySamples) * w * w;
}
// The float blocks (A's and B's coarsest level, the templates): none where
// kFloatProducts is false, and none without pyramid levels.
bool plansFloats(const MatcherConfig& c) noexcept { return detail::kFloatProducts && c.pyramid_levels > 0; }
std::size_t floatBlockBytes(const MatcherConfig& c) noexcept {
    if (!plansFloats(c)) {
        return 0U;
    }
    return 2U * Arena::blockBytes(floatLevelValues(c) * sizeof(float)) +
           Arena::blockBytes(floatBankValues(c) * sizeof(float));
}
// The coarse search's column sums: one uint32 per column of the widest level, twice.
std::size_t columnSumBytes(const MatcherConfig& c) noexcept {
    return static_cast<std::size_t>(c.max_width) * sizeof(std::uint32_t);
}
}  // namespace

std::size_t TemplateMatcher::workspaceBytes(const MatcherConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const std::size_t bytes = pyramidBytes(config);
    // Pyramid levels 1..L of A, then of B (one block each; an empty block still pads),
    // then the template bank, the polyline scan, the coarse search's column sums, the
    // forward results and (where plansFloats) the coarsest levels and the coarse templates
    // as floats. Each block is padded on its own, so the sum does not depend on the order.
    return 2U * Arena::blockBytes(bytes == 0U ? 1U : bytes) +
           Arena::blockBytes(bankValues(config) * sizeof(std::uint16_t)) + Arena::constructBytes<detail::PolylineScan>(1U) +
           floatBlockBytes(config) +
           2U * Arena::blockBytes(columnSumBytes(config)) +
           Arena::constructBytes<detail::ForwardMatch>(static_cast<std::size_t>(kMaxFeatures));
}

Status TemplateMatcher::init(const MatcherConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    prepared_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::size_t bytes = pyramidBytes(config);
    storageA_ = arena.allocateArray<std::uint8_t>(bytes == 0U ? 1U : bytes);
    storageB_ = arena.allocateArray<std::uint8_t>(bytes == 0U ? 1U : bytes);
    bank_ = arena.allocateArray<std::uint16_t>(bankValues(config));
    scan_ = arena.construct<detail::PolylineScan>(1U);
    columnSum_ = arena.allocateArray<std::uint32_t>(static_cast<std::size_t>(config.max_width));
    columnSumSq_ = arena.allocateArray<std::uint32_t>(static_cast<std::size_t>(config.max_width));
    forward_ = arena.construct<detail::ForwardMatch>(static_cast<std::size_t>(kMaxFeatures));
    const bool floats = plansFloats(config);
    floatA_ = floats ? arena.allocateArray<float>(floatLevelValues(config)) : Span<float>();
    floatB_ = floats ? arena.allocateArray<float>(floatLevelValues(config)) : Span<float>();
    floatBank_ = floats ? arena.allocateArray<float>(floatBankValues(config)) : Span<float>();
    if (storageA_.empty() || storageB_.empty() || bank_.empty() || scan_ == nullptr || columnSum_.empty() ||
        columnSumSq_.empty() || forward_ == nullptr || (floats && (floatA_.empty() || floatB_.empty() || floatBank_.empty()))) {
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
                                   Span<float> floats, Pyramid& pyramid) const noexcept {
    pyramid.level[0] = image;
    pyramid.levels = 0;
    pyramid.coarse_float = ImageView<const float>();
    pyramid.float_level = -1;
    std::size_t offset = 0U;
    for (std::int32_t l = 1; l <= config_.pyramid_levels; ++l) {
        const ImageView<const std::uint8_t>& src = pyramid.level[l - 1];
        const std::int32_t w = src.width() / 2;
        const std::int32_t h = src.height() / 2;
        if (w < config_.template_window || h < config_.template_window) {
            break;
        }
        std::uint8_t* dst = storage.data() + offset;
        (void)halveImage(src, ImageView<std::uint8_t>(dst, w, h));  // sizes hold by construction
        pyramid.level[l] = ImageView<const std::uint8_t>(dst, w, h);
        pyramid.levels = l;
        offset += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    }
    // The coarsest level as floats when every configured level was built (its size is then
    // the one floatLevelValues() provides for): the coarse search's products read it.
    if (!floats.empty() && pyramid.levels == config_.pyramid_levels) {
        const ImageView<const std::uint8_t>& top = pyramid.level[pyramid.levels];
        detail::toFloats(top, floats.data());
        pyramid.coarse_float = ImageView<const float>(floats.data(), top.width(), top.height());
        pyramid.float_level = pyramid.levels;
    }
}

namespace {
Status checkImages(const MatcherConfig& c, const ImageView<const std::uint8_t>& image_a,
                   const ImageView<const std::uint8_t>& image_b) noexcept {
    if (!image_a.valid()) {
        return Status(StatusCode::kInvalidArgument, "TemplateMatcher: image_a is empty or malformed");
    }
    if (!image_b.valid()) {
        return Status(StatusCode::kInvalidArgument, "TemplateMatcher: image_b is empty or malformed");
    }
    if (image_a.width() > c.max_width || image_a.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, "TemplateMatcher: image_a exceeds max_width x max_height",
                      image_a.width());
    }
    if (image_b.width() > c.max_width || image_b.height() > c.max_height) {
        return Status(StatusCode::kSizeMismatch, "TemplateMatcher: image_b exceeds max_width x max_height",
                      image_b.width());
    }
    return Status::ok();
}
// The prediction and the features against the (checked) images.
Status checkPrediction(const ImageView<const std::uint8_t>& image_a, const ImageView<const std::uint8_t>& image_b,
                       const FeatureSet& features_a, const MatchPrediction& p) noexcept {
    if (p.pair.model_a.width_px != image_a.width() || p.pair.model_a.height_px != image_a.height()) {
        return Status(StatusCode::kSizeMismatch, "MatchPrediction.pair.model_a: size differs from image_a",
                      p.pair.model_a.width_px);
    }
    if (p.pair.model_b.width_px != image_b.width() || p.pair.model_b.height_px != image_b.height()) {
        return Status(StatusCode::kSizeMismatch, "MatchPrediction.pair.model_b: size differs from image_b",
                      p.pair.model_b.width_px);
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
    const double n2 = p.surface_normal_a.squaredNorm();
    if (!(math::isFinite(n2) && (n2 == 0.0 || (n2 >= 0.25 && n2 <= 4.0)))) {
        return Status(StatusCode::kInvalidArgument,
                      "MatchPrediction.surface_normal_a: must be zero or a finite vector of norm 0.5..2");
    }
    if (features_a.count < 0 || features_a.count > kMaxFeatures) {
        return Status(StatusCode::kInvalidArgument, "features_a.count: must be 0..kMaxFeatures", features_a.count);
    }
    return Status::ok();
}
// The affine refinement of a forward match, started from the winning template's warp.
// False when it is not accepted. Errors cannot happen here (the configuration was
// validated, both pixels are finite); one would leave the match out, never pass it on
// unrefined.
bool refinedAffine(const AffineRefineConfig& config, const ImageView<const std::uint8_t>& image_a,
                   const ImageView<const std::uint8_t>& image_b, const Vec2& pixel_a, const detail::ForwardMatch& fwd,
                   Vec2& pixel_b) noexcept {
    Mat2 warp;
    warp << fwd.warp.a, fwd.warp.b, fwd.warp.c, fwd.warp.d;
    AffineMatch am;
    if (!refineAffine(image_a, image_b, pixel_a, fwd.pixel, warp, config, am).isOk() ||
        am.outcome != AffineOutcome::kAccepted) {
        return false;
    }
    pixel_b = am.pixel_b;
    return true;
}

// Marks for verification the passing forward matches of features 0..n-1 with the
// max_verified best scores (the lower index first among equal scores: a strict order, so
// exactly min(passed, max_verified) are marked). At most n^2 comparisons, only when more
// than max_verified passed. Returns how many passed and were not marked.
std::int32_t markVerified(detail::ForwardMatch* f, std::int32_t n, std::int32_t max_verified) noexcept {
    std::int32_t passed = 0;
    for (std::int32_t i = 0; i < n; ++i) {
        f[i].verify = f[i].passed;
        passed += f[i].passed ? 1 : 0;
    }
    if (passed <= max_verified) {
        return 0;
    }
    for (std::int32_t i = 0; i < n; ++i) {
        if (!f[i].passed) {
            continue;
        }
        std::int32_t better = 0;  // passing features ordered before i
        for (std::int32_t j = 0; j < n; ++j) {
            const bool before = j < i ? f[j].score >= f[i].score : f[j].score > f[i].score;
            better += (f[j].passed && before) ? 1 : 0;
        }
        f[i].verify = better < max_verified;
    }
    return passed - max_verified;
}

// One call's searches: both pyramids, both directions' geometry, the scratch.
struct CallContext {
    const TemplateMatcher::Pyramid* pa;
    const TemplateMatcher::Pyramid* pb;
    const Geometry* forward;
    const Geometry* backward;
    TemplateBank* bank;
    const MatcherConfig* config;
};

// Steps 1-4 of every feature into f (passed: found, with a score of at least min_score).
void searchForward(const CallContext& c, const FeatureSet& features_a, detail::ForwardMatch* f,
                   MatchStats& st) noexcept {
    for (std::int32_t i = 0; i < features_a.count; ++i) {
        ++st.attempted;
        const SearchResult fwd = search(*c.pa, *c.pb, *c.forward, features_a.items[i].pixel, *c.bank);
        f[i].passed = false;
        if (fwd.outcome == Outcome::kNoRegion) {
            ++st.no_region;
            continue;
        }
        if (fwd.outcome != Outcome::kFound || fwd.score < static_cast<double>(c.config->min_score)) {
            ++st.low_score;
            continue;
        }
        f[i].passed = true;
        f[i].pixel = fwd.pixel;
        f[i].score = fwd.score;
        f[i].warp = fwd.warp;
    }
}

// Steps 5 and 6 of the features marked for verification, in feature order, into out.
void verifyMarked(const CallContext& c, const FeatureSet& features_a, const detail::ForwardMatch* f, MatchSet& out,
                  MatchStats& st) noexcept {
    const ImageView<const std::uint8_t>& image_a = c.pa->level[0];
    const ImageView<const std::uint8_t>& image_b = c.pb->level[0];
    const auto tolerance = static_cast<double>(c.config->mutual_tolerance_px);
    for (std::int32_t i = 0; i < features_a.count; ++i) {
        if (!f[i].verify) {
            continue;
        }
        const Vec2& pixel_a = features_a.items[i].pixel;
        Vec2 pixel_b = f[i].pixel;
        if (c.config->refine_affine && !refinedAffine(c.config->affine, image_a, image_b, pixel_a, f[i], pixel_b)) {
            ++st.not_refined;
            continue;
        }
        const SearchResult back = search(*c.pb, *c.pa, *c.backward, pixel_b, *c.bank);
        if (back.outcome != Outcome::kFound || (back.pixel - pixel_a).norm() > tolerance) {
            ++st.not_mutual;
            continue;
        }
        Match& m = out.items[out.count];
        m.pixel_a = pixel_a;
        m.pixel_b = pixel_b;
        m.score = static_cast<float>(f[i].score);
        m.feature_index = i;
        ++out.count;
        ++st.matched;
    }
}

// The A -> B search of a (validated) prediction, the terrain normal normalised.
Geometry forwardGeometry(const MatchPrediction& prediction) noexcept {
    Geometry g;
    g.from = &prediction.pair.model_a;
    g.to = &prediction.pair.model_b;
    g.R_to_from = prediction.pair.b_from_a.R;
    g.t_to_from_m = prediction.pair.b_from_a.t_m;
    g.range_min_m = prediction.range_min_m;
    g.range_max_m = prediction.range_max_m;
    g.margin_px = prediction.margin_px;
    const double n2 = prediction.surface_normal_a.squaredNorm();
    g.normal_from = (n2 > 0.0) ? Vec3(prediction.surface_normal_a / math::sqrt(n2)) : Vec3::Zero();
    setAxis(g);
    return g;
}
}  // namespace

Status TemplateMatcher::prepare(const ImageView<const std::uint8_t>& image_a,
                                const ImageView<const std::uint8_t>& image_b) noexcept {
    prepared_ = false;
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "TemplateMatcher: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkImages(config_, image_a, image_b));
    buildPyramid(image_a, storageA_, floatA_, pyramidA_);
    buildPyramid(image_b, storageB_, floatB_, pyramidB_);
    prepared_ = true;
    return Status::ok();
}

Status TemplateMatcher::match(const ImageView<const std::uint8_t>& image_a,
                              const ImageView<const std::uint8_t>& image_b, const FeatureSet& features_a,
                              const MatchPrediction& prediction, MatchSet& out, MatchStats* stats) noexcept {
    out.count = 0;
    if (stats != nullptr) {
        *stats = MatchStats{};
    }
    VTM_RETURN_IF_ERROR(prepare(image_a, image_b));
    return matchPrepared(features_a, prediction, out, stats);
}

Status TemplateMatcher::matchPrepared(const FeatureSet& features_a, const MatchPrediction& prediction, MatchSet& out,
                                      MatchStats* stats) noexcept {
    out.count = 0;
    MatchStats st;
    if (stats != nullptr) {
        *stats = st;
    }
    if (!initialized_ || !prepared_) {
        return Status(StatusCode::kNotInitialized, "TemplateMatcher::matchPrepared: prepare() has not succeeded");
    }
    const Pyramid& pa = pyramidA_;
    const Pyramid& pb = pyramidB_;
    VTM_RETURN_IF_ERROR(checkPrediction(pa.level[0], pb.level[0], features_a, prediction));
    const Geometry forward = forwardGeometry(prediction);
    Geometry backward = inverseOf(forward);
    setAxis(backward);
    TemplateBank bank;
    bank.half = config_.template_window / 2;
    bank.storage = bank_.data();
    bank.float_storage = floatBank_.data();
    bank.scan = scan_;
    bank.column_sum = columnSum_.data();
    bank.column_sum_sq = columnSumSq_.data();
    bank.stride = static_cast<std::size_t>(config_.template_window) * static_cast<std::size_t>(config_.template_window);
    // Forward searches of every feature, then the verification of the best of them.
    const CallContext c{&pa, &pb, &forward, &backward, &bank, &config_};
    searchForward(c, features_a, forward_, st);
    st.unverified = markVerified(forward_, features_a.count, config_.max_verified);
    verifyMarked(c, features_a, forward_, out, st);
    if (stats != nullptr) {
        *stats = st;
    }
    return Status::ok();
}

}  // namespace vtm::features
