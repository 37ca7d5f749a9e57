// The sweep proper: per band of image-1 rows, per plane: warp image 2 (bilinear, 1/32 px
// positions) onto the band plus the window's margin, update window column sums row by
// row (add the entering row, subtract the leaving one), slide along each row for the
// window sums, and keep per pixel the best plane and its neighbours' costs. Then decide
// each pixel: reason, parabola in inverse depth, depth.
#include <cmath>
#include <limits>

#include "geometry.hpp"

namespace vtm::descent {
namespace {

constexpr float kNoCost = -1.0F;  // costs are >= 0
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr std::int32_t kSubpixelBits = 5;  // bilinear positions in 1/32 px (as OpenCV's INTER_BITS)
constexpr std::int32_t kSubpixel = 1 << kSubpixelBits;

// The running column sums of the window score (one entry per column): exact integers in
// doubles (plane_sweep.hpp, colA_).
struct ColumnSums {
    double* a;         // NCC: sum of warped levels; SAD: sum of absolute differences
    double* b;         // NCC: sum of squared warped levels
    double* c;         // NCC: sum of products with image 1
    std::int32_t* in;  // pixels whose warped sample lies inside image 2
};

// Column-sum update with one row of image 1 (levels x 16) and its warped row. Every
// product is below 2^32 and every sum below 2^52: exact in double.
template <bool kNcc, std::int32_t kSign>
void accumulateRow(const std::uint16_t* i1, const std::uint16_t* w2, const std::uint8_t* in, std::int32_t width,
                   const ColumnSums& sums) noexcept {
    double* const colA = sums.a;
    double* const colB = sums.b;
    double* const colC = sums.c;
    std::int32_t* const colIn = sums.in;
    constexpr double kS = static_cast<double>(kSign);
    for (std::int32_t x = 0; x < width; ++x) {
        const std::int32_t i = static_cast<std::int32_t>(i1[x]) << 4;
        const std::int32_t w = static_cast<std::int32_t>(w2[x]);
        if constexpr (kNcc) {
            const double wd = static_cast<double>(w);
            colA[x] += kS * wd;
            colB[x] += kS * (wd * wd);
            colC[x] += kS * (static_cast<double>(i) * wd);
        } else {
            const std::int32_t d = i - w;
            colA[x] += kS * static_cast<double>(d < 0 ? -d : d);
        }
        colIn[x] += kSign * static_cast<std::int32_t>(in[x]);
    }
}

}  // namespace

// Per band pixel: the best plane so far, the cost of the previous plane, and the costs
// of the best plane's two neighbours (for the parabola).
void PlaneSweep::warpRows(std::int32_t k, std::int32_t yFirst, std::int32_t rows) noexcept {
    const double* h = &homographies_[9U * static_cast<std::size_t>(k)];
    const std::int32_t w = width_;
    const double maxU = static_cast<double>(width_ - 1);
    const double maxV = static_cast<double>(height_ - 1);
    const std::uint16_t* src = image2_.data();
    for (std::int32_t j = 0; j < rows; ++j) {
        const double y = static_cast<double>(yFirst + j);
        const double bx = h[1] * y + h[2];
        const double by = h[4] * y + h[5];
        const double bw = h[7] * y + h[8];
        std::uint16_t* out = warped_.data() + static_cast<std::ptrdiff_t>(j) * w;
        std::uint8_t* in = inside_.data() + static_cast<std::ptrdiff_t>(j) * w;
        for (std::int32_t x = 0; x < w; ++x) {
            const double xd = static_cast<double>(x);
            const double W = h[6] * xd + bw;
            const double inv = W > 0.0 ? 1.0 / W : -1.0;
            const double u = (h[0] * xd + bx) * inv;
            const double v = (h[3] * xd + by) * inv;
            if (!(u >= 0.0 && u <= maxU && v >= 0.0 && v <= maxV)) {
                out[x] = 0U;
                in[x] = 0U;
                continue;
            }
            // floor(u * 32 + 0.5): u, v >= 0 here, so the sum is positive and truncation is
            // the floor, the same integers as std::floor without its libm call on targets
            // that have no rounding instruction (the 750). Not lround: halves go up here.
            const auto ui = static_cast<std::int32_t>(u * kSubpixel + 0.5);  // NOLINT(bugprone-incorrect-roundings)
            const auto vi = static_cast<std::int32_t>(v * kSubpixel + 0.5);  // NOLINT(bugprone-incorrect-roundings)
            std::int32_t ix = ui >> kSubpixelBits;
            std::int32_t fx = ui & (kSubpixel - 1);
            std::int32_t iy = vi >> kSubpixelBits;
            std::int32_t fy = vi & (kSubpixel - 1);
            if (ix >= width_ - 1) {  // u == w - 1: all weight on the last column
                ix = width_ - 2;
                fx = kSubpixel;
            }
            if (iy >= height_ - 1) {
                iy = height_ - 2;
                fy = kSubpixel;
            }
            const std::uint16_t* p = src + static_cast<std::ptrdiff_t>(iy) * w + ix;
            const auto top = static_cast<std::uint32_t>(p[0] * (kSubpixel - fx) + p[1] * fx);
            const auto bottom = static_cast<std::uint32_t>(p[w] * (kSubpixel - fx) + p[w + 1] * fx);
            const std::uint32_t sum = top * static_cast<std::uint32_t>(kSubpixel - fy) +
                                      bottom * static_cast<std::uint32_t>(fy);
            out[x] = static_cast<std::uint16_t>((sum + 512U) >> 10U);
            in[x] = 1U;
        }
    }
}

void PlaneSweep::scorePlane(const ImageView<const std::uint16_t>& image1, std::int32_t k, std::int32_t y0,
                            std::int32_t y1) noexcept {
    const std::int32_t r = radius_;
    const std::int32_t w = width_;
    warpRows(k, y0 - r, y1 - y0 + 2 * r);
    for (std::int32_t x = 0; x < w; ++x) {
        colA_[static_cast<std::size_t>(x)] = 0.0;
        colB_[static_cast<std::size_t>(x)] = 0.0;
        colC_[static_cast<std::size_t>(x)] = 0.0;
        colIn_[static_cast<std::size_t>(x)] = 0;
    }
    const bool ncc = config_.score == Score::kNcc;
    const ColumnSums sums{colA_.data(), colB_.data(), colC_.data(), colIn_.data()};
    auto add = [&](std::int32_t y, bool subtract) {
        const std::int32_t j = y - (y0 - r);
        const std::uint16_t* w2 = warped_.data() + static_cast<std::ptrdiff_t>(j) * w;
        const std::uint8_t* in = inside_.data() + static_cast<std::ptrdiff_t>(j) * w;
        if (ncc) {
            (subtract ? accumulateRow<true, -1> : accumulateRow<true, 1>)(
                image1.row(y), w2, in, w, sums);
        } else {
            (subtract ? accumulateRow<false, -1> : accumulateRow<false, 1>)(
                image1.row(y), w2, in, w, sums);
        }
    };
    for (std::int32_t y = y0 - r; y <= y0 + r; ++y) {
        add(y, false);
    }
    for (std::int32_t y = y0; y < y1; ++y) {
        if (y > y0) {
            add(y - r - 1, true);
            add(y + r, false);
        }
        scoreRow(k, y - y0);
    }
}

void PlaneSweep::scoreRow(std::int32_t k, std::int32_t bandRow) noexcept {
    const std::int32_t r = radius_;
    const std::int32_t w = width_;
    const std::int32_t n = config_.window * config_.window;
    const auto nd = static_cast<double>(n);
    const bool ncc = config_.score == Score::kNcc;
    // Exact integers (plane_sweep.hpp, colA_): the same values as in int64.
    double a = 0.0, b = 0.0, c = 0.0;
    std::int32_t in = 0;
    for (std::int32_t x = 0; x < 2 * r; ++x) {
        a += colA_[static_cast<std::size_t>(x)];
        b += colB_[static_cast<std::size_t>(x)];
        c += colC_[static_cast<std::size_t>(x)];
        in += colIn_[static_cast<std::size_t>(x)];
    }
    const std::size_t rowBase = static_cast<std::size_t>(bandRow) * static_cast<std::size_t>(w);
    for (std::int32_t x = r; x < w - r; ++x) {
        const std::size_t enter = static_cast<std::size_t>(x) + static_cast<std::size_t>(r);
        a += colA_[enter];
        b += colB_[enter];
        c += colC_[enter];
        in += colIn_[enter];
        bool valid = in == n;
        float cost = static_cast<float>(a);
        const std::size_t idx = rowBase + static_cast<std::size_t>(x);
        if (ncc && valid) {
            const double si = sumI_[idx];
            const double varI = nd * sumII_[idx] - si * si;  // each term < 2^52: exact
            const double varW = nd * b - a * a;
            const double cov = nd * c - si * a;
            valid = varI > 0.0;
            const double ncc_value = (valid && varW > 0.0) ? cov / std::sqrt(varI * varW) : 0.0;
            const double oneMinus = 1.0 - ncc_value;
            cost = static_cast<float>(oneMinus > 0.0 ? oneMinus : 0.0);
        }
        if (valid) {
            const std::int16_t best = bestIndex_[idx];
            if (best < 0 || cost < bestCost_[idx]) {
                belowCost_[idx] = prevCost_[idx];
                aboveCost_[idx] = kNoCost;
                bestCost_[idx] = cost;
                bestIndex_[idx] = static_cast<std::int16_t>(k);
            } else if (best == k - 1) {
                aboveCost_[idx] = cost;
            }
        }
        prevCost_[idx] = valid ? cost : kNoCost;
        const auto leave = static_cast<std::size_t>(x - r);
        a -= colA_[leave];
        b -= colB_[leave];
        c -= colC_[leave];
        in -= colIn_[leave];
    }
}

// NCC: window sums of image 1 (levels x 16) and of its squares for the band's pixels.
void PlaneSweep::imageSums(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1) noexcept {
    const std::int32_t r = radius_;
    const std::int32_t w = width_;
    for (std::int32_t y = y0; y < y1; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            std::int32_t s = 0;
            std::int64_t ss = 0;
            for (std::int32_t j = -r; j <= r; ++j) {
                const std::int32_t v = static_cast<std::int32_t>(image1.row(y + j)[x]) << 4;
                s += v;
                ss += static_cast<std::int64_t>(v) * v;
            }
            colA_[static_cast<std::size_t>(x)] = static_cast<double>(s);   // < 2^21: exact
            colB_[static_cast<std::size_t>(x)] = static_cast<double>(ss);  // < 2^37: exact
        }
        const std::size_t rowBase = static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(w);
        double s = 0.0;
        double ss = 0.0;
        for (std::int32_t x = 0; x < 2 * r; ++x) {
            s += colA_[static_cast<std::size_t>(x)];
            ss += colB_[static_cast<std::size_t>(x)];
        }
        for (std::int32_t x = r; x < w - r; ++x) {
            s += colA_[static_cast<std::size_t>(x) + static_cast<std::size_t>(r)];
            ss += colB_[static_cast<std::size_t>(x) + static_cast<std::size_t>(r)];
            sumI_[rowBase + static_cast<std::size_t>(x)] = s;
            sumII_[rowBase + static_cast<std::size_t>(x)] = ss;
            s -= colA_[static_cast<std::size_t>(x - r)];
            ss -= colB_[static_cast<std::size_t>(x - r)];
        }
    }
}

