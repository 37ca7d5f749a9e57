// Registration by aligning entropy images: coarse grid search, pattern-search refinement
// down the pyramid, parabola fit, confidence and refusals (registration.hpp).
#include <cmath>

#include "vtm/core/image_pyramid.hpp"
#include "vtm/core/math.hpp"
#include "vtm/entropy/registration.hpp"

#include "equalise.hpp"

namespace vtm::entropy {
namespace {

// p2 = M q + v in the pixels of one pyramid level (q: image 1's level pixel).
struct LevelAffine {
    double m00, m01, m10, m11, vx, vy;
};

// Exact integer sums of one correlation.
struct Sums {
    std::int64_t n = 0, a = 0, aa = 0, b = 0, bb = 0, ab = 0;
    void add(std::int64_t x, std::int64_t y) noexcept {
        ++n;
        a += x;
        aa += x * x;
        b += y;
        bb += y * y;
        ab += x * y;
    }
};

// Normalised correlation from the sums; -1 when either side has no variance.
double nccOf(const Sums& s) noexcept {
    const auto n = static_cast<double>(s.n);
    const double va = n * static_cast<double>(s.aa) - static_cast<double>(s.a) * static_cast<double>(s.a);
    const double vb = n * static_cast<double>(s.bb) - static_cast<double>(s.b) * static_cast<double>(s.b);
    if (!(va > 0.0) || !(vb > 0.0)) {
        return -1.0;
    }
    const double num = n * static_cast<double>(s.ab) - static_cast<double>(s.a) * static_cast<double>(s.b);
    return num / math::sqrt(va * vb);
}

// Bilinear sample in 1/256 px, integer weights; false outside [0, w-1] x [0, h-1] or when
// one of the four pixels has no data (mask 0).
bool sample(const ImageView<const std::uint8_t>& img, const ImageView<const std::uint8_t>& mask, double x, double y,
            std::int32_t& value) noexcept {
    if (!(x >= 0.0) || !(y >= 0.0) || x > static_cast<double>(img.width() - 1) ||
        y > static_cast<double>(img.height() - 1)) {
        return false;
    }
    const auto xf = static_cast<std::int32_t>(math::floor(x * 256.0 + 0.5));
    const auto yf = static_cast<std::int32_t>(math::floor(y * 256.0 + 0.5));
    const std::int32_t x0 = xf >> 8;
    const std::int32_t y0 = yf >> 8;
    const std::int32_t ax = xf & 255;
    const std::int32_t ay = yf & 255;
    const std::int32_t x1 = x0 + 1 < img.width() ? x0 + 1 : x0;
    const std::int32_t y1 = y0 + 1 < img.height() ? y0 + 1 : y0;
    const std::uint8_t* m0 = mask.row(y0);
    const std::uint8_t* m1 = mask.row(y1);
    if ((m0[x0] & m0[x1] & m1[x0] & m1[x1]) == 0U) {
        return false;
    }
    const std::uint8_t* r0 = img.row(y0);
    const std::uint8_t* r1 = img.row(y1);
    const std::int32_t top = r0[x0] * (256 - ax) + r0[x1] * ax;
    const std::int32_t bottom = r1[x0] * (256 - ax) + r1[x1] * ax;
    value = (top * (256 - ay) + bottom * ay + 32768) >> 16;
    return true;
}

// Data mask at half size: a pixel has data when all four it averages have.
void halveMask(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst) noexcept {
    for (std::int32_t y = 0; y < dst.height(); ++y) {
        const std::uint8_t* r0 = src.row(2 * y);
        const std::uint8_t* r1 = src.row(2 * y + 1);
        std::uint8_t* d = dst.row(y);
        for (std::int32_t x = 0; x < dst.width(); ++x) {
            const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(x) * 2;
            d[x] = static_cast<std::uint8_t>(r0[i] & r0[i + 1] & r1[i] & r1[i + 1]);
        }
    }
}

// mask := 1 where no 0 of mask lies within the (2r+1)^2 square (outside the image counts as
// data: the entropy windows replicate the border). Separable running counts through tmp.
void erodeMask(const ImageView<std::uint8_t>& mask, const ImageView<std::uint8_t>& tmp, std::int32_t r) noexcept {
    const std::int32_t w = mask.width();
    const std::int32_t h = mask.height();
    for (std::int32_t y = 0; y < h; ++y) {
        const std::uint8_t* in = mask.row(y);
        std::uint8_t* out = tmp.row(y);
        std::int32_t holes = 0;
        for (std::int32_t x = 0; x < r && x < w; ++x) {
            holes += in[x] == 0U ? 1 : 0;
        }
        for (std::int32_t x = 0; x < w; ++x) {
            holes += (x + r < w && in[x + r] == 0U) ? 1 : 0;
            holes -= (x - r - 1 >= 0 && in[x - r - 1] == 0U) ? 1 : 0;
            out[x] = holes == 0 ? 1U : 0U;
        }
    }
    for (std::int32_t x = 0; x < w; ++x) {
        std::int32_t holes = 0;
        for (std::int32_t y = 0; y < r && y < h; ++y) {
            holes += tmp.row(y)[x] == 0U ? 1 : 0;
        }
        for (std::int32_t y = 0; y < h; ++y) {
            holes += (y + r < h && tmp.row(y + r)[x] == 0U) ? 1 : 0;
            holes -= (y - r - 1 >= 0 && tmp.row(y - r - 1)[x] == 0U) ? 1 : 0;
            mask.row(y)[x] = holes == 0 ? 1U : 0U;
        }
    }
}

double centreOf(std::int32_t size) noexcept { return 0.5 * static_cast<double>(size - 1); }

Status badRequest(const char* reason) noexcept { return Status(StatusCode::kInvalidArgument, reason); }

Status checkRequest(const RegistrationRequest& r) noexcept {
    if (!std::isfinite(r.angle_min_rad) || !std::isfinite(r.angle_max_rad) || r.angle_max_rad < r.angle_min_rad ||
        r.angle_max_rad - r.angle_min_rad > math::kTwoPi + 1e-9) {
        return badRequest("request.angle_min_rad/angle_max_rad: need min <= max, a range of at most 2 pi");
    }
    if (!std::isfinite(r.scale_min) || !std::isfinite(r.scale_max) || r.scale_min < 0.125 ||
        r.scale_max < r.scale_min || r.scale_max > 8.0) {
        return badRequest("request.scale_min/scale_max: need 0.125 <= min <= max <= 8");
    }
    if (!std::isfinite(r.shift_x_px) || !std::isfinite(r.shift_y_px) || std::fabs(r.shift_x_px) > 8192.0 ||
        std::fabs(r.shift_y_px) > 8192.0) {
        return badRequest("request.shift_x_px/shift_y_px: must be finite, |t| <= 8192 px");
    }
    if (!std::isfinite(r.shift_range_px) || r.shift_range_px < 0.0 || r.shift_range_px > 4096.0) {
        return badRequest("request.shift_range_px: must be 0..4096 px");
    }
    return Status::ok();
}

// Grid of n values from lo to hi with at most `cap` points about `step` apart.
std::int32_t gridCount(double lo, double hi, double step, std::int32_t cap) noexcept {
    const double span = hi - lo;
    if (!(span > 0.0)) {
        return 1;
    }
    const double n = std::ceil(span / step) + 1.0;
    return n > static_cast<double>(cap) ? cap : static_cast<std::int32_t>(n);
}

double gridValue(double lo, double hi, std::int32_t i, std::int32_t n) noexcept {
    return n <= 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
}

// Variance check of a level image (integer sums): false when it is flat.
bool hasContrast(const ImageView<const std::uint8_t>& img) noexcept {
    Sums s;
    for (std::int32_t y = 0; y < img.height(); ++y) {
        const std::uint8_t* r = img.row(y);
        for (std::int32_t x = 0; x < img.width(); ++x) {
            s.add(r[x], r[x]);
        }
    }
    return s.n * s.aa - s.a * s.a > 0;
}

}  // namespace

Mat23 EntropyRegistration::matrixOf(const Params& p) const noexcept {
    const double s = math::exp(p.logScale);
    const double c = s * math::cos(p.angle);
    const double sn = s * math::sin(p.angle);
    const double c1x = centreOf(levels1_[0].width());
    const double c1y = centreOf(levels1_[0].height());
    const double c2x = centreOf(levels2_[0].width());
    const double c2y = centreOf(levels2_[0].height());
    Mat23 g;
    g(0, 0) = c;
    g(0, 1) = -sn;
    g(1, 0) = sn;
    g(1, 1) = c;
    g(0, 2) = c2x + p.tx - (c * c1x - sn * c1y);
    g(1, 2) = c2y + p.ty - (sn * c1x + c * c1y);
    return g;
}

namespace {
// The full-resolution transform in the pixels of level l: full = k q + o, o = (k - 1) / 2.
LevelAffine levelAffine(const Mat23& g, std::int32_t level) noexcept {
    const double k = static_cast<double>(1 << level);
    const double o = 0.5 * (k - 1.0);
    LevelAffine a{};
    a.m00 = g(0, 0);
    a.m01 = g(0, 1);
    a.m10 = g(1, 0);
    a.m11 = g(1, 1);
    a.vx = (g(0, 0) * o + g(0, 1) * o + g(0, 2) - o) / k;
    a.vy = (g(1, 0) * o + g(1, 1) * o + g(1, 2) - o) / k;
    return a;
}
}  // namespace

double EntropyRegistration::cornerDistance(const Params& a, const Params& b) const noexcept {
    const Mat23 ga = matrixOf(a);
    const Mat23 gb = matrixOf(b);
    const double xs[2] = {0.0, static_cast<double>(levels1_[0].width() - 1)};
    const double ys[2] = {0.0, static_cast<double>(levels1_[0].height() - 1)};
    double worst = 0.0;
    for (const double x : xs) {
        for (const double y : ys) {
            const double dx = (ga(0, 0) - gb(0, 0)) * x + (ga(0, 1) - gb(0, 1)) * y + (ga(0, 2) - gb(0, 2));
            const double dy = (ga(1, 0) - gb(1, 0)) * x + (ga(1, 1) - gb(1, 1)) * y + (ga(1, 2) - gb(1, 2));
            const double d = math::sqrt(dx * dx + dy * dy);
            worst = d > worst ? d : worst;
        }
    }
    return worst;
}

double EntropyRegistration::score(std::int32_t level, const Params& p, double* overlap) const noexcept {
    const ImageView<const std::uint8_t> e1 = levels1_[level];
    const ImageView<const std::uint8_t> e2 = levels2_[level];
    const LevelAffine a = levelAffine(matrixOf(p), level);
    Sums s;
    for (std::int32_t y = 0; y < e1.height(); ++y) {
        const std::uint8_t* r = e1.row(y);
        const std::uint8_t* m = masks1_[level].row(y);
        const double rx = a.m01 * static_cast<double>(y) + a.vx;
        const double ry = a.m11 * static_cast<double>(y) + a.vy;
        for (std::int32_t x = 0; x < e1.width(); ++x) {
            std::int32_t v = 0;
            if (m[x] != 0U &&
                sample(e2, masks2_[level], a.m00 * static_cast<double>(x) + rx, a.m10 * static_cast<double>(x) + ry, v)) {
                s.add(r[x], v);
            }
        }
    }
    const double area = static_cast<double>(e1.width()) * static_cast<double>(e1.height());
    const double fraction = static_cast<double>(s.n) / area;
    if (overlap != nullptr) {
        *overlap = fraction;
    }
    return fraction < config_.min_overlap ? -1.0 : nccOf(s);
}

double EntropyRegistration::scoreAt(std::int32_t level, double angle_rad, double scale, double shift_x_px,
                                    double shift_y_px, double* overlap) const noexcept {
    if (!initialized_ || level < 0 || level >= config_.levels || !levels1_[level].valid() || !(scale > 0.0)) {
        return -1.0;
    }
    Params p;
    p.angle = angle_rad;
    p.logScale = math::log(scale);
    p.tx = shift_x_px;
    p.ty = shift_y_px;
    return score(level, p, overlap);
}

Status EntropyRegistration::prepare(const ImageView<const std::uint8_t>& image1,
                                    const ImageView<const std::uint8_t>& image2) noexcept {
    VTM_RETURN_IF_ERROR(prepareOne(0, image1));
    return prepareOne(1, image2);
}

// The data mask of one image at every level: grey > fill_max_grey, eroded by the entropy
// window's radius, then halved.
void EntropyRegistration::buildMask(std::int32_t index, const ImageView<const std::uint8_t>& image) noexcept {
    ImageView<std::uint8_t>* masks = index == 0 ? masks1_ : masks2_;
    const ImageView<std::uint8_t> m0 = masks[0];
    for (std::int32_t y = 0; y < image.height(); ++y) {
        const std::uint8_t* r = image.row(y);
        std::uint8_t* d = m0.row(y);
        for (std::int32_t x = 0; x < image.width(); ++x) {
            d[x] = static_cast<std::int32_t>(r[x]) > config_.fill_max_grey ? 1U : 0U;
        }
    }
    if (config_.representation == Representation::kEntropy && config_.fill_max_grey >= 0) {
        erodeMask(m0, ImageView<std::uint8_t>(scratch_.data(), image.width(), image.height()), config_.entropy.window / 2);
    }
    for (std::int32_t l = 1; l < config_.levels; ++l) {
        halveMask(masks[l - 1], masks[l]);
    }
}

Status EntropyRegistration::prepareOne(std::int32_t index, const ImageView<const std::uint8_t>& image) noexcept {
    const ImageView<const std::uint8_t>& img = image;
    const std::int32_t coarse = config_.levels - 1;
    if (!img.valid()) {
        return Status(StatusCode::kInvalidArgument, "EntropyRegistration: empty or malformed image view", index + 1);
    }
    if (img.width() > config_.max_width || img.height() > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "EntropyRegistration: image larger than max_width x max_height",
                      index + 1);
    }
    if ((img.width() >> coarse) < 8 || (img.height() >> coarse) < 8) {
        return Status(StatusCode::kSizeMismatch, "EntropyRegistration: image below 8 px at the coarse level", index + 1);
    }
    ImageView<std::uint8_t>* levels = index == 0 ? levels1_ : levels2_;
    ImageView<std::uint8_t>* masks = index == 0 ? masks1_ : masks2_;
    std::uint8_t* base = (index == 0 ? pyramid1_ : pyramid2_).data();
    std::uint8_t* maskBase = (index == 0 ? maskPyramid1_ : maskPyramid2_).data();
    std::size_t used = 0U;
    for (std::int32_t l = 0; l <= coarse; ++l) {
        const std::int32_t w = img.width() >> l;
        const std::int32_t h = img.height() >> l;
        levels[l] = ImageView<std::uint8_t>(base + used, w, h);
        masks[l] = ImageView<std::uint8_t>(maskBase + used, w, h);
        used += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    }
    if (config_.representation == Representation::kEntropy && config_.equalise) {
        const ImageView<std::uint8_t> eq(scratch_.data(), img.width(), img.height());
        if (config_.equalise_radius_px > 0) {
            detail::localRank(img, eq, config_.equalise_radius_px, config_.fill_max_grey, rankCounts_);
        } else {
            detail::equalise(img, eq, config_.fill_max_grey);
        }
        VTM_RETURN_IF_ERROR(entropy_.compute(eq, levels[0]));
    } else if (config_.representation == Representation::kEntropy) {
        VTM_RETURN_IF_ERROR(entropy_.compute(img, levels[0]));
    } else {
        VTM_RETURN_IF_ERROR(copyImage(img, levels[0]));
    }
    for (std::int32_t l = 1; l <= coarse; ++l) {
        VTM_RETURN_IF_ERROR(halveImage(levels[l - 1], levels[l]));
    }
    buildMask(index, img);
    if (!hasContrast(levels[coarse])) {
        return Status(StatusCode::kDegenerate, "EntropyRegistration: an image has no contrast at the coarse level",
                      index + 1);
    }
    return Status::ok();
}

