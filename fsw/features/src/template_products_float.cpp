// The coarse search's products from float copies (template_ncc.hpp, crossSumsFloatRun).
// Its own file: added to template_ncc.cpp it moved that file's integer pass and made the
// host's (x86-64) rover refine stage 5 % slower with the same instructions (code layout).
#include "template_ncc.hpp"

namespace vtm::features::detail {
namespace {

// acc + a b, fused where the target has a fast fused multiply-add. Exact for the values of
// crossSumsFloatRun either way (no rounding), so the same bits on every target.
inline double mulAdd(double a, double b, double acc) noexcept {
#if defined(__FP_FAST_FMA)
    return __builtin_fma(a, b, acc);
#else
    return a * b + acc;
#endif
}

// Template column dx against the row rb: position k's value is rb[dx + k].
template <std::size_t kCount, std::size_t kRun>
inline void accumulateColumn(const float* const* t, std::int32_t dx, const float* rb, double (*sab)[kCount]) noexcept {
    double tv[kCount];
    for (std::size_t i = 0; i < kCount; ++i) {
        tv[i] = static_cast<double>(t[i][dx]);
    }
    for (std::size_t k = 0; k < kRun; ++k) {
        const double vb = rb[dx + static_cast<std::int32_t>(k)];
        for (std::size_t i = 0; i < kCount; ++i) {
            sab[k][i] = mulAdd(tv[i], vb, sab[k][i]);
        }
    }
}

// Template columns dx .. dx + kRun - 1 against the image values w[0 .. 2 kRun - 2] (w[u + k]
// is position k's value under column dx + u).
template <std::size_t kCount, std::size_t kRun>
inline void accumulateGroup(const float* const* t, std::int32_t dx, const double* w, double (*sab)[kCount]) noexcept {
    for (std::size_t u = 0; u < kRun; ++u) {
        for (std::size_t i = 0; i < kCount; ++i) {
            const double tv = t[i][dx + static_cast<std::int32_t>(u)];
            for (std::size_t k = 0; k < kRun; ++k) {
                sab[k][i] = mulAdd(tv, w[u + k], sab[k][i]);
            }
        }
    }
}

// The first columns of a row in groups of kRun (accumulateGroup): the image values a group
// needs are loaded once into w (2 kRun - 1 of them, kRun new per group) and each template
// value once. Returns the first column not done.
template <std::size_t kCount, std::size_t kRun>
std::int32_t accumulateGroups(const float* const* t, const float* rb, std::int32_t side, double (*sab)[kCount]) noexcept {
    constexpr auto kStep = static_cast<std::int32_t>(kRun);
    double w[2 * kRun];
    for (std::size_t k = 0; k + 1 < kRun; ++k) {
        w[k] = rb[k];
    }
    std::int32_t dx = 0;
    for (; dx + kStep <= side; dx += kStep) {
        for (std::size_t k = 0; k < kRun; ++k) {
            w[kRun - 1 + k] = rb[dx + static_cast<std::int32_t>(kRun - 1 + k)];
        }
        accumulateGroup<kCount, kRun>(t, dx, w, sab);
        for (std::size_t k = 0; k + 1 < kRun; ++k) {
            w[k] = w[kRun + k];
        }
    }
    return dx;
}

// Position k of the run is the window whose top-left pixel is rb + k. kGroups: the row's
// columns in groups of kRun first (accumulateGroups), the rest one by one. On the 750 about
// 4.2 instructions per position and pixel at kRun 4 with groups, 5.2 without (there a
// register rotation of the loaded values costs a move per value and step).
template <std::size_t kCount, std::size_t kRun, bool kGroups>
void floatRunPass(const float* const* templates, const float* rb, std::int32_t stride, std::int32_t half,
                  double* cross) noexcept {
    const std::int32_t side = 2 * half + 1;
    const float* t[kCount];
    double sab[kRun][kCount];
    for (std::size_t i = 0; i < kCount; ++i) {
        t[i] = templates[i];
        for (std::size_t k = 0; k < kRun; ++k) {
            sab[k][i] = 0.0;
        }
    }
    for (std::int32_t dy = 0; dy < side; ++dy, rb += stride) {
        std::int32_t dx = 0;
        if constexpr (kGroups) {
            dx = accumulateGroups<kCount, kRun>(t, rb, side, sab);
        }
        for (; dx < side; ++dx) {
            accumulateColumn<kCount, kRun>(t, dx, rb, sab);
        }
        for (std::size_t i = 0; i < kCount; ++i) {
            t[i] += side;
        }
    }
    for (std::size_t k = 0; k < kRun; ++k) {
        for (std::size_t i = 0; i < kCount; ++i) {
            cross[k * kCount + i] = sab[k][i];
        }
    }
}

template <std::size_t kCount>
void floatRunOf(const float* const* templates, const float* rb, std::int32_t stride, std::int32_t run,
                std::int32_t half, double* cross) noexcept {
    switch (run) {
        case 4:
            floatRunPass<kCount, 4, true>(templates, rb, stride, half, cross);
            break;
        case 3:
            floatRunPass<kCount, 3, false>(templates, rb, stride, half, cross);
            break;
        case 2:
            floatRunPass<kCount, 2, false>(templates, rb, stride, half, cross);
            break;
        default:
            floatRunPass<kCount, 1, false>(templates, rb, stride, half, cross);
            break;
    }
}

}  // namespace

void crossSumsFloatRun(const float* const* templates, std::int32_t count, const ImageView<const float>& to, Pos b,
                       std::int32_t run, std::int32_t half, double* cross) noexcept {
    static_assert(kMaxRun == 4, "floatRunOf instantiates runs of 1..4");
    const float* rb = to.row(b.y - half) + (b.x - half);
    if (count > 1) {
        floatRunOf<2>(templates, rb, to.stride(), run, half, cross);
    } else {
        floatRunOf<1>(templates, rb, to.stride(), run, half, cross);
    }
}

void toFloats(const std::uint16_t* values, std::int32_t n, float* dst) noexcept {
    for (std::int32_t i = 0; i < n; ++i) {
        dst[i] = static_cast<float>(values[i]);
    }
}

void toFloats(const ImageView<const std::uint8_t>& image, float* dst) noexcept {
    const std::int32_t w = image.width();
    for (std::int32_t y = 0; y < image.height(); ++y) {
        const std::uint8_t* r = image.row(y);
        float* d = dst + static_cast<std::ptrdiff_t>(y) * w;
        for (std::int32_t x = 0; x < w; ++x) {
            d[x] = static_cast<float>(r[x]);
        }
    }
}

}  // namespace vtm::features::detail
