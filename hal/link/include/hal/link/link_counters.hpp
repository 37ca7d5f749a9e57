// Per-reason fault counters of the HIL link receiver, readable by the caller (telemetry,
// tests). Each fault has one Status code (docs/icd-hil-link.md, "Receiver rules").
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/status.hpp"

namespace vtm::hal::link {

enum class LinkFault : std::uint8_t {
    kBadMagic = 0,          // kCorruptData: bytes that do not start a header (one per garbage run)
    kHeaderCrc = 1,         // kCorruptData
    kPayloadCrc = 2,        // kCorruptData
    kBadLength = 3,         // kCorruptData: payload_length wrong for the type, or a bad payload field
    kBadType = 4,           // kCorruptData: unknown message type
    kBadVersion = 5,        // kUnsupported: protocol version other than 1
    kOversized = 6,         // kUnsupported: payload_length beyond the receiver's buffer
    kReplay = 7,            // kOutOfOrder: sequence not newer than the last accepted one
    kSequenceGap = 8,       // (accepted) sequence skipped ahead: messages were lost
    kFrameSize = 9,         // kSizeMismatch: frame size differs from the camera description
    kFrameIncomplete = 10,  // kCorruptData: chunk missing / out of place, frame cut short
    kBadPose = 11,          // pose rejected (validatePose or time going backwards); not returned by capture
    kTimeout = 12,          // kTimeout: nothing complete before the deadline
    kStreamError = 13,      // kIoError: the connection failed or closed without end of stream
};
inline constexpr std::size_t kLinkFaultCount = 14U;

struct LinkCounters {
    std::uint64_t faults[kLinkFaultCount] = {};
    std::uint64_t messages_ok = 0U;     // messages that passed every decoder check
    std::uint64_t messages_lost = 0U;   // sum of sequence gaps
    std::uint64_t bytes_skipped = 0U;   // bytes dropped while resynchronising
    std::uint64_t frames_ok = 0U;       // frames delivered by capture
    std::uint64_t poses_ok = 0U;        // poses stored in the ring
    std::uint64_t orphan_chunks = 0U;   // chunks of an abandoned frame, dropped
    std::uint64_t reconnects = 0U;      // LinkSession::reconnect() calls

    [[nodiscard]] std::uint64_t count(LinkFault f) const noexcept {
        return faults[static_cast<std::size_t>(f)];
    }
    void add(LinkFault f) noexcept { ++faults[static_cast<std::size_t>(f)]; }
    // All faults except kSequenceGap.
    [[nodiscard]] std::uint64_t totalFaults() const noexcept {
        std::uint64_t n = 0U;
        for (std::size_t i = 0U; i < kLinkFaultCount; ++i) {
            n += (i == static_cast<std::size_t>(LinkFault::kSequenceGap)) ? 0U : faults[i];
        }
        return n;
    }
};

// Short stable name of a fault ("bad_magic", ...), for reports.
[[nodiscard]] const char* linkFaultName(LinkFault f) noexcept;

}  // namespace vtm::hal::link
