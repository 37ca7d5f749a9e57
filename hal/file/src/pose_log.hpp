// Parsing of the pose-log text format into fixed-capacity storage (init only).
#pragma once

#include "hal/file/file_limits.hpp"
#include "hal/odometry.hpp"
#include "vtm/core/fixed_vector.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::detail {

// Reads the pose log at `path` into `out` (cleared first). Status as FileOdometry::init.
[[nodiscard]] Status loadPoseLog(const char* path, FixedVector<PoseEstimate, file_limits::kMaxPoses>& out) noexcept;

}  // namespace vtm::hal::detail
