// Variogram models and the experimental semivariogram.
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"
#include "vtm/kriging/variogram.hpp"

namespace vtm::kriging {

double modelShape(VariogramModel model, double u) noexcept {
    if (!(u > 0.0)) {
        return 0.0;
    }
    if (model == VariogramModel::kSpherical) {
        return u < 1.0 ? 1.5 * u - 0.5 * u * u * u : 1.0;
    }
    return 1.0 - math::exp(-3.0 * u);
}

double Variogram::gamma(double h_m) const noexcept {
    if (!(h_m > 0.0)) {
        return 0.0;
    }
    return nugget_m2 + partial_sill_m2 * modelShape(model, h_m / range_m);
}

double Variogram::covariance(double h_m) const noexcept { return sillM2() - gamma(h_m); }

namespace {

// Adds the pair (i, j) to its bin when within the max lag.
void addPair(Span<const double> n, Span<const double> e, Span<const double> z, std::size_t i, std::size_t j,
             ExperimentalVariogram& out) noexcept {
    const double dn = n[i] - n[j];
    const double de = e[i] - e[j];
    const double h = std::sqrt(dn * dn + de * de);
    if (!(h < out.max_lag_m)) {
        return;
    }
    auto bin = static_cast<std::int32_t>(h / out.bin_width_m);
    bin = bin < out.bins ? bin : out.bins - 1;
    const double dz = z[i] - z[j];
    out.lag_m[bin] += h;
    out.gamma_m2[bin] += dz * dz;
    ++out.pairs[bin];
    ++out.pairs_used;
}

Status checkSampling(const PairSampling& s) noexcept {
    if (s.bins < 4 || s.bins > kMaxVariogramBins) {
        return Status(StatusCode::kInvalidArgument, "variogram sampling: bins must be 4..64", s.bins);
    }
    if (!std::isfinite(s.max_lag_m) || !(s.max_lag_m > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "variogram sampling: max_lag_m must be finite and > 0");
    }
    if (s.max_pairs < 1) {
        return Status(StatusCode::kInvalidArgument, "variogram sampling: max_pairs must be >= 1", s.max_pairs);
    }
    return Status::ok();
}

}  // namespace

Status experimentalVariogram(Span<const double> north_m, Span<const double> east_m, Span<const double> elevation_m,
                             const PairSampling& sampling, ExperimentalVariogram& out) noexcept {
    VTM_RETURN_IF_ERROR(checkSampling(sampling));
    const std::size_t n = north_m.size();
    if (east_m.size() != n || elevation_m.size() != n) {
        return Status(StatusCode::kInvalidArgument, "variogram samples: north, east and elevation differ in length");
    }
    if (n < 2U) {
        return Status(StatusCode::kInvalidArgument, "variogram samples: fewer than two",
                      static_cast<std::int64_t>(n));
    }
    out = ExperimentalVariogram{};
    out.bins = sampling.bins;
    out.max_lag_m = sampling.max_lag_m;
    out.bin_width_m = sampling.max_lag_m / static_cast<double>(sampling.bins);
    const auto all_pairs = static_cast<std::int64_t>(n) * (static_cast<std::int64_t>(n) - 1) / 2;
    if (all_pairs <= sampling.max_pairs) {
        for (std::size_t i = 0; i + 1U < n; ++i) {
            for (std::size_t j = i + 1U; j < n; ++j) {
                addPair(north_m, east_m, elevation_m, i, j, out);
            }
        }
    } else {
        Random random(sampling.seed);
        const auto last = static_cast<std::int64_t>(n) - 1;
        for (std::int64_t p = 0; p < sampling.max_pairs; ++p) {
            const std::int64_t i = random.uniformInt(0, last);
            const std::int64_t j0 = random.uniformInt(0, last - 1);
            const std::int64_t j = j0 >= i ? j0 + 1 : j0;  // any other sample, uniformly
            addPair(north_m, east_m, elevation_m, static_cast<std::size_t>(i), static_cast<std::size_t>(j), out);
        }
    }
    for (std::int32_t b = 0; b < out.bins; ++b) {
        if (out.pairs[b] > 0) {
            const auto count = static_cast<double>(out.pairs[b]);
            out.lag_m[b] /= count;
            out.gamma_m2[b] /= 2.0 * count;
        }
    }
    return Status::ok();
}

}  // namespace vtm::kriging