// Image 2's coarse level sampled at M (q + u) + v for every q + u of image 1's coarse grid
// widened by `margin` on each side (-1 where outside image 2).
void EntropyRegistration::warpCoarse(double angle, double logScale, double tx0, double ty0,
                                     std::int32_t margin) noexcept {
    const std::int32_t coarse = config_.levels - 1;
    const ImageView<const std::uint8_t> e2 = levels2_[coarse];
    Params p;
    p.angle = angle;
    p.logScale = logScale;
    p.tx = tx0;
    p.ty = ty0;
    const LevelAffine a = levelAffine(matrixOf(p), coarse);
    const std::int32_t w = levels1_[coarse].width() + 2 * margin;
    const std::int32_t h = levels1_[coarse].height() + 2 * margin;
    warpStride_ = w;
    for (std::int32_t j = 0; j < h; ++j) {
        const auto qy = static_cast<double>(j - margin);
        const double rx = a.m01 * qy + a.vx;
        const double ry = a.m11 * qy + a.vy;
        std::int16_t* out = &warp_[static_cast<std::size_t>(j) * static_cast<std::size_t>(w)];
        for (std::int32_t i = 0; i < w; ++i) {
            const auto qx = static_cast<double>(i - margin);
            std::int32_t v = 0;
            out[i] = sample(e2, masks2_[coarse], a.m00 * qx + rx, a.m10 * qx + ry, v) ? static_cast<std::int16_t>(v)
                                                                     : static_cast<std::int16_t>(-1);
        }
    }
}

