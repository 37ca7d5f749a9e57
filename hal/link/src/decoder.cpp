#include "hal/link/decoder.hpp"

#include <algorithm>
#include <cstring>

#include "vtm/core/crc32.hpp"

namespace vtm::hal::link {
namespace {

StatusCode codeFor(LinkFault f) noexcept {
    switch (f) {
        case LinkFault::kBadVersion:
        case LinkFault::kOversized: return StatusCode::kUnsupported;
        case LinkFault::kReplay: return StatusCode::kOutOfOrder;
        case LinkFault::kFrameSize: return StatusCode::kSizeMismatch;
        case LinkFault::kTimeout: return StatusCode::kTimeout;
        case LinkFault::kStreamError: return StatusCode::kIoError;
        default: return StatusCode::kCorruptData;
    }
}

}  // namespace

const char* linkFaultName(LinkFault f) noexcept {
    static const char* const kNames[kLinkFaultCount] = {
        "bad_magic",   "header_crc",   "payload_crc", "bad_length",       "bad_type",
        "bad_version", "oversized",    "replay",      "sequence_gap",     "frame_size",
        "frame_incomplete", "bad_pose", "timeout",    "stream_error"};
    const auto i = static_cast<std::size_t>(f);
    return i < kLinkFaultCount ? kNames[i] : "unknown";
}

void LinkDecoder::reset() noexcept {
    state_ = State::kHeader;
    header_len_ = 0U;
    payload_len_ = 0U;
    skip_remaining_ = 0U;
    rescan_pos_ = 0U;
    rescan_end_ = 0U;
    resyncing_ = false;
    have_sequence_ = false;
    last_sequence_ = 0U;
    message_ = Message{};
}

Status LinkDecoder::fault(LinkFault which, const char* reason, std::int64_t detail) noexcept {
    counters_.add(which);
    last_fault_ = which;
    resyncing_ = true;
    return Status(codeFor(which), reason, detail);
}

bool LinkDecoder::hasInput(Span<const std::uint8_t> bytes, std::size_t consumed) const noexcept {
    return rescan_pos_ < rescan_end_ || consumed < bytes.size();
}

std::uint8_t LinkDecoder::nextByte(Span<const std::uint8_t> bytes, std::size_t& consumed) noexcept {
    if (rescan_pos_ < rescan_end_) {
        return payload_buffer_[rescan_pos_++];
    }
    return bytes[consumed++];
}

Status LinkDecoder::push(Span<const std::uint8_t> bytes, std::size_t& consumed, bool& message_ready) noexcept {
    consumed = 0U;
    message_ready = false;
    // Every pass consumes at least one byte of the rescan region or of `bytes` (or
    // completes a zero-length payload, which returns).
    // bound: payload_buffer_.size() + bytes.size() passes
    while (hasInput(bytes, consumed) || (state_ == State::kPayload && payload_len_ == header_fields_.payload_length)) {
        if (state_ == State::kPayload) {
            const std::size_t need = header_fields_.payload_length - payload_len_;
            if (need == 0U) {
                return finishPayload(message_ready);
            }
            std::uint8_t* dst = payload_buffer_.data() + payload_len_;
            std::size_t n = 0U;
            if (rescan_pos_ < rescan_end_) {
                n = std::min(need, rescan_end_ - rescan_pos_);
                std::memmove(dst, payload_buffer_.data() + rescan_pos_, n);  // source lies ahead of dst
                rescan_pos_ += n;
            } else {
                n = std::min(need, bytes.size() - consumed);
                std::memcpy(dst, bytes.data() + consumed, n);
                consumed += n;
            }
            payload_len_ += n;
        } else if (state_ == State::kSkipPayload) {
            const std::uint8_t dropped = nextByte(bytes, consumed);
            (void)dropped;
            ++counters_.bytes_skipped;
            --skip_remaining_;
            state_ = (skip_remaining_ == 0U) ? State::kHeader : State::kSkipPayload;
        } else {
            const Status s = feedHeaderByte(nextByte(bytes, consumed));
            if (!s.isOk()) {
                return s;
            }
        }
    }
    return Status::ok();
}

Status LinkDecoder::feedHeaderByte(std::uint8_t b) noexcept {
    if (header_len_ < sizeof(kMagic)) {
        if (b == kMagic[header_len_]) {
            header_[header_len_++] = b;
            return Status::ok();
        }
        // The magic's four bytes differ from each other, so a mismatch can only restart
        // the magic at this byte.
        counters_.bytes_skipped += header_len_ + ((b == kMagic[0]) ? 0U : 1U);
        Status s = Status::ok();
        if (!resyncing_) {
            s = fault(LinkFault::kBadMagic, "link: bytes that do not start a header (bad magic), skipped", b);
        }
        header_len_ = 0U;
        if (b == kMagic[0]) {
            header_[header_len_++] = b;
        }
        return s;
    }
    header_[header_len_++] = b;
    return (header_len_ == kHeaderBytes) ? checkHeader() : Status::ok();
}

void LinkDecoder::shiftHeaderToNextMagic() noexcept {
    // The next header may begin inside the rejected one: keep the bytes from the first
    // later position that matches (a prefix of) the magic.
    std::size_t start = 1U;
    for (; start < header_len_; ++start) {  // bound: kHeaderBytes
        bool match = true;
        for (std::size_t k = 0U; k < sizeof(kMagic) && start + k < header_len_; ++k) {
            match = match && header_[start + k] == kMagic[k];
        }
        if (match) {
            break;
        }
    }
    counters_.bytes_skipped += start;
    std::memmove(header_, header_ + start, header_len_ - start);
    header_len_ -= start;
}

Status LinkDecoder::checkHeader() noexcept {
    if (crc32(header_, kHeaderBytes - 4U) != getU32(header_ + kHeaderBytes - 4U)) {
        Status s = Status::ok();
        if (!resyncing_) {
            s = fault(LinkFault::kHeaderCrc, "link: header CRC mismatch", getU32(header_ + 8));
        }
        shiftHeaderToNextMagic();
        return s;
    }
    const Header h = decodeHeaderFields(header_);
    header_len_ = 0U;
    resyncing_ = false;
    if (h.version != kProtocolVersion) {
        counters_.bytes_skipped += kHeaderBytes;
        return fault(LinkFault::kBadVersion, "link: protocol version not supported (only 1)", h.version);
    }
    if (h.payload_length > payload_buffer_.size()) {
        // Not read: the receiver resynchronises on the next magic.
        counters_.bytes_skipped += kHeaderBytes;
        return fault(LinkFault::kOversized, "link: payload_length larger than the receive buffer",
                     static_cast<std::int64_t>(h.payload_length));
    }
    std::size_t need = 0U;
    bool exact = true;
    const bool known = payloadSizeFor(static_cast<std::uint8_t>(h.type), need, exact);
    const bool length_ok = known && (exact ? h.payload_length == need : h.payload_length >= need);
    if (!length_ok) {
        // The header is intact, so its payload can be stepped over exactly.
        counters_.bytes_skipped += kHeaderBytes;
        skip_remaining_ = h.payload_length;
        state_ = (skip_remaining_ > 0U) ? State::kSkipPayload : State::kHeader;
        const Status s = known ? fault(LinkFault::kBadLength, "link: payload_length invalid for the message type",
                                       static_cast<std::int64_t>(h.payload_length))
                               : fault(LinkFault::kBadType, "link: unknown message type",
                                       static_cast<std::int64_t>(h.type));
        resyncing_ = false;
        return s;
    }
    header_fields_ = h;
    payload_len_ = 0U;
    state_ = State::kPayload;
    return Status::ok();
}

void LinkDecoder::rescanPayload() noexcept {
    // Decode the rejected payload again, followed by what was still waiting to be
    // rescanned: payload [0, payload_len_) then [rescan_pos_, rescan_end_).
    const std::size_t waiting = rescan_end_ - rescan_pos_;
    if (waiting > 0U) {
        std::memmove(payload_buffer_.data() + payload_len_, payload_buffer_.data() + rescan_pos_, waiting);
    }
    rescan_pos_ = 0U;
    rescan_end_ = payload_len_ + waiting;
    payload_len_ = 0U;
    counters_.bytes_skipped += kHeaderBytes;
}

Status LinkDecoder::finishPayload(bool& message_ready) noexcept {
    state_ = State::kHeader;
    const std::size_t len = header_fields_.payload_length;
    const std::uint32_t crc = (len == 0U) ? 0U : crc32(payload_buffer_.data(), len);
    if (crc != header_fields_.payload_crc32) {
        const Status s = fault(LinkFault::kPayloadCrc, "link: payload CRC mismatch", header_fields_.sequence);
        rescanPayload();
        return s;
    }
    const std::uint32_t seq = header_fields_.sequence;
    if (have_sequence_) {
        const std::uint32_t ahead = seq - last_sequence_;  // modulo 2^32
        if (ahead == 0U || ahead >= 0x80000000U) {
            const Status s = fault(LinkFault::kReplay, "link: sequence not newer than the last message (replay)", seq);
            resyncing_ = false;
            return s;
        }
        if (ahead > 1U) {
            counters_.add(LinkFault::kSequenceGap);
            counters_.messages_lost += ahead - 1U;
        }
    }
    have_sequence_ = true;
    last_sequence_ = seq;
    message_.header = header_fields_;
    message_.payload = Span<const std::uint8_t>(payload_buffer_.data(), len);
    message_ready = true;
    ++counters_.messages_ok;
    return Status::ok();
}

}  // namespace vtm::hal::link
