// LinkDecoder: bytes in, complete validated messages out. Pure (no I/O, no clock), so it
// is unit-tested and fuzzed without sockets. The payload lands in a caller-provided
// buffer (at least kMaxPayloadBytes for the whole protocol; a smaller buffer refuses
// longer payloads as oversized).
//
// Validation of each message, in this order (docs/icd-hil-link.md, "Receiver rules"):
//   magic (resynchronise: skip bytes until "VTML")      -> kBadMagic      kCorruptData
//   header CRC                                          -> kHeaderCrc     kCorruptData
//   version == 1                                        -> kBadVersion    kUnsupported
//   payload_length <= buffer (the payload is not read)  -> kOversized     kUnsupported
//   type known                                          -> kBadType       kCorruptData
//   payload_length valid for the type                   -> kBadLength     kCorruptData
//   payload CRC                                         -> kPayloadCrc    kCorruptData
//   sequence newer than the last accepted one           -> kReplay        kOutOfOrder
// A sequence that skips ahead is accepted and counted (kSequenceGap, messagesLost()).
// After a header failure the decoder rescans the header bytes after the magic; after a
// payload CRC failure it rescans the payload (a truncated message swallows the start of
// the next one). Bytes skipped while resynchronising after a fault belong to that fault
// and are not counted as a second one.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/link/link_counters.hpp"
#include "hal/link/protocol.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::link {

// A complete message; payload points into the decoder's buffer and is valid until the
// next push().
struct Message {
    Header header{};
    Span<const std::uint8_t> payload{};
};

class LinkDecoder {
public:
    explicit LinkDecoder(Span<std::uint8_t> payload_buffer) noexcept : payload_buffer_(payload_buffer) {}

    // Consumes bytes from `bytes` until one message is complete or one fault is found,
    // and sets `consumed` (may be less than bytes.size(): call again with the rest).
    // Ok + message_ready: message() holds the message. Ok + !message_ready: all bytes
    // were consumed and more are needed. Not ok: a fault (its counter was incremented);
    // decoding continues with the next push.
    [[nodiscard]] Status push(Span<const std::uint8_t> bytes, std::size_t& consumed, bool& message_ready) noexcept;

    [[nodiscard]] const Message& message() const noexcept { return message_; }
    [[nodiscard]] LinkCounters& counters() noexcept { return counters_; }
    [[nodiscard]] const LinkCounters& counters() const noexcept { return counters_; }

    // True while a message is partly received (a header or payload is incomplete).
    [[nodiscard]] bool midMessage() const noexcept { return header_len_ > 0U || state_ != State::kHeader; }
    // True when bytes of a rejected payload wait to be decoded again: call push() (with
    // an empty span if need be) before waiting for more input.
    [[nodiscard]] bool hasPending() const noexcept { return rescan_pos_ < rescan_end_; }

    // The fault behind the last Status that was not ok.
    [[nodiscard]] LinkFault lastFault() const noexcept { return last_fault_; }
    // True for the faults that destroy no message: bytes outside any message (kBadMagic)
    // and a message received again (kReplay). The session counts them and goes on.
    [[nodiscard]] static bool harmless(LinkFault f) noexcept { return f == LinkFault::kBadMagic || f == LinkFault::kReplay; }

    // Forgets any partial message and the sequence history (a new connection).
    void reset() noexcept;

private:
    enum class State : std::uint8_t { kHeader, kPayload, kSkipPayload };

    [[nodiscard]] std::uint8_t nextByte(Span<const std::uint8_t> bytes, std::size_t& consumed) noexcept;
    [[nodiscard]] bool hasInput(Span<const std::uint8_t> bytes, std::size_t consumed) const noexcept;
    [[nodiscard]] Status feedHeaderByte(std::uint8_t b) noexcept;
    [[nodiscard]] Status checkHeader() noexcept;
    [[nodiscard]] Status finishPayload(bool& message_ready) noexcept;
    [[nodiscard]] Status fault(LinkFault which, const char* reason, std::int64_t detail) noexcept;
    void shiftHeaderToNextMagic() noexcept;
    void rescanPayload() noexcept;

    Span<std::uint8_t> payload_buffer_;
    State state_ = State::kHeader;
    std::uint8_t header_[kHeaderBytes] = {};
    std::size_t header_len_ = 0U;
    Header header_fields_{};
    std::size_t payload_len_ = 0U;      // payload bytes received so far
    std::size_t skip_remaining_ = 0U;   // kSkipPayload: bytes still to drop
    // Bytes of payload_buffer_ [rescan_pos_, rescan_end_) to decode again before new input.
    std::size_t rescan_pos_ = 0U;
    std::size_t rescan_end_ = 0U;
    bool resyncing_ = false;        // after a fault, until the next good header
    bool have_sequence_ = false;
    LinkFault last_fault_ = LinkFault::kBadMagic;
    std::uint32_t last_sequence_ = 0U;
    Message message_{};
    LinkCounters counters_{};
};

}  // namespace vtm::hal::link
