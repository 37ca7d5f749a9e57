// hal::Odometry: the vehicle's pose estimate (wheel odometry + IMU on a rover, the
// navigation filter on a lander) at a requested time, with its covariance.
#pragma once

#include <cstdint>

#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

// Pose of the vehicle in the site frame: site_from_vehicle.
// Site frame: x north, y east, z down (metres). Attitude: unit quaternion (w, x, y, z)
// rotating vehicle-frame vectors into the site frame.
// Covariance: 6x6 row-major over (x, y, z [m], rx, ry, rz [rad]), the rotation part as
// a small rotation vector applied on the left (site frame).
// The fields mirror the HIL link's pose record (docs/icd-hil-link.md) and the pose log;
// code that computes with the pose takes it as a vtm::RigidPose through siteFromVehicle()
// below, the one place that turns the quaternion into a rotation matrix (docs/hal.md).
struct PoseEstimate {
    std::uint64_t timestamp_ns = 0U;
    double position_m[3] = {0.0, 0.0, 0.0};
    double attitude_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
    double covariance[36] = {};
};

class Odometry {
public:

    // Pose at time t (monotonic ns, same clock as FrameInfo::timestamp_ns).
    // Failures: kNoData (no pose covers t), kCorruptData (NaN or non-unit quaternion),
    // kOutOfOrder (the source's timestamps went backwards), kTimeout.
    [[nodiscard]] virtual Status poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) = 0;

protected:
    // Not deletable through the interface, hence no virtual destructor: a virtual one
    // makes every driver emit a deleting destructor that references operator delete
    // (the heap-symbol check rejects it). Drivers are statically allocated and final.
    Odometry() = default;
    ~Odometry() = default;
    Odometry(const Odometry&) = default;
    Odometry& operator=(const Odometry&) = default;
    Odometry(Odometry&&) = default;
    Odometry& operator=(Odometry&&) = default;
};

// Checks what every driver must check before handing a pose out: finite numbers,
// quaternion norm within 1e-6 of 1, covariance diagonal non-negative.
[[nodiscard]] Status validatePose(const PoseEstimate& pose) noexcept;

// The pose as the shared vocabulary's site_from_vehicle (vtm/core/pose.hpp): R from the
// attitude quaternion, normalised (Eigen's Quaternion::normalized().toRotationMatrix()),
// t_m = position_m. For a pose that passed validatePose (the covariance is not carried).
[[nodiscard]] RigidPose siteFromVehicle(const PoseEstimate& pose) noexcept;

// The pose at time t between two poses, a.timestamp_ns < t < b.timestamp_ns; the same
// bits on every target (only + - * / and sqrt, no transcendental function):
//  - position and covariance: a + s (b - a), s = (t - ta) / (tb - ta); a convex
//    combination of two covariances stays symmetric and positive semi-definite;
//  - attitude: slerp along the shorter arc, q = qa (qa* qb)^s, the power computed from
//    the binary digits of s by repeated quaternion square roots.
[[nodiscard]] PoseEstimate interpolatePose(const PoseEstimate& a, const PoseEstimate& b, std::uint64_t t) noexcept;

}  // namespace vtm::hal
