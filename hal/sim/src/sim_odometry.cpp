#include "hal/sim/sim_odometry.hpp"

#include "vtm/core/math.hpp"

namespace vtm::hal {
namespace {

const sim::VehiclePose& odometryPose(const sim::ScenarioFrames& frames, std::int32_t frame) noexcept {
    return frames.frames[frame].odometry_pose;
}

void copyPose(const sim::VehiclePose& from, PoseEstimate& to) noexcept {
    to.timestamp_ns = from.timestamp_ns;
    for (int i = 0; i < 3; ++i) {
        to.position_m[i] = from.position_m[i];
    }
    for (int i = 0; i < 4; ++i) {
        to.attitude_wxyz[i] = from.attitude_wxyz[i];
    }
    for (int i = 0; i < 36; ++i) {
        to.covariance[i] = from.covariance[i];
    }
}

}  // namespace

Status SimOdometry::init(const Config& config) noexcept {
    initialized_ = false;
    if (config.frames == nullptr) {
        return Status(StatusCode::kInvalidConfig, "SimOdometry::Config: frames is null");
    }
    const sim::ScenarioFrames& frames = *config.frames;
    std::int32_t count = 0;
    // Insertion by timestamp, one sample per distinct time: at most kMaxScenarioFrames^2 steps.
    for (std::int32_t f = 0; f < frames.count && f < sim::kMaxScenarioFrames; ++f) {
        const std::uint64_t t = frames.frames[f].odometry_pose.timestamp_ns;
        std::int32_t at = count;
        while (at > 0 && odometryPose(frames, sample_frame_[at - 1]).timestamp_ns > t) {  // bound: count
            --at;
        }
        if (at > 0 && odometryPose(frames, sample_frame_[at - 1]).timestamp_ns == t) {
            continue;  // same instant as a sample already kept (a stereo pair's two frames)
        }
        for (std::int32_t k = count; k > at; --k) {
            sample_frame_[k] = sample_frame_[k - 1];
        }
        sample_frame_[at] = f;
        ++count;
    }
    if (count == 0) {
        return Status(StatusCode::kInvalidConfig, "SimOdometry::Config: frames holds no frame");
    }
    config_ = config;
    sample_count_ = count;
    initialized_ = true;
    return Status::ok();
}

// The time stamp the pose source puts on a sample (its true time unless a
// kPoseTimestampBackwards fault is active at that time).
std::uint64_t SimOdometry::sourceStamp(std::int32_t sample) const noexcept {
    const std::uint64_t t = odometryPose(*config_.frames, sample_frame_[sample]).timestamp_ns;
    const Fault* f = (config_.faults == nullptr) ? nullptr
                                                 : config_.faults->odometryFault(FaultKind::kPoseTimestampBackwards, t);
    if (f == nullptr) {
        return t;
    }
    return (t > f->backwards_ns) ? t - f->backwards_ns : 0U;
}

// A driver's own check: the samples it uses must be stamped after their predecessors.
Status SimOdometry::checkSourceOrder(std::int32_t sample) const noexcept {
    if (sample > 0 && sourceStamp(sample) <= sourceStamp(sample - 1)) {
        return Status(StatusCode::kOutOfOrder, "SimOdometry: pose source timestamps went backwards",
                      static_cast<std::int64_t>(sample));
    }
    return Status::ok();
}

Status SimOdometry::poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "SimOdometry: poseAt before a successful init()");
    }
    const sim::ScenarioFrames& frames = *config_.frames;
    const sim::VehiclePose& first = odometryPose(frames, sample_frame_[0]);
    const sim::VehiclePose& last = odometryPose(frames, sample_frame_[sample_count_ - 1]);
    if (timestamp_ns < first.timestamp_ns) {
        return Status(StatusCode::kNoData, "SimOdometry: time before the first pose", -1);
    }
    if (timestamp_ns > last.timestamp_ns) {
        return Status(StatusCode::kNoData, "SimOdometry: time after the last pose", 1);
    }
    std::int32_t b = 0;  // first sample at or after t
    while (b < sample_count_ && odometryPose(frames, sample_frame_[b]).timestamp_ns < timestamp_ns) {  // bound: count
        ++b;
    }
    PoseEstimate pose;
    const sim::VehiclePose& pb = odometryPose(frames, sample_frame_[b]);
    VTM_RETURN_IF_ERROR(checkSourceOrder(b));
    if (pb.timestamp_ns == timestamp_ns) {
        copyPose(pb, pose);
    } else {
        VTM_RETURN_IF_ERROR(checkSourceOrder(b - 1));
        PoseEstimate before;
        PoseEstimate after;
        copyPose(odometryPose(frames, sample_frame_[b - 1]), before);
        copyPose(pb, after);
        pose = interpolatePose(before, after, timestamp_ns);
    }
    pose.timestamp_ns = timestamp_ns;
    if (config_.faults != nullptr) {
        if (const Fault* f = config_.faults->odometryFault(FaultKind::kOdometryJump, timestamp_ns); f != nullptr) {
            for (int i = 0; i < 3; ++i) {
                pose.position_m[i] += f->offset_m[i];
            }
        }
        if (config_.faults->odometryFault(FaultKind::kPoseNaN, timestamp_ns) != nullptr) {
            pose.position_m[0] = math::kNaN;
        }
    }
    VTM_RETURN_IF_ERROR(validatePose(pose));
    out = pose;
    return Status::ok();
}

}  // namespace vtm::hal
