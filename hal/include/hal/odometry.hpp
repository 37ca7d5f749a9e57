// hal::Odometry: the vehicle's pose estimate (wheel odometry + IMU on a rover, the
// navigation filter on a lander) at a requested time, with its covariance.
#pragma once

#include <cstdint>

#include "vtm/core/status.hpp"

namespace vtm::hal {

// Pose of the vehicle in the site frame: T_site_from_vehicle.
// Site frame: x north, y east, z down (metres). Attitude: unit quaternion (w, x, y, z)
// rotating vehicle-frame vectors into the site frame.
// Covariance: 6x6 row-major over (x, y, z [m], rx, ry, rz [rad]), the rotation part as
// a small rotation vector applied on the left (site frame).
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

}  // namespace vtm::hal