namespace {
// Index of shift (ux, uy) in the shift plane of half-width margin.
std::size_t shiftIndex(std::int32_t ux, std::int32_t uy, std::int32_t margin) noexcept {
    return static_cast<std::size_t>(uy + margin) * static_cast<std::size_t>(2 * margin + 1) +
           static_cast<std::size_t>(ux + margin);
}
}  // namespace

// Every integer shift u (|u| <= margin, coarse px of image 1) scored against the warped
// level: NCC over the pixels both have, -2 below min_overlap.
void EntropyRegistration::scoreShifts(std::int32_t margin) noexcept {
    const ImageView<const std::uint8_t> e1 = levels1_[config_.levels - 1];
    const double minCount = config_.min_overlap * static_cast<double>(e1.width()) * static_cast<double>(e1.height());
    for (std::int32_t uy = -margin; uy <= margin; ++uy) {
        for (std::int32_t ux = -margin; ux <= margin; ++ux) {
            std::int64_t n = 0;
            const double ncc = shiftNcc(ux, uy, margin, n);
            shiftScores_[shiftIndex(ux, uy, margin)] = static_cast<double>(n) < minCount ? -2.0 : ncc;
        }
    }
    ++coarseScored_;
}

// NCC of image 1's coarse level with the warped level shifted by u; n: pixels both have.
double EntropyRegistration::shiftNcc(std::int32_t ux, std::int32_t uy, std::int32_t margin,
                                     std::int64_t& n) const noexcept {
    const std::int32_t coarse = config_.levels - 1;
    const ImageView<const std::uint8_t> e1 = levels1_[coarse];
    Sums s;
    for (std::int32_t y = 0; y < e1.height(); ++y) {
        const std::uint8_t* r = e1.row(y);
        const std::uint8_t* m = masks1_[coarse].row(y);
        const std::int16_t* wrow = &warp_[static_cast<std::size_t>(y + uy + margin) * static_cast<std::size_t>(warpStride_) +
                                          static_cast<std::size_t>(ux + margin)];
        for (std::int32_t x = 0; x < e1.width(); ++x) {
            if (wrow[x] >= 0 && m[x] != 0U) {
                s.add(r[x], wrow[x]);
            }
        }
    }
    n = s.n;
    return nccOf(s);
}

