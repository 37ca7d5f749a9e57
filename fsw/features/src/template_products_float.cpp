// The coarse search's products from float copies (template_ncc.hpp, crossSumsFloatRun).
// Its own file: added to template_ncc.cpp it moved that file's integer pass and made the
// host's (x86-64) rover refine stage 5 % slower with the same instructions (code layout).
#include "template_ncc.hpp"

namespace vtm::features::detail {
namespace {

// acc + a b, fused where the target has a fast fused multiply-add. Exact for the values of
// crossSumsFloat either way (no rounding), so the same bits on every target.
inline double mulAdd(double a, double b, double acc) noexcept {
#if defined(__FP_FAST_FMA)
    return __builtin_fma(a, b, acc);
#else
    return a * b + acc;
#endif
}

// Position k of the run is the window whose top-left pixel is rb + k.
template <std::size_t kCount, std::size_t kRun>
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
        for (std::int32_t dx = 0; dx < side; ++dx) {
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

// Template column dx against the row rb: position k's value is rb[dx + k].
template <std::size_t kCount, std::size_t kRun>
inline void accumulateColumn(const float* const* t, std::int32_t dx, const float* rb, double (*sab)[kCount]) noexcept {
    for (std::size_t i = 0; i < kCount; ++i) {
        const double tv = t[i][dx];
        for (std::size_t k = 0; k < kRun; ++k) {
            sab[k][i] = mulAdd(tv, rb[dx + static_cast<std::int32_t>(k)], sab[k][i]);
        }
    }
}

// floatRunPass for a run of kRun positions with the row unrolled by kRun: the image values
// a group of kRun template columns needs are loaded once into w (2 kRun - 1 of them, kRun
// new per group) and each template value once; the remaining columns as floatRunPass. On
// the 750 about 4.2 instructions per position and pixel at kRun 4 (floatRunPass: 5.2; a
// register rotation of its loaded values costs a move per value and step).
template <std::size_t kCount, std::size_t kRun>
void floatRunPassUnrolled(const float* const* templates, const float* rb, std::int32_t stride,
                          std::int32_t half, double* cross) noexcept {
    constexpr auto kStep = static_cast<std::int32_t>(kRun);
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
            floatRunPassUnrolled<kCount, 4>(templates, rb, stride, half, cross);
            break;
        case 3:
            floatRunPass<kCount, 3>(templates, rb, stride, half, cross);
            break;
        case 2:
            floatRunPass<kCount, 2>(templates, rb, stride, half, cross);
            break;
        default:
            floatRunPass<kCount, 1>(templates, rb, stride, half, cross);
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