void PlaneSweep::sweepBand(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1) noexcept {
    const std::size_t n = static_cast<std::size_t>(y1 - y0) * static_cast<std::size_t>(width_);
    for (std::size_t i = 0; i < n; ++i) {
        bestIndex_[i] = -1;
        bestCost_[i] = kNoCost;
        prevCost_[i] = kNoCost;
        belowCost_[i] = kNoCost;
        aboveCost_[i] = kNoCost;
        sumI_[i] = 0.0;
        sumII_[i] = 0.0;
    }
    if (config_.score == Score::kNcc) {
        imageSums(image1, y0, y1);
    }
    for (std::int32_t k = 0; k < config_.planes; ++k) {
        scorePlane(image1, k, y0, y1);
    }
}

namespace {

// Whether the window around (x, y) lies inside image 2 for every plane. The window maps
// to a convex quadrilateral (w > 0), and each pixel's image-2 position moves along a
// segment between its positions for the nearest and the farthest plane, so the four
// corners at the two extreme planes decide it.
bool windowInsideForAllPlanes(const double* hNear, const double* hFar, double x, double y, double r, double maxU,
                              double maxV) noexcept {
    const double* hs[2] = {hNear, hFar};
    for (const double* h : hs) {
        for (std::int32_t corner = 0; corner < 4; ++corner) {
            const double cx = (corner & 1) != 0 ? x + r : x - r;
            const double cy = (corner & 2) != 0 ? y + r : y - r;
            double u = 0.0, v = 0.0;
            if (!detail::mapPixel(h, cx, cy, u, v) || !(u >= 0.0 && u <= maxU && v >= 0.0 && v <= maxV)) {
                return false;
            }
        }
    }
    return true;
}

struct Decision {
    Reason reason = Reason::kValid;
    double offset = 0.0;  // parabola vertex, planes, in [-0.5, 0.5]
};

Decision decide(std::int16_t best, std::int32_t planes, float below, float at, float above) noexcept {
    Decision d;
    if (best == 0 || best == planes - 1) {
        d.reason = Reason::kOutOfRange;
    } else if (best < 0 || below < 0.0F || above < 0.0F) {
        d.reason = Reason::kOutOfView;
    } else {
        const double a = static_cast<double>(below);
        const double b = static_cast<double>(at);
        const double c = static_cast<double>(above);
        const double curvature = a - 2.0 * b + c;
        if (!(curvature > 0.0)) {
            d.reason = Reason::kNoTexture;
        } else {
            const double o = 0.5 * (a - c) / curvature;
            d.offset = o < -0.5 ? -0.5 : (o > 0.5 ? 0.5 : o);
        }
    }
    return d;
}

}  // namespace