// The local maxima of the shift plane (no neighbour higher) are offered as candidates.
void EntropyRegistration::offerShiftPeaks(double angle, double logScale, double tx0, double ty0,
                                          std::int32_t margin) noexcept {
    const double k = static_cast<double>(1 << (config_.levels - 1));
    const double sc = math::exp(logScale);
    const double c = sc * math::cos(angle);
    const double sn = sc * math::sin(angle);
    for (std::int32_t uy = -margin; uy <= margin; ++uy) {
        for (std::int32_t ux = -margin; ux <= margin; ++ux) {
            const double v = shiftScores_[shiftIndex(ux, uy, margin)];
            bool peak = v > -1.0;
            for (std::int32_t n = 0; n < 9 && peak; ++n) {
                const std::int32_t nx = ux + n % 3 - 1;
                const std::int32_t ny = uy + n / 3 - 1;
                const bool inside = nx >= -margin && nx <= margin && ny >= -margin && ny <= margin;
                peak = n == 4 || !inside || v >= shiftScores_[shiftIndex(nx, ny, margin)];
            }
            if (peak) {
                Params p;
                p.angle = angle;
                p.logScale = logScale;
                p.tx = tx0 + k * (c * static_cast<double>(ux) - sn * static_cast<double>(uy));
                p.ty = ty0 + k * (sn * static_cast<double>(ux) + c * static_cast<double>(uy));
                p.score = v;
                offerCandidate(p);
            }
        }
    }
}

