// The variogram of elevation samples (paper §3; docs/kriging.md "Variogram"): the
// experimental semivariogram in distance bins from a bounded, deterministic set of sample
// pairs, and a spherical or exponential model (nugget, partial sill, range) fitted to it
// by weighted least squares.
//
// Models (h >= 0, metres; gamma in m^2; gamma(0) = 0 by definition):
//   spherical:   gamma(h) = c0 + c (1.5 h/a - 0.5 (h/a)^3) for 0 < h < a, c0 + c beyond;
//   exponential: gamma(h) = c0 + c (1 - exp(-3 h / a))  (a = the practical range: 95 %).
// c0 = nugget_m2, c = partial_sill_m2, a = range_m; the sill is c0 + c.
// Covariance form used by the kriging: C(h) = sill - gamma(h), C(0) = sill.
#pragma once

#include <cstdint>

#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::kriging {

enum class VariogramModel : std::uint8_t {
    kSpherical = 0,
    kExponential = 1,
};

// Which model fitVariogram() may choose. Stable values (telemetry).
enum class ModelChoice : std::uint8_t {
    kBest = 0,         // both fitted; the lower weighted residual wins (spherical on a tie)
    kSpherical = 1,
    kExponential = 2,
};

constexpr std::int32_t kMaxVariogramBins = 64;
// Bins with fewer pairs than this are left out of the fit (too noisy to weigh).
constexpr std::int32_t kMinPairsPerBin = 8;

struct Variogram {
    VariogramModel model = VariogramModel::kExponential;
    double nugget_m2 = 0.0;        // c0 >= 0
    double partial_sill_m2 = 0.0;  // c > 0
    double range_m = 1.0;          // a > 0
    // True when the samples were flatter than KrigingConfig::min_sill_m2 and the
    // documented minimum variogram was used instead of a fit (docs/kriging.md).
    bool fallback = false;
    // Weighted residual sum of squares of the fit (m^4 times the weights; 0 for a fallback).
    double fit_cost = 0.0;

    [[nodiscard]] double sillM2() const noexcept { return nugget_m2 + partial_sill_m2; }
    // gamma(h), h in metres (h <= 0 gives 0).
    [[nodiscard]] double gamma(double h_m) const noexcept;
    // C(h) = sill - gamma(h); C(0) = sill.
    [[nodiscard]] double covariance(double h_m) const noexcept;
};

// The experimental semivariogram: per bin the pairs' mean distance and
// gamma = sum (z_i - z_j)^2 / (2 pairs).
struct ExperimentalVariogram {
    std::int32_t bins = 0;
    double bin_width_m = 0.0;
    double max_lag_m = 0.0;
    std::int64_t pairs_used = 0;  // pairs within max_lag that entered a bin
    double lag_m[kMaxVariogramBins]{};
    double gamma_m2[kMaxVariogramBins]{};
    std::int64_t pairs[kMaxVariogramBins]{};
};

// The model's shape at h / a in [0, inf): spherical 1.5 u - 0.5 u^3 (u < 1) else 1;
// exponential 1 - exp(-3 u). vtm::math only: the same bits on every target.
[[nodiscard]] double modelShape(VariogramModel model, double u) noexcept;

// How the experimental semivariogram is taken (KrigingConfig carries these fields).
struct PairSampling {
    std::int32_t bins = 16;            // 4..kMaxVariogramBins
    double max_lag_m = 1.0;            // > 0: pairs farther apart are left out
    std::int64_t max_pairs = 200000;   // all pairs when n (n - 1) / 2 <= max_pairs, else
                                       // max_pairs pairs drawn by vtm::Random(seed)
    std::uint64_t seed = 1U;
};

// The experimental semivariogram of samples (north_m[i], east_m[i], elevation_m[i]), all
// spans of one length. Deterministic: the pairs, their order and the sums are fixed by the
// inputs and the seed. kInvalidArgument for spans of different lengths, fewer than two
// samples or a bad sampling (reason names the field).
[[nodiscard]] Status experimentalVariogram(Span<const double> north_m, Span<const double> east_m,
                                           Span<const double> elevation_m, const PairSampling& sampling,
                                           ExperimentalVariogram& out) noexcept;

// Fits a model to an experimental semivariogram (docs/kriging.md "Variogram"): for each
// model a weighted least-squares fit of (nugget, partial sill) for each candidate range
// (a geometric ladder of kRangeLadder ranges from half a bin width to twice the max lag,
// then kGoldenSteps golden-section steps about the best), weights pairs_j / gamma_j^2 over
// the bins holding at least kMinPairsPerBin pairs. zero_nugget holds c0 at 0; a negative
// c0 refits with c0 = 0. `choice` picks the model or the lower weighted residual.
// Flat samples (no bin's gamma reaches min_sill_m2): the minimum variogram (exponential,
// nugget 0, partial sill min_sill_m2, range = max lag), fallback = true, ok.
// kDegenerate when fewer than three bins are usable or no range gives a positive sill.
[[nodiscard]] Status fitVariogramModel(const ExperimentalVariogram& experimental, ModelChoice choice,
                                       bool zero_nugget, double min_sill_m2, Variogram& out) noexcept;

constexpr std::int32_t kRangeLadder = 48;
constexpr std::int32_t kGoldenSteps = 40;

}  // namespace vtm::kriging
