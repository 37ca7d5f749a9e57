// The only way flight code includes Eigen. It routes eigen_assert to VTM_ASSERT (so
// EIGEN_NO_MALLOC's heap check fires in every build type, NDEBUG included) and names the
// fixed-size types flight code uses. tools/checks/policy.py rejects any other Eigen
// include under fsw/.
#pragma once

#include "vtm/core/assert.hpp"

#if defined(eigen_assert)
#  error "vtm/core/eigen.hpp must be included before any Eigen header"
#endif
#define eigen_assert(x) VTM_ASSERT(x)

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/Cholesky>

namespace vtm {
using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaternion<double>;
}  // namespace vtm
