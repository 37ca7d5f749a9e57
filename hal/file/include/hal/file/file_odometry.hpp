// hal::Odometry playing back a recorded pose log (docs/hal-file.md, "Pose log"):
//
//   vtm-poses 1
//   # timestamp_ns x y z qw qx qy qz  then 6 variances or 36 covariance values
//   1000000000 0 0 0 1 0 0 0  1e-4 1e-4 1e-4 1e-6 1e-6 1e-6
//
// Poses are T_site_from_vehicle as hal/odometry.hpp defines them (site frame x north,
// y east, z down, metres; unit quaternion w x y z). Between two logged poses poseAt()
// interpolates: position and covariance linearly, attitude along the great arc (slerp,
// computed with square roots only, so the same bits on every target).
//
// Memory: kMaxPoses poses in this object (about 1.4 MiB: declare it static or inside a
// statically allocated owner). Nothing allocates, at init or after.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/file/file_limits.hpp"
#include "hal/odometry.hpp"
#include "vtm/core/fixed_vector.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

// A final driver, statically allocated and never deleted through hal::Odometry (whose
// destructor is protected): its implicit public destructor needs no virtual.
class FileOdometry final : public Odometry {
public:
    struct Config {
        // The pose log, NUL-terminated, 1..kMaxPathChars (255) characters. Only read during init().
        const char* pose_log_path = nullptr;
        // Two logged poses further apart than this are not interpolated (kNoData): a gap in
        // the log is a gap in knowledge. 0: no limit.
        std::uint64_t max_interpolation_gap_ns = 0U;

        // kInvalidConfig naming the field when it is out of range.
        [[nodiscard]] Status validate() const noexcept;
    };

    FileOdometry() noexcept = default;

    // Validates the config and loads the pose log. Errors carry the 1-based line number in
    // detail() (errno for kIoError): kIoError, kCorruptData (malformed line; a pose that
    // fails validatePose(), with validatePose's reason), kOutOfOrder (timestamp_ns not
    // increasing), kUnsupported (beyond file_limits, version other than 1), kNoData (no pose).
    // On failure the odometry stays uninitialised.
    [[nodiscard]] Status init(const Config& config) noexcept;

    // The pose at timestamp_ns: a logged pose exactly, else interpolated between the two
    // logged poses around it. kNoData before the first or after the last logged pose
    // (detail -1 / +1) or inside a gap longer than max_interpolation_gap_ns (detail = gap).
    [[nodiscard]] Status poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept override;

    [[nodiscard]] std::size_t poseCount() const noexcept { return poses_.size(); }

private:
    FixedVector<PoseEstimate, file_limits::kMaxPoses> poses_{};
    std::uint64_t max_gap_ns_ = 0U;
    bool initialized_ = false;
};

}  // namespace vtm::hal
