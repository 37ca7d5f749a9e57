// The linear solve of one ordinary-kriging system: at most kMaxSystemSize unknowns
// (kMaxKrigingNeighbours weights and the Lagrange multiplier), Gaussian elimination with
// partial pivoting on a fixed-size array (no Eigen dynamic matrices in flight code, no heap).
#pragma once

#include <cstdint>

namespace vtm::kriging {

constexpr std::int32_t kMaxSystemSize = 17;

struct KrigingSystem {
    std::int32_t n = 0;                          // unknowns, 1..kMaxSystemSize
    double a[kMaxSystemSize][kMaxSystemSize]{};  // row-major; destroyed by solve()
    double b[kMaxSystemSize]{};                  // right-hand side; destroyed by solve()
};

// Solves a x = b in place of the system. False (x untouched) when n is out of range or a
// pivot is not larger than 1e-12 times the largest |a_ij| (singular: two samples at one
// position). Row swaps choose the largest |pivot|, the lower row on a tie: the same steps,
// and the same bits, on every target.
[[nodiscard]] bool solveKrigingSystem(KrigingSystem& system, double (&x)[kMaxSystemSize]) noexcept;

}  // namespace vtm::kriging