// Keeps the `candidates` best peaks, none within 3 coarse pixels of another.
void EntropyRegistration::offerCandidate(const Params& p) noexcept {
    const double separation = 3.0 * static_cast<double>(1 << (config_.levels - 1));
    for (std::int32_t i = 0; i < candidateCount_; ++i) {
        if (cornerDistance(p, candidates_[i]) <= separation) {
            if (p.score > candidates_[i].score) {
                candidates_[i] = p;
            }
            return;
        }
    }
    if (candidateCount_ < config_.candidates) {
        candidates_[candidateCount_] = p;
        ++candidateCount_;
        return;
    }
    std::int32_t worst = 0;
    for (std::int32_t i = 1; i < candidateCount_; ++i) {
        worst = candidates_[i].score < candidates_[worst].score ? i : worst;
    }
    if (p.score > candidates_[worst].score) {
        candidates_[worst] = p;
    }
}

Status EntropyRegistration::coarseSearch(const RegistrationRequest& request, Registration& result) noexcept {
    const std::int32_t coarse = config_.levels - 1;
    const ImageView<const std::uint8_t> e1 = levels1_[coarse];
    const double k = static_cast<double>(1 << coarse);
    // One coarse pixel of motion at the edge of image 1's coarse level.
    const double radius = 0.5 * static_cast<double>(e1.width() > e1.height() ? e1.width() : e1.height());
    const double step = 1.0 / radius;
    const double logMin = math::log(request.scale_min);
    const double logMax = math::log(request.scale_max);
    const std::int32_t angles = gridCount(request.angle_min_rad, request.angle_max_rad, step, config_.max_angle_steps);
    const std::int32_t scales = gridCount(logMin, logMax, step, config_.max_scale_steps);
    const double wanted = std::ceil(request.shift_range_px * math::sqrt(2.0) / (request.scale_min * k));
    const std::int32_t cap = (config_.max_shift_steps - 1) / 2;
    const std::int32_t margin = wanted > static_cast<double>(cap) ? cap : static_cast<std::int32_t>(wanted);
    candidateCount_ = 0;
    coarseScored_ = 0;
    for (std::int32_t si = 0; si < scales; ++si) {
        const double logScale = gridValue(logMin, logMax, si, scales);
        for (std::int32_t ai = 0; ai < angles; ++ai) {
            const double angle = gridValue(request.angle_min_rad, request.angle_max_rad, ai, angles);
            warpCoarse(angle, logScale, request.shift_x_px, request.shift_y_px, margin);
            scoreShifts(margin);
            offerShiftPeaks(angle, logScale, request.shift_x_px, request.shift_y_px, margin);
        }
    }
    result.coarse_scored = coarseScored_ * (2 * margin + 1) * (2 * margin + 1);
    if (candidateCount_ == 0) {
        return Status(StatusCode::kNoData, "EntropyRegistration: no transform of the search overlaps min_overlap");
    }
    return Status::ok();
}

