#include <algorithm>
#include <cstring>

#include "hal/link/link_session.hpp"

namespace vtm::hal::link {

Status LinkSession::Config::validate() const noexcept {
    if (timeout_ms < 1U || timeout_ms > 600000U) {
        return Status(StatusCode::kInvalidConfig, "link: timeout_ms must be 1..600000", timeout_ms);
    }
    return Status::ok();
}

Status LinkSession::init(const Config& config, ByteStream& stream, const Clock& clock) noexcept {
    VTM_RETURN_IF_ERROR(config.validate());
    config_ = config;
    stream_ = &stream;
    clock_ = &clock;
    decoder_.reset();
    decoder_.counters() = LinkCounters{};
    end_of_stream_ = false;
    have_description_ = false;
    has_pending_frame_ = false;
    PoseEstimate drained;
    // bound: kPoseRingCapacity entries
    while (poses_.pop(drained)) {
    }
    rejected_pose_status_ = Status::ok();
    receive_pos_ = 0U;
    receive_len_ = 0U;
    initialized_ = true;
    return Status::ok();
}

Status LinkSession::reconnect(ByteStream& stream) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "link: reconnect() before init()");
    }
    LinkCounters& c = decoder_.counters();
    c.bytes_skipped += receive_len_ - receive_pos_;
    ++c.reconnects;
    decoder_.reset();  // the new stream's sequence numbers start again
    stream_ = &stream;
    end_of_stream_ = false;
    has_pending_frame_ = false;
    receive_pos_ = 0U;
    receive_len_ = 0U;
    return Status::ok();
}

Status LinkSession::fault(LinkFault which, StatusCode code, const char* reason, std::int64_t detail) noexcept {
    decoder_.counters().add(which);
    return Status(code, reason, detail);
}

std::uint64_t LinkSession::deadlineNs() const noexcept {
    return clock_->monotonicNs() + static_cast<std::uint64_t>(config_.timeout_ms) * 1000000ULL;
}

Status LinkSession::nextMessage(std::uint64_t deadline_ns) noexcept {
    // Each pass either decodes buffered bytes (the decoder consumes at least one byte or
    // completes a message) or waits on the stream for at most the time left.
    // bound: the deadline (kTimeout)
    for (;;) {
        if (receive_pos_ < receive_len_ || decoder_.hasPending()) {
            std::size_t used = 0U;
            bool ready = false;
            const Status s = decoder_.push(
                Span<const std::uint8_t>(receive_ + receive_pos_, receive_len_ - receive_pos_), used, ready);
            receive_pos_ += used;
            if (!s.isOk() && LinkDecoder::harmless(decoder_.lastFault())) {
                continue;  // counted; garbage and a message received again cost no message
            }
            if (!s.isOk() || ready) {
                return s;
            }
            continue;
        }
        const std::uint64_t now = clock_->monotonicNs();
        if (now >= deadline_ns) {
            return fault(LinkFault::kTimeout, StatusCode::kTimeout, "link: no complete message before the timeout",
                         static_cast<std::int64_t>(config_.timeout_ms));
        }
        const std::uint64_t left_ms = (deadline_ns - now + 999999U) / 1000000U;
        std::size_t got = 0U;
        const Status s = stream_->receive(receive_, sizeof(receive_), static_cast<std::uint32_t>(left_ms), got);
        if (s.code() == StatusCode::kTimeout) {
            continue;  // the deadline check above decides
        }
        if (s.code() == StatusCode::kNoData) {
            return fault(LinkFault::kStreamError, StatusCode::kIoError,
                         "link: connection closed before the end-of-stream message", 0);
        }
        if (!s.isOk()) {
            return fault(LinkFault::kStreamError, s.code(), s.reason(), s.detail());
        }
        receive_pos_ = 0U;
        receive_len_ = got;
    }
}

Status LinkSession::applyControl(const Message& message) noexcept {
    switch (message.header.type) {
        case MessageType::kCameraDescription: {
            CameraDescription d;
            const Status s = decodeCameraDescription(message.payload, d);
            if (!s.isOk()) {
                decoder_.counters().add(LinkFault::kBadLength);
                return s;
            }
            description_ = d;
            have_description_ = true;
            return Status::ok();
        }
        case MessageType::kPose: {
            PoseEstimate p;
            Status s = decodePose(message.payload, p);
            if (s.isOk()) {
                s = validatePose(p);
            }
            if (s.isOk() && !poses_.empty() && p.timestamp_ns <= poses_.at(poses_.size() - 1U).timestamp_ns) {
                s = Status(StatusCode::kOutOfOrder, "link: pose timestamp_ns not after the previous pose's");
            }
            if (!s.isOk()) {
                // Not the camera's problem: poseAt() reports it for this time.
                decoder_.counters().add(LinkFault::kBadPose);
                rejected_pose_time_ns_ = p.timestamp_ns;
                rejected_pose_status_ = s;
                return Status::ok();
            }
            poses_.push(p);
            ++decoder_.counters().poses_ok;
            return Status::ok();
        }
        case MessageType::kEndOfStream:
            end_of_stream_ = true;
            return Status::ok();
        default:
            return Status::ok();  // heartbeat
    }
}

// One message outside a capture: control messages are applied, a frame's begin is kept
// for the next capture (its chunks stay unread), chunks of no frame are dropped.
Status LinkSession::pumpOneControl(std::uint64_t deadline_ns) noexcept {
    VTM_RETURN_IF_ERROR(nextMessage(deadline_ns));
    const Message& m = decoder_.message();
    if (m.header.type == MessageType::kFrameBegin) {
        const Status s = decodeFrameBegin(m.payload, pending_frame_);
        if (!s.isOk()) {
            decoder_.counters().add(LinkFault::kBadLength);
            return s;
        }
        has_pending_frame_ = true;
        return Status::ok();
    }
    if (m.header.type == MessageType::kFrameChunk) {
        ++decoder_.counters().orphan_chunks;
        return Status::ok();
    }
    return applyControl(m);
}

Status LinkSession::pumpControlUntilDescription(std::uint64_t deadline_ns) noexcept {
    // bound: nextMessage() returns kTimeout at the deadline.
    while (!have_description_ && !has_pending_frame_ && !end_of_stream_) {
        VTM_RETURN_IF_ERROR(pumpOneControl(deadline_ns));
    }
    return Status::ok();
}

Status LinkSession::pumpControlUntilPose(std::uint64_t timestamp_ns, std::uint64_t deadline_ns) noexcept {
    // bound: nextMessage() returns kTimeout at the deadline.
    while (!has_pending_frame_ && !end_of_stream_ &&
           (poses_.empty() || poses_.at(poses_.size() - 1U).timestamp_ns < timestamp_ns)) {
        VTM_RETURN_IF_ERROR(pumpOneControl(deadline_ns));
    }
    return Status::ok();
}

Status LinkSession::describe(CameraDescription& out) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "link: describe() before init()");
    }
    VTM_RETURN_IF_ERROR(pumpControlUntilDescription(deadlineNs()));
    if (!have_description_) {
        return Status(StatusCode::kNoData, "link: no camera description before the first frame or end of stream");
    }
    out = description_;
    return Status::ok();
}

}  // namespace vtm::hal::link
