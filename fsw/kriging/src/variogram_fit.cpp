// Weighted least-squares fit of a variogram model to the experimental semivariogram.
#include <cmath>
#include <limits>

#include "vtm/core/math.hpp"
#include "vtm/kriging/variogram.hpp"

namespace vtm::kriging {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The bins that enter the fit, with their weights pairs / gamma^2 (gamma floored at
// min_sill_m2 so a bin of zero semivariance does not weigh infinitely).
struct FitData {
    std::int32_t count = 0;
    double h[kMaxVariogramBins]{};
    double g[kMaxVariogramBins]{};
    double w[kMaxVariogramBins]{};
    double max_gamma = 0.0;
};

FitData fitData(const ExperimentalVariogram& ev, double min_sill_m2) noexcept {
    FitData d;
    for (std::int32_t b = 0; b < ev.bins && b < kMaxVariogramBins; ++b) {
        if (ev.pairs[b] < kMinPairsPerBin) {
            continue;
        }
        const double g = ev.gamma_m2[b];
        const double floor_g = g > min_sill_m2 ? g : min_sill_m2;
        d.h[d.count] = ev.lag_m[b];
        d.g[d.count] = g;
        d.w[d.count] = static_cast<double>(ev.pairs[b]) / (floor_g * floor_g);
        d.max_gamma = g > d.max_gamma ? g : d.max_gamma;
        ++d.count;
    }
    return d;
}

struct Trial {
    double range_m = 0.0;
    double nugget_m2 = 0.0;
    double sill_m2 = 0.0;  // partial
    double cost = kInfinity;
};

// Best (nugget, partial sill) for one model and range: linear weighted least squares.
Trial fitAtRange(const FitData& d, VariogramModel model, double range_m, bool zero_nugget) noexcept {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, t0 = 0.0, t1 = 0.0;
    double f[kMaxVariogramBins]{};
    for (std::int32_t j = 0; j < d.count; ++j) {
        f[j] = modelShape(model, d.h[j] / range_m);
        s0 += d.w[j];
        s1 += d.w[j] * f[j];
        s2 += d.w[j] * f[j] * f[j];
        t0 += d.w[j] * d.g[j];
        t1 += d.w[j] * f[j] * d.g[j];
    }
    Trial t;
    t.range_m = range_m;
    const double det = s0 * s2 - s1 * s1;
    bool free_fit = !zero_nugget && det > 1e-12 * s0 * s2;
    if (free_fit) {
        t.sill_m2 = (s0 * t1 - s1 * t0) / det;
        t.nugget_m2 = (t0 - s1 * t.sill_m2) / s0;
        free_fit = t.nugget_m2 >= 0.0;
    }
    if (!free_fit) {
        t.nugget_m2 = 0.0;
        t.sill_m2 = s2 > 0.0 ? t1 / s2 : 0.0;
    }
    if (!(t.sill_m2 > 0.0)) {
        return Trial{range_m, 0.0, 0.0, kInfinity};
    }
    double cost = 0.0;
    for (std::int32_t j = 0; j < d.count; ++j) {
        const double r = d.g[j] - t.nugget_m2 - t.sill_m2 * f[j];
        cost += d.w[j] * r * r;
    }
    t.cost = cost;
    return t;
}

// The ladder of ranges, then golden-section steps about its best rung.
Trial fitModel(const FitData& d, VariogramModel model, double lo_m, double hi_m, bool zero_nugget) noexcept {
    const double ratio = math::exp(math::log(hi_m / lo_m) / static_cast<double>(kRangeLadder - 1));
    double rung[kRangeLadder]{};
    Trial best;
    std::int32_t best_rung = 0;
    double a = lo_m;
    for (std::int32_t i = 0; i < kRangeLadder; ++i) {
        rung[i] = a;
        const Trial t = fitAtRange(d, model, a, zero_nugget);
        if (t.cost < best.cost) {
            best = t;
            best_rung = i;
        }
        a *= ratio;
    }
    if (!(best.cost < kInfinity)) {
        return best;
    }
    double left = rung[best_rung > 0 ? best_rung - 1 : 0];
    double right = rung[best_rung + 1 < kRangeLadder ? best_rung + 1 : kRangeLadder - 1];
    constexpr double kInvPhi = 0.6180339887498949;
    double x1 = right - kInvPhi * (right - left);
    double x2 = left + kInvPhi * (right - left);
    Trial t1 = fitAtRange(d, model, x1, zero_nugget);
    Trial t2 = fitAtRange(d, model, x2, zero_nugget);
    for (std::int32_t s = 0; s < kGoldenSteps; ++s) {
        if (t1.cost < t2.cost) {
            right = x2;
            x2 = x1;
            t2 = t1;
            x1 = right - kInvPhi * (right - left);
            t1 = fitAtRange(d, model, x1, zero_nugget);
        } else {
            left = x1;
            x1 = x2;
            t1 = t2;
            x2 = left + kInvPhi * (right - left);
            t2 = fitAtRange(d, model, x2, zero_nugget);
        }
    }
    const Trial& golden = t1.cost < t2.cost ? t1 : t2;
    return golden.cost < best.cost ? golden : best;
}

Variogram fromTrial(VariogramModel model, const Trial& t) noexcept {
    Variogram v;
    v.model = model;
    v.nugget_m2 = t.nugget_m2;
    v.partial_sill_m2 = t.sill_m2;
    v.range_m = t.range_m;
    v.fit_cost = t.cost;
    return v;
}

}  // namespace

Status fitVariogramModel(const ExperimentalVariogram& experimental, ModelChoice choice, bool zero_nugget,
                         double min_sill_m2, Variogram& out) noexcept {
    if (!std::isfinite(min_sill_m2) || !(min_sill_m2 > 0.0) || !(experimental.max_lag_m > 0.0) ||
        !(experimental.bin_width_m > 0.0)) {
        return Status(StatusCode::kInvalidArgument, "variogram fit: min_sill_m2, max_lag_m or bin width not > 0");
    }
    const FitData d = fitData(experimental, min_sill_m2);
    if (d.count < 3) {
        return Status(StatusCode::kDegenerate, "variogram fit: fewer than three bins hold kMinPairsPerBin pairs",
                      d.count);
    }
    if (d.max_gamma < min_sill_m2) {
        Variogram v;
        v.model = VariogramModel::kExponential;
        v.partial_sill_m2 = min_sill_m2;
        v.range_m = experimental.max_lag_m;
        v.fallback = true;
        out = v;
        return Status::ok();
    }
    const double lo = 0.5 * experimental.bin_width_m;
    const double hi = 2.0 * experimental.max_lag_m;
    Trial sph;
    Trial expo;
    if (choice != ModelChoice::kExponential) {
        sph = fitModel(d, VariogramModel::kSpherical, lo, hi, zero_nugget);
    }
    if (choice != ModelChoice::kSpherical) {
        expo = fitModel(d, VariogramModel::kExponential, lo, hi, zero_nugget);
    }
    if (!(sph.cost < kInfinity) && !(expo.cost < kInfinity)) {
        return Status(StatusCode::kDegenerate, "variogram fit: no range gives a positive sill");
    }
    out = expo.cost < sph.cost ? fromTrial(VariogramModel::kExponential, expo)
                               : fromTrial(VariogramModel::kSpherical, sph);
    return Status::ok();
}

}  // namespace vtm::kriging
