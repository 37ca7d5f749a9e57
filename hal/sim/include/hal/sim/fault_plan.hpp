// FaultPlan: the faults a simulated driver injects on cue (docs/hal-sim.md has the table
// of what each one looks like to the consumer). Fixed capacity, plain data, no heap.
//
// Camera faults hit one frame: the frame of camera `camera_id` whose per-camera sequence
// number (FrameInfo::sequence, 0, 1, ...) is `sequence`. Odometry faults hit every
// poseAt() query time t with from_ns <= t < until_ns (until_ns = 0: no end).
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/status.hpp"

namespace vtm::hal {

// Explicit values: they appear in test reports and bit masks (1 << kind).
enum class FaultKind : std::uint8_t {
    kDroppedFrame = 1,             // camera: frame lost -> kNoData
    kTruncatedFrame = 2,           // camera: fewer rows arrive than the frame has -> kCorruptData
    kStuckColumns = 3,             // camera: columns stuck at stuck_value -> delivered, kOk
    kDeadColumns = 4,              // camera: columns read zero -> delivered, kOk
    kSaturation = 5,               // camera: every pixel times gain_factor, clipped to full scale -> kOk
    kBlackFrame = 6,               // camera: all pixels zero -> delivered, kOk
    kFrameTimestampBackwards = 7,  // camera: frame stamped backwards_ns before the previous one -> kOutOfOrder
    kOdometryJump = 8,             // odometry: position offset by offset_m -> delivered, kOk
    kPoseNaN = 9,                  // odometry: NaN in the position -> kCorruptData
    kPoseTimestampBackwards = 10,  // odometry: the source's pose samples in the window are stamped
                                   // backwards_ns earlier -> kOutOfOrder if that goes backwards
};

struct Fault {
    FaultKind kind = FaultKind::kDroppedFrame;
    // Camera faults.
    std::uint8_t camera_id = 0U;
    std::uint32_t sequence = 0U;
    std::int32_t first_column = 0;      // kStuckColumns, kDeadColumns: columns [first, first + count)
    std::int32_t column_count = 1;      //   clipped to the frame; count >= 1
    std::uint16_t stuck_value = 0U;     // kStuckColumns: the value they read (<= full scale)
    std::uint32_t gain_factor = 4U;     // kSaturation: integer gain >= 2
    std::int32_t delivered_rows = 0;    // kTruncatedFrame: rows that arrive, 0 <= rows < height
    // Both timestamp faults: how far back the stamp goes (> 0).
    std::uint64_t backwards_ns = 1U;
    // Odometry faults: query-time window.
    std::uint64_t from_ns = 0U;
    std::uint64_t until_ns = 0U;        // 0 = no end
    double offset_m[3] = {0.0, 0.0, 0.0};  // kOdometryJump, site frame

    [[nodiscard]] bool isCameraFault() const noexcept {
        return kind <= FaultKind::kFrameTimestampBackwards;
    }
    [[nodiscard]] bool activeAt(std::uint64_t t_ns) const noexcept {
        return t_ns >= from_ns && (until_ns == 0U || t_ns < until_ns);
    }
};

// Shorthands for the usual cases.
[[nodiscard]] Fault cameraFault(FaultKind kind, std::uint8_t camera_id, std::uint32_t sequence) noexcept;
[[nodiscard]] Fault odometryFault(FaultKind kind, std::uint64_t from_ns, std::uint64_t until_ns) noexcept;

constexpr std::size_t kMaxFaults = 32U;

class FaultPlan {
public:
    // Adds a fault after checking its parameters: kInvalidArgument naming the field
    // ("FaultPlan: gain_factor must be >= 2"), kUnsupported when kMaxFaults are planned.
    [[nodiscard]] Status add(const Fault& fault) noexcept;
    void clear() noexcept { count_ = 0U; }
    [[nodiscard]] std::size_t size() const noexcept { return count_; }

    // The first planned camera fault of `kind` for that frame, or nullptr.
    [[nodiscard]] const Fault* cameraFault(FaultKind kind, std::uint8_t camera_id,
                                           std::uint32_t sequence) const noexcept;
    // The first planned odometry fault of `kind` active at t_ns, or nullptr.
    [[nodiscard]] const Fault* odometryFault(FaultKind kind, std::uint64_t t_ns) const noexcept;

private:
    Fault faults_[kMaxFaults];
    std::size_t count_ = 0U;
};

}  // namespace vtm::hal
