// Anti-alias prefilter of image 2 (the closer image): a separable Gaussian with integer
// weights summing to 256 per pass, borders replicated. Output grey levels x 16.
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/descent/plane_sweep.hpp"

namespace vtm::descent {
namespace {

constexpr std::int32_t kWeightSum = 256;  // per pass; two passes: 65536 = 2^16
// Result = sum / 2^16 * 16 = sum >> 12, rounded.
constexpr std::int32_t kShift = 12;
constexpr std::int32_t kRound = 1 << (kShift - 1);

struct Kernel {
    std::int32_t radius = 0;
    std::int32_t weight[kMaxPrefilterRadius + 1] = {};  // weight[|j|]
};

// Quantised Gaussian: w_j = round(256 g_j / sum g) for j != 0, the centre takes the rest,
// so the weights sum to exactly 256. vtm::math::exp: the same weights on every target.
Kernel makeKernel(double sigma_px) noexcept {
    Kernel k;
    if (!(sigma_px >= 0.1)) {
        k.weight[0] = kWeightSum;
        return k;
    }
    const double r = std::ceil(3.0 * sigma_px);
    k.radius = r < static_cast<double>(kMaxPrefilterRadius) ? static_cast<std::int32_t>(r) : kMaxPrefilterRadius;
    double g[kMaxPrefilterRadius + 1] = {};
    double total = 0.0;
    for (std::int32_t j = 0; j <= k.radius; ++j) {
        const double x = static_cast<double>(j);
        g[j] = math::exp(-x * x / (2.0 * sigma_px * sigma_px));
        total += (j == 0) ? g[j] : 2.0 * g[j];
    }
    std::int32_t rest = kWeightSum;
    for (std::int32_t j = 1; j <= k.radius; ++j) {
        k.weight[j] = static_cast<std::int32_t>(std::floor(static_cast<double>(kWeightSum) * g[j] / total + 0.5));
        rest -= 2 * k.weight[j];
    }
    k.weight[0] = rest;
    return k;
}

std::int32_t clampIndex(std::int32_t i, std::int32_t n) noexcept { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

}  // namespace

void PlaneSweep::prefilter(const ImageView<const std::uint16_t>& image2, double sigma_px) noexcept {
    const Kernel k = makeKernel(sigma_px);
    const std::int32_t w = image2.width();
    const std::int32_t h = image2.height();
    std::int32_t* acc = filterRow_.data();
    for (std::int32_t y = 0; y < h; ++y) {
        // Vertical pass into one row (at most 4095 * 256, fits easily).
        for (std::int32_t x = 0; x < w; ++x) {
            acc[x] = k.weight[0] * static_cast<std::int32_t>(image2.row(y)[x]);
        }
        for (std::int32_t j = 1; j <= k.radius; ++j) {
            const std::uint16_t* up = image2.row(clampIndex(y - j, h));
            const std::uint16_t* down = image2.row(clampIndex(y + j, h));
            for (std::int32_t x = 0; x < w; ++x) {
                acc[x] += k.weight[j] * (static_cast<std::int32_t>(up[x]) + static_cast<std::int32_t>(down[x]));
            }
        }
        // Horizontal pass (at most 4095 * 65536 < 2^31).
        std::uint16_t* out = image2_.data() + static_cast<std::ptrdiff_t>(y) * w;
        for (std::int32_t x = 0; x < w; ++x) {
            std::int32_t s = k.weight[0] * acc[x];
            for (std::int32_t j = 1; j <= k.radius; ++j) {
                s += k.weight[j] * (acc[clampIndex(x - j, w)] + acc[clampIndex(x + j, w)]);
            }
            out[x] = static_cast<std::uint16_t>((s + kRound) >> kShift);
        }
    }
    // The padding after the last row (warpRows() reads it with weight 0 at the image's
    // last row and column; zero, so that every value read is defined).
    std::uint16_t* pad = image2_.data() + static_cast<std::ptrdiff_t>(h) * w;
    for (std::int32_t x = 0; x <= w; ++x) {
        pad[x] = 0U;
    }
}

}  // namespace vtm::descent
