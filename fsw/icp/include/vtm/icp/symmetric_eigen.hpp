// Eigen-decomposition of a small symmetric matrix by cyclic Jacobi rotations: only + - * /
// and sqrt, a fixed number of sweeps at most, so the same bits on every target (Eigen's
// SelfAdjointEigenSolver is not part of vtm/core/eigen.hpp). Used for the 3x3 covariance
// of a model neighbourhood (its normal) and the 6x6 normal matrix of a fit (its conditioning).
#pragma once

#include <cmath>

#include "vtm/core/eigen.hpp"

namespace vtm::icp {

// Sweeps at most; each sweep rotates every off-diagonal pair once. Jacobi converges
// quadratically: 3x3 and 6x6 matrices reach full precision in 4-8 sweeps.
constexpr int kJacobiMaxSweeps = 16;

namespace detail {

// Sum of squares of the off-diagonal (upper) and diagonal elements.
template <int N>
void offAndDiagonal(const Eigen::Matrix<double, N, N>& a, double& off, double& diag) noexcept {
    off = 0.0;
    diag = 0.0;
    for (int p = 0; p < N; ++p) {
        diag += a(p, p) * a(p, p);
        for (int q = p + 1; q < N; ++q) {
            off += a(p, q) * a(p, q);
        }
    }
}

// One Jacobi rotation that zeroes a(p, q) (Golub and Van Loan 8.5.2, the smaller angle):
// a <- J^T a J, vectors <- vectors J.
template <int N>
void jacobiRotate(Eigen::Matrix<double, N, N>& a, Eigen::Matrix<double, N, N>& vectors, int p, int q) noexcept {
    const double apq = a(p, q);
    if (apq == 0.0) {
        return;
    }
    const double theta = (a(q, q) - a(p, p)) / (2.0 * apq);
    const double at = std::fabs(theta);
    const double t = (at > 1e150) ? 0.5 / theta : (theta >= 0.0 ? 1.0 : -1.0) / (at + std::sqrt(theta * theta + 1.0));
    const double c = 1.0 / std::sqrt(t * t + 1.0);
    const double s = t * c;
    for (int k = 0; k < N; ++k) {
        const double akp = a(k, p);
        const double akq = a(k, q);
        a(k, p) = c * akp - s * akq;
        a(k, q) = s * akp + c * akq;
    }
    for (int k = 0; k < N; ++k) {
        const double apk = a(p, k);
        const double aqk = a(q, k);
        a(p, k) = c * apk - s * aqk;
        a(q, k) = s * apk + c * aqk;
    }
    for (int k = 0; k < N; ++k) {
        const double vkp = vectors(k, p);
        const double vkq = vectors(k, q);
        vectors(k, p) = c * vkp - s * vkq;
        vectors(k, q) = s * vkp + c * vkq;
    }
}

// Ascending order by selection (N <= 6): ties keep the lower index first.
template <int N>
void sortAscending(Eigen::Matrix<double, N, 1>& values, Eigen::Matrix<double, N, N>& vectors) noexcept {
    for (int i = 0; i < N - 1; ++i) {
        int best = i;
        for (int j = i + 1; j < N; ++j) {
            best = values(j) < values(best) ? j : best;
        }
        if (best != i) {
            const double v = values(i);
            values(i) = values(best);
            values(best) = v;
            vectors.col(i).swap(vectors.col(best));
        }
    }
}

}  // namespace detail

// values ascending; vectors' column i is the unit eigenvector of values(i).
template <int N>
void symmetricEigen(const Eigen::Matrix<double, N, N>& m, Eigen::Matrix<double, N, 1>& values,
                    Eigen::Matrix<double, N, N>& vectors) noexcept {
    Eigen::Matrix<double, N, N> a = m;
    vectors.setIdentity();
    for (int sweep = 0; sweep < kJacobiMaxSweeps; ++sweep) {
        double off = 0.0;
        double diag = 0.0;
        detail::offAndDiagonal<N>(a, off, diag);
        if (off <= 1e-32 * diag || off == 0.0) {
            break;
        }
        for (int p = 0; p < N - 1; ++p) {
            for (int q = p + 1; q < N; ++q) {
                detail::jacobiRotate<N>(a, vectors, p, q);
            }
        }
    }
    for (int i = 0; i < N; ++i) {
        values(i) = a(i, i);
    }
    detail::sortAscending<N>(values, vectors);
}

}  // namespace vtm::icp