void PlaneSweep::decideBand(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1,
                            const SweepOutput& out, SweepStats& stats) noexcept {
    (void)image1;
    const std::int32_t r = radius_;
    const double* hNear = &homographies_[9U * static_cast<std::size_t>(config_.planes - 1)];
    const double* hFar = &homographies_[0];
    const double minParallax2 = config_.min_parallax_px * config_.min_parallax_px;
    const auto maxU = static_cast<double>(width_ - 1);
    const auto maxV = static_cast<double>(height_ - 1);
    const float sadScale = 1.0F / static_cast<float>(16 * config_.window * config_.window);
    for (std::int32_t y = y0; y < y1; ++y) {
        for (std::int32_t x = 0; x < width_; ++x) {
            const std::size_t idx = static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width_) +
                                    static_cast<std::size_t>(x);
            const std::int16_t best = bestIndex_[idx];
            Decision d;
            double un = 0.0, vn = 0.0, uf = 0.0, vf = 0.0;
            const auto xd = static_cast<double>(x);
            const auto yd = static_cast<double>(y);
            if (x < r || x >= width_ - r) {
                d.reason = Reason::kBorder;
            } else if (!windowInsideForAllPlanes(hNear, hFar, xd, yd, static_cast<double>(r), maxU, maxV) ||
                       !detail::mapPixel(hNear, xd, yd, un, vn) || !detail::mapPixel(hFar, xd, yd, uf, vf)) {
                d.reason = Reason::kOutOfView;
            } else if ((un - uf) * (un - uf) + (vn - vf) * (vn - vf) < minParallax2) {
                d.reason = Reason::kLowParallax;
            } else if (config_.score == Score::kNcc && best < 0 &&
                       static_cast<double>(config_.window * config_.window) * sumII_[idx] - sumI_[idx] * sumI_[idx] <=
                           0.0) {
                d.reason = Reason::kNoTexture;
            } else {
                d = decide(best, config_.planes, belowCost_[idx], bestCost_[idx], aboveCost_[idx]);
            }
            float depth = kNaN;
            if (d.reason == Reason::kValid) {
                const double i0 = inverseDepth_[static_cast<std::size_t>(best)];
                const double step = inverseDepth_[static_cast<std::size_t>(best) + 1U] - i0;
                depth = static_cast<float>(1.0 / (i0 + d.offset * step));
                ++stats.valid_pixels;
            }
            ++stats.reason_counts[static_cast<std::int32_t>(d.reason)];
            out.depth_m.row(y)[x] = depth;
            if (out.score.data() != nullptr) {
                const float cost = bestCost_[idx];
                out.score.row(y)[x] = (best < 0 || x < r || x >= width_ - r)
                                          ? kNaN
                                          : (config_.score == Score::kSad ? cost * sadScale : cost);
            }
            if (out.reason.data() != nullptr) {
                out.reason.row(y)[x] = static_cast<std::uint8_t>(d.reason);
            }
        }
    }
}

