// The bundle adjuster's small numerical pieces: SO(3)'s left Jacobian, the robust losses,
// a dense Cholesky of the reduced camera system.
#include "bundle_internal.hpp"

#include "vtm/core/math.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::bundle {

Mat3 leftJacobian(const Vec3& theta) noexcept {
    const double a2 = theta.squaredNorm();
    const Mat3 k = skew(theta);
    if (a2 < 1e-12) {
        return Mat3::Identity() + 0.5 * k + (1.0 / 6.0) * (k * k);
    }
    const double a = math::sqrt(a2);
    const double c1 = (1.0 - math::cos(a)) / a2;
    const double c2 = (a - math::sin(a)) / (a2 * a);
    return Mat3::Identity() + c1 * k + c2 * (k * k);
}

double robustRho(const BundleConfig& c, double u) noexcept {
    const double k = c.robust_k;
    if (c.loss == RobustLoss::kCauchy) {
        return k * k * math::log1p((u * u) / (k * k));
    }
    return u <= k ? u * u : 2.0 * k * u - k * k;
}

double robustWeight(const BundleConfig& c, double u) noexcept {
    const double k = c.robust_k;
    if (c.loss == RobustLoss::kCauchy) {
        return 1.0 / (1.0 + (u * u) / (k * k));
    }
    return u <= k ? 1.0 : k / u;
}

std::int64_t choleskyInPlace(double* a, std::size_t n, double relative_floor) noexcept {
    for (std::size_t j = 0; j < n; ++j) {
        double* rj = a + j * n;
        const double diagonal = rj[j];
        double d = diagonal;
        for (std::size_t k = 0; k < j; ++k) {
            d -= rj[k] * rj[k];
        }
        if (!(d > relative_floor * diagonal) || !(d > 0.0)) {
            return static_cast<std::int64_t>(j);
        }
        const double ljj = math::sqrt(d);
        rj[j] = ljj;
        for (std::size_t i = j + 1; i < n; ++i) {
            double* ri = a + i * n;
            double s = ri[j];
            for (std::size_t k = 0; k < j; ++k) {
                s -= ri[k] * rj[k];
            }
            ri[j] = s / ljj;
        }
    }
    return -1;
}

void choleskySolve(const double* l, std::size_t n, double* b) noexcept {
    for (std::size_t i = 0; i < n; ++i) {  // L y = b
        const double* ri = l + i * n;
        double s = b[i];
        for (std::size_t k = 0; k < i; ++k) {
            s -= ri[k] * b[k];
        }
        b[i] = s / ri[i];
    }
    for (std::size_t ii = n; ii > 0U; --ii) {  // L^T x = y
        const std::size_t i = ii - 1U;
        double s = b[i];
        for (std::size_t k = i + 1U; k < n; ++k) {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

}  // namespace vtm::bundle
