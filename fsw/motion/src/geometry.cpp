// Small rotation / direction helpers of the motion refinement: the tangent basis of the
// translation direction and the direction angle used by the evaluation (the rotation
// helpers are vtm/core/rotation.hpp). Only + - * / and vtm::math: the same bits on
// every target.
#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/motion/motion_refiner.hpp"

namespace vtm::motion {
namespace {

bool finite3(const Vec3& v) noexcept {
    return math::isFinite(v.x()) && math::isFinite(v.y()) && math::isFinite(v.z());
}

}  // namespace

void directionTangentBasis(const Vec3& u, Vec3& b1, Vec3& b2) noexcept {
    // The axis least aligned with u gives the best-conditioned cross product.
    int k = 0;
    if (std::fabs(u.y()) < std::fabs(u.x())) {
        k = 1;
    }
    if (std::fabs(u.z()) < std::fabs(u[k])) {
        k = 2;
    }
    const Vec3 e = Vec3::Unit(k);
    const Vec3 c = e.cross(u);
    b1 = c / math::sqrt(c.dot(c));
    b2 = u.cross(b1);
}

double directionAngleRad(const Vec3& a, const Vec3& b) noexcept {
    if (!finite3(a) || !finite3(b) || a.dot(a) == 0.0 || b.dot(b) == 0.0) {
        return math::kNaN;
    }
    const Vec3 c = a.cross(b);
    return math::atan2(math::sqrt(c.dot(c)), a.dot(b));
}

}  // namespace vtm::motion
