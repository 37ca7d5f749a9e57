// The flight side of the HIL link: one LinkSession reads the simulator's byte stream
// (ByteStream: a socket, or a scripted stream in tests) and decodes it (LinkDecoder);
// LinkCamera and LinkOdometry are the hal::Camera and hal::Odometry views of it.
//
//   static vtm::hal::link::SocketStream stream;       // ~150 KiB session: static storage
//   static vtm::hal::link::LinkSession session;
//   static vtm::hal::link::LinkCamera camera{session};
//   static vtm::hal::link::LinkOdometry odometry{session};
//   stream.connectUnix("/tmp/vtm.sock", 5000);  session.init({}, stream, clock);
//
// Every call returns within Config::timeout_ms (kTimeout, counted). Malformed input is a
// Status plus a per-reason counter (counters(), LinkFault); the session then carries on
// with the next valid message. Poses arriving while capture() waits for a frame go into
// a ring of the last kPoseRingCapacity poses, which LinkOdometry::poseAt() answers from.
// One thread at a time; memory: members only (no heap, nothing at run time).
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/camera.hpp"
#include "hal/clock.hpp"
#include "hal/link/byte_stream.hpp"
#include "hal/link/decoder.hpp"
#include "hal/link/link_counters.hpp"
#include "hal/link/protocol.hpp"
#include "hal/odometry.hpp"
#include "vtm/core/ring_buffer.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::link {

namespace detail {
// The caller's frame buffer as the chunk copier sees it (8- or 16-bit samples).
struct FrameSink {
    std::uint8_t* px8 = nullptr;
    std::uint16_t* px16 = nullptr;
    std::int32_t width_px = 0;
    std::int32_t height_px = 0;
    std::int32_t stride_px = 0;
    std::uint32_t max_sample = 255U;  // largest value the camera's bit depth allows
};
// A frame being assembled from its chunks.
struct FrameAssembly {
    bool active = false;
    FrameBegin begin{};
    std::uint32_t received_bytes = 0U;
};
}  // namespace detail

class LinkSession {
public:
    static constexpr std::size_t kPoseRingCapacity = 64U;
    static constexpr std::size_t kReceiveBytes = 65536U;  // one recv() at most

    struct Config {
        // Longest a capture(), describe() or poseAt() call waits, milliseconds (1..600000).
        std::uint32_t timeout_ms = 2000U;
        // Two received poses further apart than this are not interpolated (kNoData, detail
        // = the gap): a gap in the stream is a gap in knowledge. 0: no limit.
        std::uint64_t max_interpolation_gap_ns = 0U;
        [[nodiscard]] Status validate() const noexcept;
    };

    LinkSession() noexcept : decoder_(Span<std::uint8_t>(payload_, sizeof(payload_))) {}

    // Validates the config and starts a session on `stream` (already connected), timing
    // with `clock`. Both must outlive the session. Forgets any earlier session's state.
    [[nodiscard]] Status init(const Config& config, ByteStream& stream, const Clock& clock) noexcept;

    // Carries on over a new connection after the old one failed or closed (kIoError): the
    // simulator starts a new stream there (sequence numbers from 1, its camera description
    // first). Bytes of the old connection not yet decoded, a frame in assembly and a frame
    // begin kept for the next capture are dropped (counted in bytes_skipped as far as they
    // were received); the counters, the camera description and the pose ring are kept (the
    // poses are the vehicle's history, not the connection's). Counted in reconnects.
    // kNotInitialized before init().
    [[nodiscard]] Status reconnect(ByteStream& stream) noexcept;

    [[nodiscard]] const LinkCounters& counters() const noexcept { return decoder_.counters(); }
    // True once the simulator's kEndOfStream arrived: captures then return kNoData.
    [[nodiscard]] bool endOfStream() const noexcept { return end_of_stream_; }

