#include <cmath>

#include "hal/link/link_session.hpp"

namespace vtm::hal::link {
namespace {

// Pose between a (f = 0) and b (f = 1): position and covariance linearly, attitude by
// normalised linear interpolation on the shorter arc (square root only: same bits on
// every target).
PoseEstimate interpolate(const PoseEstimate& a, const PoseEstimate& b, std::uint64_t t_ns) noexcept {
    const double f = static_cast<double>(t_ns - a.timestamp_ns) / static_cast<double>(b.timestamp_ns - a.timestamp_ns);
    PoseEstimate out;
    out.timestamp_ns = t_ns;
    for (std::size_t i = 0U; i < 3U; ++i) {
        out.position_m[i] = a.position_m[i] + f * (b.position_m[i] - a.position_m[i]);
    }
    double dot = 0.0;
    for (std::size_t i = 0U; i < 4U; ++i) {
        dot += a.attitude_wxyz[i] * b.attitude_wxyz[i];
    }
    const double sign = (dot < 0.0) ? -1.0 : 1.0;
    double norm2 = 0.0;
    for (std::size_t i = 0U; i < 4U; ++i) {
        out.attitude_wxyz[i] = (1.0 - f) * a.attitude_wxyz[i] + f * sign * b.attitude_wxyz[i];
        norm2 += out.attitude_wxyz[i] * out.attitude_wxyz[i];
    }
    const double inv = 1.0 / std::sqrt(norm2);
    for (double& q : out.attitude_wxyz) {
        q *= inv;
    }
    for (std::size_t i = 0U; i < 36U; ++i) {
        out.covariance[i] = a.covariance[i] + f * (b.covariance[i] - a.covariance[i]);
    }
    return out;
}

}  // namespace

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
            out = interpolate(before, p, timestamp_ns);
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
