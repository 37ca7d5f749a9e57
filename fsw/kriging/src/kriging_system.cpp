// Gaussian elimination with partial pivoting for the kriging system.
#include <cmath>

#include "vtm/kriging/kriging_system.hpp"

namespace vtm::kriging {
namespace {

double largestEntry(const KrigingSystem& s) noexcept {
    double m = 0.0;
    for (std::int32_t i = 0; i < s.n; ++i) {
        for (std::int32_t j = 0; j < s.n; ++j) {
            const double v = std::fabs(s.a[i][j]);
            m = v > m ? v : m;
        }
    }
    return m;
}

void swapRows(KrigingSystem& s, std::int32_t r0, std::int32_t r1) noexcept {
    for (std::int32_t j = 0; j < s.n; ++j) {
        const double t = s.a[r0][j];
        s.a[r0][j] = s.a[r1][j];
        s.a[r1][j] = t;
    }
    const double t = s.b[r0];
    s.b[r0] = s.b[r1];
    s.b[r1] = t;
}

}  // namespace

bool solveKrigingSystem(KrigingSystem& s, double (&x)[kMaxSystemSize]) noexcept {
    if (s.n < 1 || s.n > kMaxSystemSize) {
        return false;
    }
    const double tiny = 1e-12 * largestEntry(s);
    if (!(tiny > 0.0) || !std::isfinite(tiny)) {
        return false;
    }
    for (std::int32_t c = 0; c < s.n; ++c) {
        std::int32_t pivot = c;
        for (std::int32_t r = c + 1; r < s.n; ++r) {
            pivot = std::fabs(s.a[r][c]) > std::fabs(s.a[pivot][c]) ? r : pivot;
        }
        if (!(std::fabs(s.a[pivot][c]) > tiny)) {
            return false;
        }
        if (pivot != c) {
            swapRows(s, c, pivot);
        }
        for (std::int32_t r = c + 1; r < s.n; ++r) {
            const double f = s.a[r][c] / s.a[c][c];
            for (std::int32_t j = c; j < s.n; ++j) {
                s.a[r][j] -= f * s.a[c][j];
            }
            s.b[r] -= f * s.b[c];
        }
    }
    double y[kMaxSystemSize]{};
    for (std::int32_t r = s.n - 1; r >= 0; --r) {
        double v = s.b[r];
        for (std::int32_t j = r + 1; j < s.n; ++j) {
            v -= s.a[r][j] * y[j];
        }
        y[r] = v / s.a[r][r];
    }
    for (std::int32_t i = 0; i < s.n; ++i) {
        x[i] = y[i];
    }
    return true;
}

}  // namespace vtm::kriging