    // The camera description (waits for it up to the timeout). kNoData if the stream
    // ended, or a frame arrived, without one.
    [[nodiscard]] Status describe(CameraDescription& out) noexcept;
    // The next complete frame into sink (sized as the description); see LinkCamera.
    [[nodiscard]] Status captureFrame(const detail::FrameSink& sink, bool wide, FrameInfo& info) noexcept;
    // See LinkOdometry.
    [[nodiscard]] Status poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept;

private:
    [[nodiscard]] std::uint64_t deadlineNs() const noexcept;
    [[nodiscard]] Status nextMessage(std::uint64_t deadline_ns) noexcept;
    [[nodiscard]] Status applyControl(const Message& message) noexcept;
    [[nodiscard]] Status pumpControlUntilDescription(std::uint64_t deadline_ns) noexcept;
    [[nodiscard]] Status pumpControlUntilPose(std::uint64_t timestamp_ns, std::uint64_t deadline_ns) noexcept;
    [[nodiscard]] Status pumpOneControl(std::uint64_t deadline_ns) noexcept;
    [[nodiscard]] Status startFrame(const FrameBegin& begin, detail::FrameAssembly& frame) noexcept;
    [[nodiscard]] Status addChunk(const FrameChunk& chunk, const detail::FrameSink& sink,
                                  detail::FrameAssembly& frame) noexcept;
    [[nodiscard]] Status onFrameMessage(const Message& message, const detail::FrameSink& sink,
                                        detail::FrameAssembly& frame, bool& done) noexcept;
    [[nodiscard]] Status lookUpPose(std::uint64_t timestamp_ns, PoseEstimate& out) const noexcept;
    [[nodiscard]] Status fault(LinkFault which, StatusCode code, const char* reason, std::int64_t detail) noexcept;

    ByteStream* stream_ = nullptr;
    const Clock* clock_ = nullptr;
    Config config_{};
    bool initialized_ = false;
    bool end_of_stream_ = false;
    bool have_description_ = false;
    CameraDescription description_{};
    bool has_pending_frame_ = false;  // a kFrameBegin read outside capture, for the next capture
    FrameBegin pending_frame_{};
    RingBuffer<PoseEstimate, kPoseRingCapacity> poses_{};
    std::uint64_t rejected_pose_time_ns_ = 0U;  // the last pose refused, and why
    Status rejected_pose_status_{};
    std::uint8_t payload_[kMaxPayloadBytes] = {};
    std::uint8_t receive_[kReceiveBytes] = {};
    std::size_t receive_pos_ = 0U;
    std::size_t receive_len_ = 0U;
    LinkDecoder decoder_;
};

// hal::Camera over the link. Statically allocated, never deleted through hal::Camera.
class LinkCamera final : public Camera {
public:
    explicit LinkCamera(LinkSession& session) noexcept : session_(&session) {}

    // The simulator's camera description; waits for it up to the timeout.
    [[nodiscard]] Status describe(CameraDescription& out) const noexcept override;

    // Waits (up to the timeout) for the next complete frame and copies its pixels into
    // `out`, which must have the described size (else kSizeMismatch, nothing consumed).
    // 8-bit cameras only (else kUnsupported: use capture16). Poses that arrive
    // meanwhile go to the pose ring. Failures, each also counted (LinkFault):
    //   kTimeout; kCorruptData (bad CRC/length/type, frame cut short or a chunk
    //   missing); kUnsupported (unknown version,
    //   oversized); kSizeMismatch (frame size differs from the description); kNoData
    //   (end of stream); kIoError (connection lost). A frame in assembly when a fault
    //   occurs is abandoned; the next call carries on with the next frame. Faults that
    //   destroy no message are only counted: bytes outside any message (kBadMagic,
    //   skipped) and a message received again (kReplay, dropped) fail no call and cost
    //   no frame.
    [[nodiscard]] Status capture(const ImageView<std::uint8_t>& out, FrameInfo& info) noexcept override;
    // The same for cameras of bit_depth 9..16 (samples above 2^bit_depth - 1: kCorruptData).
    [[nodiscard]] Status capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) noexcept override;

private:
    LinkSession* session_;
};

// hal::Odometry over the link. Statically allocated, never deleted through hal::Odometry.
class LinkOdometry final : public Odometry {
public:
    explicit LinkOdometry(LinkSession& session) noexcept : session_(&session) {}

    // The pose at timestamp_ns from the ring of received poses: exact, or interpolated
    // between the two around it (position and covariance linearly, attitude by
    // normalised linear interpolation; not across more than max_interpolation_gap_ns).
    // If timestamp_ns is newer than every pose held,
    // reads control messages from the link (up to the timeout) until a newer pose or
    // the next frame arrives. kNoData: older than the ring (detail -1) or newer than
    // anything received (detail +1); kCorruptData / kOutOfOrder: the pose for exactly
    // this time was refused (validatePose, or its time went backwards); link errors
    // as LinkCamera::capture.
    [[nodiscard]] Status poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) noexcept override;

private:
    LinkSession* session_;
};

}  // namespace vtm::hal::link