// Pattern search at one level: the 8 neighbours at +-step of each parameter; move to the
// best that improves, halve the steps when none does.
void EntropyRegistration::searchLevel(std::int32_t level, Params& p, double* steps, Registration& result) const noexcept {
    p.score = score(level, p, nullptr);
    ++result.fine_scored;
    for (std::int32_t round = 0; round < config_.refine_rounds; ++round) {
        Params best = p;
        for (std::int32_t i = 0; i < 8; ++i) {
            Params q = p;
            double* fields[4] = {&q.angle, &q.logScale, &q.tx, &q.ty};
            *fields[i / 2] += ((i % 2) == 0 ? -1.0 : 1.0) * steps[i / 2];
            clampToRequest(q);
            q.score = score(level, q, nullptr);
            ++result.fine_scored;
            if (q.score > best.score) {
                best = q;
            }
        }
        if (best.score > p.score) {
            p = best;
        } else {
            for (std::int32_t j = 0; j < 4; ++j) {
                steps[j] *= 0.5;
            }
        }
    }
}

// A parabola through the scores at -h, 0, +h of each parameter; the vertices (within half a
// step) are applied together and kept when they do not lower the score.
void EntropyRegistration::fitParabolas(Params& p, const double* steps, Registration& result) const noexcept {
    Params fitted = p;
    double* out[4] = {&fitted.angle, &fitted.logScale, &fitted.tx, &fitted.ty};
    for (std::int32_t j = 0; j < 4; ++j) {
        Params lo = p;
        Params hi = p;
        double* l[4] = {&lo.angle, &lo.logScale, &lo.tx, &lo.ty};
        double* h[4] = {&hi.angle, &hi.logScale, &hi.tx, &hi.ty};
        *l[j] -= steps[j];
        *h[j] += steps[j];
        const double sl = score(0, lo, nullptr);
        const double sh = score(0, hi, nullptr);
        result.fine_scored += 2;
        const double curvature = sl - 2.0 * p.score + sh;
        if (sl > -1.0 && sh > -1.0 && curvature < 0.0) {
            double offset = 0.5 * (sl - sh) / curvature;
            offset = offset > 0.5 ? 0.5 : (offset < -0.5 ? -0.5 : offset);
            *out[j] += offset * steps[j];
        }
    }
    clampToRequest(fitted);
    fitted.score = score(0, fitted, nullptr);
    ++result.fine_scored;
    if (fitted.score >= p.score) {
        p = fitted;
    }
}