void PlaneSweep::markRow(std::int32_t y, const SweepOutput& out, SweepStats& stats) noexcept {
    for (std::int32_t x = 0; x < width_; ++x) {
        out.depth_m.row(y)[x] = kNaN;
        if (out.score.data() != nullptr) {
            out.score.row(y)[x] = kNaN;
        }
        if (out.reason.data() != nullptr) {
            out.reason.row(y)[x] = static_cast<std::uint8_t>(Reason::kBorder);
        }
    }
    stats.reason_counts[static_cast<std::int32_t>(Reason::kBorder)] += width_;
}

Status PlaneSweep::compute(const ImageView<const std::uint16_t>& image1,
                           const ImageView<const std::uint16_t>& image2, const PairGeometry& geometry,
                           const SweepOutput& out, SweepStats* stats) noexcept {
    SweepStats s;
    VTM_RETURN_IF_ERROR(prepare(image1, image2, geometry, out));
    s.scale = scale_;
    s.prefilter_sigma_px = prefilterSigma_;
    const std::int32_t r = radius_;
    for (std::int32_t y = 0; y < r; ++y) {
        markRow(y, out, s);
        markRow(height_ - 1 - y, out, s);
    }
    // bound: (height - 2r) / band_rows + 1 bands
    for (std::int32_t y0 = r; y0 < height_ - r; y0 += config_.band_rows) {
        const std::int32_t y1 = (y0 + config_.band_rows < height_ - r) ? y0 + config_.band_rows : height_ - r;
        sweepBand(image1, y0, y1);
        decideBand(image1, y0, y1, out, s);
    }
    if (stats != nullptr) {
        *stats = s;
    }
    return Status::ok();
}

}  // namespace vtm::descent
