#include "hal/file/file_odometry.hpp"

#include "pose_log.hpp"
#include "text_lines.hpp"

namespace vtm::hal {

Status FileOdometry::Config::validate() const noexcept {
    if (pose_log_path == nullptr) {
        return Status(StatusCode::kInvalidConfig, "FileOdometry::Config: pose_log_path is null");
    }
    const std::size_t length = detail::boundedLength(pose_log_path, file_limits::kMaxPathChars);
    if (length == 0U) {
        return Status(StatusCode::kInvalidConfig, "FileOdometry::Config: pose_log_path is empty");
    }
    if (length > file_limits::kMaxPathChars) {
        return Status(StatusCode::kInvalidConfig,
                      "FileOdometry::Config: pose_log_path longer than kMaxPathChars (255)",
                      static_cast<std::int64_t>(length));
    }
    return Status::ok();
}

Status FileOdometry::init(const Config& config) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    max_gap_ns_ = config.max_interpolation_gap_ns;
    VTM_RETURN_IF_ERROR(detail::loadPoseLog(config.pose_log_path, poses_));
    initialized_ = true;
    return Status::ok();
}

Status FileOdometry::poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "FileOdometry: poseAt before a successful init()");
    }
    const std::size_t last = poses_.size() - 1U;  // init() guarantees at least one pose
    if (timestamp_ns < poses_[0].timestamp_ns) {
        return Status(StatusCode::kNoData, "FileOdometry: time before the first logged pose", -1);
    }
    if (timestamp_ns > poses_[last].timestamp_ns) {
        return Status(StatusCode::kNoData, "FileOdometry: time after the last logged pose", 1);
    }
    if (timestamp_ns == poses_[last].timestamp_ns) {
        out = poses_[last];
        return Status::ok();
    }
    // Binary search for t[lo] <= t < t[hi], hi = lo + 1 (invariant holds from the start).
    // It halves the interval each pass: 64 passes cover any size_t count.
    std::size_t lo = 0U;
    std::size_t hi = last;
    for (int pass = 0; pass < 64 && hi - lo > 1U; ++pass) {
        const std::size_t mid = lo + (hi - lo) / 2U;
        if (poses_[mid].timestamp_ns <= timestamp_ns) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    if (timestamp_ns == poses_[lo].timestamp_ns) {
        out = poses_[lo];
        return Status::ok();
    }
    const std::uint64_t gap_ns = poses_[hi].timestamp_ns - poses_[lo].timestamp_ns;
    if (max_gap_ns_ != 0U && gap_ns > max_gap_ns_) {
        const std::uint64_t kMaxDetail = 0x7FFFFFFFFFFFFFFFU;
        return Status(StatusCode::kNoData, "FileOdometry: time inside a log gap longer than max_interpolation_gap_ns",
                      static_cast<std::int64_t>(gap_ns < kMaxDetail ? gap_ns : kMaxDetail));
    }
    const PoseEstimate p = interpolatePose(poses_[lo], poses_[hi], timestamp_ns);
    VTM_RETURN_IF_ERROR(validatePose(p));
    out = p;
    return Status::ok();
}

}  // namespace vtm::hal