namespace {
double clampTo(double v, double lo, double hi) noexcept { return v < lo ? lo : (v > hi ? hi : v); }
}  // namespace

// The refinement stays inside the request's ranges (the shift within the searched square).
void EntropyRegistration::clampToRequest(Params& p) const noexcept {
    const RegistrationRequest& r = request_;
    p.angle = clampTo(p.angle, r.angle_min_rad, r.angle_max_rad);
    p.logScale = clampTo(p.logScale, math::log(r.scale_min), math::log(r.scale_max));
    p.tx = clampTo(p.tx, r.shift_x_px - r.shift_range_px, r.shift_x_px + r.shift_range_px);
    p.ty = clampTo(p.ty, r.shift_y_px - r.shift_range_px, r.shift_y_px + r.shift_range_px);
}

void EntropyRegistration::refine(Params& p, Registration& result) const noexcept {
    double steps[4] = {0.0, 0.0, 0.0, 0.0};
    for (std::int32_t level = config_.levels - 1; level >= 0; --level) {
        const ImageView<const std::uint8_t> e1 = levels1_[level];
        const double radius = 0.5 * static_cast<double>(e1.width() > e1.height() ? e1.width() : e1.height());
        steps[0] = 1.0 / radius;                           // one level pixel at the edge
        steps[1] = 1.0 / radius;
        steps[2] = static_cast<double>(1 << level);        // one level pixel, in full-resolution px
        steps[3] = steps[2];
        searchLevel(level, p, steps, result);
    }
    fitParabolas(p, steps, result);
}

Status EntropyRegistration::registerImages(const ImageView<const std::uint8_t>& image1,
                                           const ImageView<const std::uint8_t>& image2,
                                           const RegistrationRequest& request, Registration& result) noexcept {
    result = Registration{};
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "EntropyRegistration::registerImages: init() has not succeeded");
    }
    VTM_RETURN_IF_ERROR(checkRequest(request));
    request_ = request;
    VTM_RETURN_IF_ERROR(prepare(image1, image2));
    VTM_RETURN_IF_ERROR(coarseSearch(request, result));
    std::int32_t best = 0;
    for (std::int32_t i = 0; i < candidateCount_; ++i) {
        refine(candidates_[i], result);
        best = candidates_[i].score > candidates_[best].score ? i : best;
    }
    const Params& b = candidates_[best];
    const double separation = 2.0 * static_cast<double>(1 << (config_.levels - 1));
    for (std::int32_t i = 0; i < candidateCount_; ++i) {
        if (i != best && cornerDistance(candidates_[i], b) > separation && candidates_[i].score > result.second_ncc) {
            result.second_ncc = candidates_[i].score;
        }
    }
    result.image2_from_image1 = matrixOf(b);
    result.angle_rad = b.angle;
    result.scale = math::exp(b.logScale);
    result.shift_x_px = b.tx;
    result.shift_y_px = b.ty;
    result.ncc = score(0, b, &result.overlap);
    if (!(b.score > -1.0)) {
        return Status(StatusCode::kNoData, "EntropyRegistration: the best peak lost its overlap in refinement");
    }
    if (b.score < config_.min_ncc) {
        return Status(StatusCode::kNoData, "EntropyRegistration: peak NCC below min_ncc (no match)");
    }
    if (result.second_ncc >= config_.max_peak_ratio * b.score) {
        return Status(StatusCode::kDegenerate, "EntropyRegistration: a separated second peak reaches max_peak_ratio (ambiguous)");
    }
    return Status::ok();
}

ImageView<const std::uint8_t> EntropyRegistration::matchedImage1() const noexcept { return levels1_[0]; }
ImageView<const std::uint8_t> EntropyRegistration::matchedImage2() const noexcept { return levels2_[0]; }

}  // namespace vtm::entropy
