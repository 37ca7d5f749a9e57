// Test-side encoder of HIL link streams (ground code: std::vector is fine here). Builds
// the byte stream a simulator would send, message by message, so tests can cut, corrupt
// and replay it. Uses hal/link/protocol.hpp for the field layout; the expected values
// the tests compare against are the inputs given here, never decoder output.
#pragma once

#include <cstdint>
#include <vector>

#include "vtm/core/crc32.hpp"
#include "hal/link/protocol.hpp"

namespace vtm::hal::link::test {

struct MessageSpan {
    std::size_t begin = 0U;  // offset of the header in the stream
    std::size_t size = 0U;   // header + payload
};

class StreamBuilder {
public:
    std::vector<std::uint8_t> bytes;
    std::vector<MessageSpan> messages;
    std::uint32_t next_sequence = 1U;

    // Any type/payload; returns the message index.
    std::size_t raw(std::uint8_t type, const std::vector<std::uint8_t>& payload, std::uint8_t version = 1U) {
        Header h;
        h.version = version;
        h.type = static_cast<MessageType>(type);
        h.sequence = next_sequence++;
        h.payload_length = static_cast<std::uint32_t>(payload.size());
        h.payload_crc32 = payload.empty() ? 0U : crc32(payload.data(), payload.size());
        std::uint8_t header[kHeaderBytes];
        encodeHeader(h, header);
        MessageSpan span{bytes.size(), kHeaderBytes + payload.size()};
        bytes.insert(bytes.end(), header, header + kHeaderBytes);
        bytes.insert(bytes.end(), payload.begin(), payload.end());
        messages.push_back(span);
        return messages.size() - 1U;
    }
    std::size_t camera(const CameraDescription& d) {
        std::vector<std::uint8_t> p(kCameraDescriptionBytes);
        encodeCameraDescription(d, p.data());
        return raw(static_cast<std::uint8_t>(MessageType::kCameraDescription), p);
    }
    std::size_t pose(const PoseEstimate& pose) {
        std::vector<std::uint8_t> p(kPoseBytes);
        encodePose(pose, p.data());
        return raw(static_cast<std::uint8_t>(MessageType::kPose), p);
    }
    std::size_t heartbeat(std::uint64_t t_ns) {
        std::vector<std::uint8_t> p(kHeartbeatBytes);
        putU64(p.data(), t_ns);
        return raw(static_cast<std::uint8_t>(MessageType::kHeartbeat), p);
    }
    std::size_t endOfStream() { return raw(static_cast<std::uint8_t>(MessageType::kEndOfStream), {}); }
    std::size_t frameBegin(const FrameInfo& info) {
        FrameBegin f;
        f.info = info;
        f.bytes_per_pixel = info.bit_depth > 8U ? 2U : 1U;
        f.pixel_bytes = static_cast<std::uint32_t>(info.width_px * info.height_px) * f.bytes_per_pixel;
        std::vector<std::uint8_t> p(kFrameBeginBytes);
        encodeFrameBegin(f, p.data());
        return raw(static_cast<std::uint8_t>(MessageType::kFrameBegin), p);
    }
    std::size_t chunk(std::uint32_t frame_sequence, std::uint32_t offset, const std::uint8_t* data, std::size_t n) {
        std::vector<std::uint8_t> p(kFrameChunkPrefixBytes + n);
        encodeFrameChunkPrefix(frame_sequence, offset, p.data());
        std::copy(data, data + n, p.begin() + static_cast<std::ptrdiff_t>(kFrameChunkPrefixBytes));
        return raw(static_cast<std::uint8_t>(MessageType::kFrameChunk), p);
    }
    // Frame begin + chunks of at most chunk_bytes (pixels already packed: 1 byte, or
    // 2 bytes big-endian per pixel). Returns the index of the first chunk.
    std::size_t frame(const FrameInfo& info, const std::vector<std::uint8_t>& packed, std::size_t chunk_bytes) {
        frameBegin(info);
        const std::size_t first = messages.size();
        for (std::size_t off = 0U; off < packed.size(); off += chunk_bytes) {
            const std::size_t n = std::min(chunk_bytes, packed.size() - off);
            chunk(info.sequence, static_cast<std::uint32_t>(off), packed.data() + off, n);
        }
        return first;
    }
    // The bytes of one message.
    [[nodiscard]] std::vector<std::uint8_t> messageBytes(std::size_t i) const {
        const MessageSpan s = messages.at(i);
        return {bytes.begin() + static_cast<std::ptrdiff_t>(s.begin),
                bytes.begin() + static_cast<std::ptrdiff_t>(s.begin + s.size)};
    }
};

// Deterministic test content.
inline CameraDescription testCamera(std::int32_t w, std::int32_t h, std::uint8_t bit_depth) {
    CameraDescription d;
    d.camera_id = 3U;
    d.bit_depth = bit_depth;
    d.width_px = w;
    d.height_px = h;
    d.model.kind = CameraModelKind::kPinholeBrown;
    d.model.width_px = static_cast<std::uint16_t>(w);
    d.model.height_px = static_cast<std::uint16_t>(h);
    d.model.fx_px = 100.25;
    d.model.fy_px = 101.5;
    d.model.cx_px = (w - 1) / 2.0;
    d.model.cy_px = (h - 1) / 2.0;
    d.model.k1 = -0.125;
    d.model.p2 = 1e-3;
    d.model.r[2] = -7.0;
    return d;
}

inline PoseEstimate testPose(std::uint64_t t_ns, double x_m) {
    PoseEstimate p;
    p.timestamp_ns = t_ns;
    p.position_m[0] = x_m;
    p.position_m[1] = -2.5;
    p.position_m[2] = 0.75;
    p.attitude_wxyz[0] = 0.6;
    p.attitude_wxyz[3] = 0.8;
    for (int i = 0; i < 6; ++i) {
        p.covariance[i * 7] = 1e-4 * (i + 1);
    }
    return p;
}

inline FrameInfo testFrameInfo(std::uint32_t seq, std::int32_t w, std::int32_t h, std::uint8_t bit_depth) {
    FrameInfo f;
    f.sequence = seq;
    f.timestamp_ns = 1000000000ULL + seq * 100000000ULL;
    f.exposure_us = 2500U + seq;
    f.camera_id = 3U;
    f.bit_depth = bit_depth;
    f.width_px = w;
    f.height_px = h;
    return f;
}

// Packed 8-bit pixels, a pattern that differs per frame.
inline std::vector<std::uint8_t> testPixels8(std::uint32_t seq, std::int32_t w, std::int32_t h) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h));
    for (std::size_t i = 0U; i < px.size(); ++i) {
        px[i] = static_cast<std::uint8_t>((i * 7U + seq * 13U + (i >> 8U)) & 0xFFU);
    }
    return px;
}

}  // namespace vtm::hal::link::test
