// The sweep proper: per band of image-1 rows, per plane: warp image 2 (bilinear, 1/32 px
// positions) onto the band plus the window's margin, slide the window column sums down
// the band (the entering row in, the leaving one out, one pass), slide along each row for
// the window sums, and keep per pixel the best plane and its neighbours' scores. Then
// decide each pixel: reason, parabola in inverse depth, depth.
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry.hpp"
#include "warp_row.hpp"

namespace vtm::descent {
namespace {

constexpr float kNoScore = std::numeric_limits<float>::lowest();  // below every score
constexpr float kNoCost = -1.0F;                                   // costs are >= 0
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The running column sums of the window score (one entry per column): exact integers in
// doubles (plane_sweep.hpp, colA_).
struct ColumnSums {
    double* a;  // NCC: sum of warped levels; SAD: sum of absolute differences
    double* b;  // NCC: sum of squared warped levels
    double* c;  // NCC: sum of products with image 1
};

// One row's contribution to a column: NCC: w, w^2, i w; SAD: |i - w| (in a). Every
// value is an integer below 2^32: exact in double.
template <bool kNcc>
void addRow(const float* i1, const float* w2, std::int32_t width, const ColumnSums& sums) noexcept {
    double* const colA = sums.a;
    double* const colB = sums.b;
    double* const colC = sums.c;
    for (std::int32_t x = 0; x < width; ++x) {
        const double i = static_cast<double>(i1[x]);
        const double w = static_cast<double>(w2[x]);
        if constexpr (kNcc) {
            colA[x] += w;
            colB[x] += w * w;
            colC[x] += i * w;
        } else {
            colA[x] += std::fabs(i - w);
        }
    }
}

// Moves every column's window down a row: the entering row (i1, w2) in, the leaving row
// (o1, ow) out, in one pass. Exact, so the same sums as adding and subtracting apart.
template <bool kNcc>
void slideRow(const float* i1, const float* w2, const float* o1, const float* ow, std::int32_t width,
              const ColumnSums& sums) noexcept {
    double* const colA = sums.a;
    double* const colB = sums.b;
    double* const colC = sums.c;
    for (std::int32_t x = 0; x < width; ++x) {
        const double i = static_cast<double>(i1[x]);
        const double w = static_cast<double>(w2[x]);
        const double io = static_cast<double>(o1[x]);
        const double wo = static_cast<double>(ow[x]);
        if constexpr (kNcc) {
            colA[x] += w - wo;
            colB[x] += w * w - wo * wo;
            colC[x] += i * w - io * wo;
        } else {
            colA[x] += std::fabs(i - w) - std::fabs(io - wo);
        }
    }
}

// The band's row buffers the column sums run over (buffer row j = image row y0 - r + j):
// image 1's and the warped image 2's, or image 1's twice (its own sums, imageSums()),
// from the first column summed (width columns of rows stride apart).
struct BandRows {
    const float* first;
    const float* second;
    std::int32_t width;
    std::int32_t stride;
    std::int32_t radius;
};

// Zeroes the column sums and adds buffer rows 0..2r: the windows of the band's first row.
void startColumns(const ColumnSums& sums, const BandRows& rows, bool ncc) noexcept {
    const float* const first = rows.first;
    const float* const second = rows.second;
    for (std::int32_t x = 0; x < rows.width; ++x) {
        sums.a[x] = 0.0;
        sums.b[x] = 0.0;
        sums.c[x] = 0.0;
    }
    for (std::int32_t j = 0; j <= 2 * rows.radius; ++j) {
        const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(j) * rows.stride;
        (ncc ? addRow<true> : addRow<false>)(first + at, second + at, rows.width, sums);
    }
}

// Moves the column sums from the windows of band row bandRow - 1 to those of bandRow
// (>= 1): buffer row bandRow + 2r enters, bandRow - 1 leaves.
void slideColumns(const ColumnSums& sums, const BandRows& rows, std::int32_t bandRow, bool ncc) noexcept {
    const float* const first = rows.first;
    const float* const second = rows.second;
    const std::ptrdiff_t enter = static_cast<std::ptrdiff_t>(bandRow + 2 * rows.radius) * rows.stride;
    const std::ptrdiff_t leave = static_cast<std::ptrdiff_t>(bandRow - 1) * rows.stride;
    (ncc ? slideRow<true> : slideRow<false>)(first + enter, second + enter, first + leave, second + leave,
                                             rows.width, sums);
}

// The per-pixel state of a band row (plane_sweep.hpp, bestScore_ ...), as pointers to its
// first pixel.
struct RowState {
    const double* sumI;  // NCC: image 1's window sums and variances
    const double* varI;
    float* best;
    float* prev;
    float* below;
    float* above;
    std::int16_t* index;
};

// Plane k's score at pixel x: the best so far, or the best's upper neighbour; and the
// previous plane's score for the next plane.
inline void keepScore(const RowState& st, std::int32_t x, std::int32_t k, float score) noexcept {
    const std::int16_t best = st.index[x];
    if (best < 0 || score > st.best[x]) {
        st.below[x] = st.prev[x];
        st.above[x] = kNoScore;
        st.best[x] = score;
        st.index[x] = static_cast<std::int16_t>(k);
    } else if (best == k - 1) {
        st.above[x] = score;
    }
    st.prev[x] = score;
}

// The window sums along a row from the column sums: a, b, c over columns p - r .. p + r - 1,
// the run before pixel p's window takes column p + r.
struct WindowRun {
    double a = 0.0, b = 0.0, c = 0.0;
};
WindowRun startRun(const ColumnSums& cols, std::int32_t p, std::int32_t r) noexcept {
    WindowRun run;
    for (std::int32_t x = p - r; x < p + r; ++x) {
        run.a += cols.a[x];
        run.b += cols.b[x];
        run.c += cols.c[x];
    }
    return run;
}

// The pixels of a band row that are scored, [p0, p1] (decideBand() flags the others
// kBorder or kOutOfView whatever their scores).
struct Pixels {
    std::int32_t p0, p1;
};

// SAD: the score is minus the window's sum of absolute differences.
void scoreRowSad(const ColumnSums& cols, std::int32_t r, Pixels px, std::int32_t k, const RowState& st) noexcept {
    const double* colA = cols.a;
    double a = startRun(cols, px.p0, r).a;
    for (std::int32_t x = px.p0; x <= px.p1; ++x) {
        a += colA[x + r];
        keepScore(st, x, k, -static_cast<float>(a));
        a -= colA[x - r];
    }
}

// NCC: the score is ncc * |ncc| = cov |cov| / (varI varW), the planes' order without a
// square root; none where image 1 is flat.
void scoreRowNcc(const ColumnSums& cols, double n, std::int32_t r, Pixels px, std::int32_t k,
                 const RowState& st) noexcept {
    const double* sumI = st.sumI;
    const double* varI = st.varI;
    const double* colA = cols.a;
    const double* colB = cols.b;
    const double* colC = cols.c;
    WindowRun run = startRun(cols, px.p0, r);
    double a = run.a, b = run.b, c = run.c;
    for (std::int32_t x = px.p0; x <= px.p1; ++x) {
        a += colA[x + r];
        b += colB[x + r];
        c += colC[x + r];
        if (varI[x] > 0.0) {
            const double varW = n * b - a * a;
            const double cov = n * c - sumI[x] * a;
            keepScore(st, x, k, varW > 0.0 ? static_cast<float>(cov * std::fabs(cov) / (varI[x] * varW)) : 0.0F);
        } else {
            st.prev[x] = kNoScore;  // image 1 flat here: no score at any plane
        }
        a -= colA[x - r];
        b -= colB[x - r];
        c -= colC[x - r];
    }
}

}  // namespace

// Image 1's rows y0 - r .. y1 + r - 1 as floats, levels x 16 (the warped rows' scale).
void PlaneSweep::loadImage1Rows(const ImageView<const std::uint16_t>& image1, std::int32_t y0,
                                std::int32_t y1) noexcept {
    const std::int32_t w = width_;
    float* out = image1Rows_.data();
    for (std::int32_t y = y0 - radius_; y < y1 + radius_; ++y) {
        const std::uint16_t* row = image1.row(y);
        for (std::int32_t x = 0; x < w; ++x) {
            out[x] = static_cast<float>(static_cast<std::int32_t>(row[x]) << 4);
        }
        out += w;
    }
}

// Image 2 sampled at H_k p for the band's rows, columns [x0, x1) (detail::warpRow).
void PlaneSweep::warpRows(std::int32_t k, std::int32_t yFirst, std::int32_t rows, std::int32_t x0,
                          std::int32_t x1) noexcept {
    const double* h = &homographies_[9U * static_cast<std::size_t>(k)];
    for (std::int32_t j = 0; j < rows; ++j) {
        float* out = warped_.data() + static_cast<std::ptrdiff_t>(j) * width_;
        detail::warpRow(h, yFirst + j, x0, x1, image2_.data(), width_, height_, out);
    }
}

// Plane k over the band's pixels p0..p1: its columns p0 - r .. p1 + r warped and summed.
void PlaneSweep::scorePlane(std::int32_t k, std::int32_t y0, std::int32_t y1, std::int32_t p0,
                            std::int32_t p1) noexcept {
    const std::int32_t c0 = p0 - radius_;
    const std::int32_t c1 = p1 + radius_ + 1;  // past the last column
    warpRows(k, y0 - radius_, y1 - y0 + 2 * radius_, c0, c1);
    const ColumnSums sums{colA_.data() + c0, colB_.data() + c0, colC_.data() + c0};
    const BandRows rows{image1Rows_.data() + c0, warped_.data() + c0, c1 - c0, width_, radius_};
    const bool ncc = config_.score == Score::kNcc;
    startColumns(sums, rows, ncc);
    for (std::int32_t j = 0; j < y1 - y0; ++j) {
        if (j > 0) {
            slideColumns(sums, rows, j, ncc);
        }
        scoreRow(k, j, p0, p1);
    }
}

void PlaneSweep::scoreRow(std::int32_t k, std::int32_t bandRow, std::int32_t p0, std::int32_t p1) noexcept {
    // Raw pointers into the spans, taken once (the loops' bounds keep every index inside:
    // columns 0..w-1, the band row's pixels r..w-r-1).
    const std::ptrdiff_t rowBase = static_cast<std::ptrdiff_t>(bandRow) * width_;
    const ColumnSums cols{colA_.data(), colB_.data(), colC_.data()};
    const RowState st{sumI_.data() + rowBase,       varI_.data() + rowBase,       bestScore_.data() + rowBase,
                      prevScore_.data() + rowBase,  belowScore_.data() + rowBase, aboveScore_.data() + rowBase,
                      bestIndex_.data() + rowBase};
    if (config_.score == Score::kNcc) {
        scoreRowNcc(cols, static_cast<double>(config_.window * config_.window), radius_, Pixels{p0, p1}, k, st);
    } else {
        scoreRowSad(cols, radius_, Pixels{p0, p1}, k, st);
    }
}

// NCC: window sum of image 1 (levels x 16) and its variance term n sum(i^2) - sum(i)^2
// for the band's pixels (each term below 2^52: exact).
void PlaneSweep::imageSums(std::int32_t y0, std::int32_t y1) noexcept {
    const std::int32_t r = radius_;
    const std::int32_t w = width_;
    const auto nd = static_cast<double>(config_.window * config_.window);
    // The image-1 rows stand in for the warped ones: a = sum i, b = sum i^2.
    const ColumnSums sums{colA_.data(), colB_.data(), colC_.data()};
    const BandRows rows{image1Rows_.data(), image1Rows_.data(), w, w, r};
    startColumns(sums, rows, true);
    for (std::int32_t j = 0; j < y1 - y0; ++j) {
        if (j > 0) {
            slideColumns(sums, rows, j, true);
        }
        double* const sumI = sumI_.data() + static_cast<std::ptrdiff_t>(j) * w;
        double* const varI = varI_.data() + static_cast<std::ptrdiff_t>(j) * w;
        const WindowRun run = startRun(sums, r, r);
        double s = run.a;
        double ss = run.b;
        for (std::int32_t x = r; x < w - r; ++x) {
            s += sums.a[x + r];
            ss += sums.b[x + r];
            sumI[x] = s;
            varI[x] = nd * ss - s * s;
            s -= sums.a[x - r];
            ss -= sums.b[x - r];
        }
    }
}

void PlaneSweep::sweepBand(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1) noexcept {
    const std::size_t n = static_cast<std::size_t>(y1 - y0) * static_cast<std::size_t>(width_);
    for (std::size_t i = 0; i < n; ++i) {
        bestIndex_[i] = -1;
        bestScore_[i] = kNoScore;
        prevScore_[i] = kNoScore;
        belowScore_[i] = kNoScore;
        aboveScore_[i] = kNoScore;
        sumI_[i] = 0.0;
        varI_[i] = 0.0;
    }
    loadImage1Rows(image1, y0, y1);
    if (config_.score == Score::kNcc) {
        imageSums(y0, y1);
    }
    std::int32_t p0 = 0, p1 = -1;
    inViewColumns(y0, y1, p0, p1);
    // bound: planes_ <= Config::planes; none when no pixel of the band can get a depth
    for (std::int32_t k = 0; p0 <= p1 && k < planes_; ++k) {
        scorePlane(k, y0, y1, p0, p1);
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

}  // namespace

// A superset of the pixels of the band whose window stays inside image 2 for every plane
// (decideBand()'s kOutOfView test: its corners at the nearest and the farthest plane),
// as the first and last column: only they can get a depth, so only their windows are
// scored. Per row the intersection of each corner's span (detail::spanMappedInside).
// p0 > p1: none.
void PlaneSweep::inViewColumns(std::int32_t y0, std::int32_t y1, std::int32_t& p0, std::int32_t& p1) const noexcept {
    const double* hs[2] = {&homographies_[9U * static_cast<std::size_t>(planes_ - 1)], &homographies_[0]};
    const std::int32_t r = radius_;
    const auto rd = static_cast<double>(r);
    p0 = width_;
    p1 = -1;
    for (std::int32_t y = y0; y < y1; ++y) {
        double lo = rd;
        double hi = static_cast<double>(width_ - 1 - r);
        for (const double* h : hs) {
            for (std::int32_t corner = 0; corner < 4; ++corner) {
                const double dx = (corner & 1) != 0 ? rd : -rd;
                const double yc = static_cast<double>(y) + ((corner & 2) != 0 ? rd : -rd);
                double a = 0.0, b = 0.0;
                detail::spanMappedInside(h, dx, yc, width_, height_, a, b);
                lo = std::max(lo, a);
                hi = std::min(hi, b);
            }
        }
        if (lo <= hi) {  // lo, hi >= 0: truncation is floor; one more column each side
            p0 = std::min(p0, std::max(r, static_cast<std::int32_t>(lo) - 1));
            p1 = std::max(p1, std::min(width_ - 1 - r, static_cast<std::int32_t>(hi) + 1));
        }
    }
}

namespace {

// A kept score as the cost the parabola and the score output use: SAD: the sum of
// absolute differences; NCC: 1 - ncc (0 .. 2). kNoCost where there is no score.
float costOf(float score, bool ncc) noexcept {
    if (score == kNoScore) {
        return kNoCost;
    }
    if (!ncc) {
        return -score;
    }
    const double q = static_cast<double>(score);
    const double value = q >= 0.0 ? std::sqrt(q) : -std::sqrt(-q);
    const double oneMinus = 1.0 - value;
    return static_cast<float>(oneMinus > 0.0 ? oneMinus : 0.0);
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
    const double* hNear = &homographies_[9U * static_cast<std::size_t>(planes_ - 1)];
    const double* hFar = &homographies_[0];
    const double minParallax2 = config_.min_parallax_px * config_.min_parallax_px;
    const auto maxU = static_cast<double>(width_ - 1);
    const auto maxV = static_cast<double>(height_ - 1);
    const float sadScale = 1.0F / static_cast<float>(16 * config_.window * config_.window);
    const bool ncc = config_.score == Score::kNcc;
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
            } else if (ncc && best < 0 && varI_[idx] <= 0.0) {
                d.reason = Reason::kNoTexture;
            } else {
                d = decide(best, planes_, costOf(belowScore_[idx], ncc), costOf(bestScore_[idx], ncc),
                           costOf(aboveScore_[idx], ncc));
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
                // No score where the window left either image (its samples there are
                // border stand-ins, warpRows()).
                const float cost = costOf(bestScore_[idx], ncc);
                const bool none = best < 0 || d.reason == Reason::kBorder || d.reason == Reason::kOutOfView;
                out.score.row(y)[x] = none ? kNaN : (ncc ? cost : cost * sadScale);
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
    s.max_parallax_px = maxParallax_;
    s.planes = planes_;
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
