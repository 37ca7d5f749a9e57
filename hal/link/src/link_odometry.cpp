#include "hal/link/link_session.hpp"
#include "hal/odometry.hpp"

namespace vtm::hal::link {

Status LinkSession::lookUpPose(std::uint64_t timestamp_ns, PoseEstimate& out) const noexcept {
    if (!rejected_pose_status_.isOk() && rejected_pose_time_ns_ == timestamp_ns) {
        return rejected_pose_status_;
    }
    if (poses_.empty() || timestamp_ns > poses_.at(poses_.size() - 1U).timestamp_ns) {
        return Status(StatusCode::kNoData, "link: no pose received for this time yet", 1);
    }
    if (timestamp_ns < poses_.at(0U).timestamp_ns) {
        return Status(StatusCode::kNoData, "link: time older than the pose ring holds", -1);
    }
    // bound: kPoseRingCapacity entries
    for (std::size_t i = 0U; i < poses_.size(); ++i) {
        const PoseEstimate& p = poses_.at(i);
        if (p.timestamp_ns == timestamp_ns) {
            out = p;
            return Status::ok();
        }
        if (p.timestamp_ns > timestamp_ns) {
            // i > 0: at(0) <= timestamp_ns was checked, and equality returned above.
            const PoseEstimate& before = poses_.at(i - 1U);
            const std::uint64_t gap_ns = p.timestamp_ns - before.timestamp_ns;
            if (config_.max_interpolation_gap_ns > 0U && gap_ns > config_.max_interpolation_gap_ns) {
                return Status(StatusCode::kNoData, "link: poses around this time too far apart to interpolate",
                              static_cast<std::int64_t>(gap_ns));
            }
            out = interpolatePose(before, p, timestamp_ns);
            return Status::ok();
        }
    }
    return Status(StatusCode::kNoData, "link: no pose received for this time yet", 1);
}

Status LinkSession::poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "link: poseAt() before init()");
    }
    VTM_RETURN_IF_ERROR(pumpControlUntilPose(timestamp_ns, deadlineNs()));
    return lookUpPose(timestamp_ns, out);
}

Status LinkOdometry::poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept {
    return session_->poseAt(timestamp_ns, out);
}

}  // namespace vtm::hal::link
