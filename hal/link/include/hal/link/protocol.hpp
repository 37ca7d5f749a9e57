// The HIL link protocol, version 1 (docs/icd-hil-link.md is the interface control
// document; this header is its code form, shared by the flight receiver and the ground
// simulator). Every multi-byte field is BIG-ENDIAN and is read and written byte by
// byte, so the same code runs on little- and big-endian targets. Reals are IEEE-754
// binary64, sent as their 64-bit pattern, big-endian.
//
// Message = 24-byte header + payload:
//   offset size field
//    0      4   magic           0x56 0x54 0x4D 0x4C ("VTML")
//    4      1   version         1
//    5      1   type            MessageType
//    6      2   flags           0 in version 1 (receivers ignore them)
//    8      4   sequence        +1 per message from the sender (modulo 2^32)
//   12      4   payload_length  bytes after the header, <= kMaxPayloadBytes
//   16      4   payload_crc32   CRC-32 of the payload (0x00000000 for an empty one)
//   20      4   header_crc32    CRC-32 of header bytes 0..19
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/camera.hpp"
#include "hal/odometry.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::link {

inline constexpr std::uint8_t kMagic[4] = {0x56U, 0x54U, 0x4DU, 0x4CU};  // "VTML"
inline constexpr std::uint8_t kProtocolVersion = 1U;
inline constexpr std::size_t kHeaderBytes = 24U;

enum class MessageType : std::uint8_t {
    kCameraDescription = 1,  // CameraDescription: once at the start (may be repeated)
    kPose = 2,               // PoseEstimate (T_site_from_vehicle): before the frame it belongs to
    kFrameBegin = 3,         // FrameInfo + pixel format of the frame whose chunks follow
    kFrameChunk = 4,         // frame sequence, byte offset, pixel bytes
    kHeartbeat = 5,          // sender time (ns): "still alive" between frames
    kEndOfStream = 6,        // nothing follows
};

// Payload sizes (fixed for every type except kFrameChunk).
inline constexpr std::size_t kCameraDescriptionBytes = 16U + 27U * 8U;  // 232
inline constexpr std::size_t kPoseBytes = 8U + 43U * 8U;                // 352
inline constexpr std::size_t kFrameBeginBytes = 32U;
inline constexpr std::size_t kFrameChunkPrefixBytes = 8U;  // frame sequence, byte offset
inline constexpr std::size_t kHeartbeatBytes = 8U;
inline constexpr std::size_t kEndOfStreamBytes = 0U;

// Frame limits: each side 1..4096 px, at most 2048 x 2048 x 2 bytes of pixels, sent in
// chunks of 1..kMaxChunkDataBytes pixel bytes (whole pixels), in offset order.
inline constexpr std::int32_t kMaxFrameSidePx = 4096;
inline constexpr std::uint32_t kMaxFramePixelBytes = 2048U * 2048U * 2U;
inline constexpr std::size_t kMaxChunkDataBytes = 65536U;
inline constexpr std::size_t kMaxPayloadBytes = kFrameChunkPrefixBytes + kMaxChunkDataBytes;

struct Header {
    std::uint8_t version = kProtocolVersion;
    MessageType type = MessageType::kHeartbeat;
    std::uint16_t flags = 0U;
    std::uint32_t sequence = 0U;
    std::uint32_t payload_length = 0U;
    std::uint32_t payload_crc32 = 0U;
};

// kFrameBegin payload.
struct FrameBegin {
    FrameInfo info{};                   // sequence, timestamp, exposure, camera, bit depth, size
    std::uint8_t bytes_per_pixel = 1U;  // 1 (bit_depth <= 8) or 2 (16-bit big-endian samples)
    std::uint32_t pixel_bytes = 0U;     // width_px * height_px * bytes_per_pixel
};

// kFrameChunk payload prefix; the pixel bytes follow it.
struct FrameChunk {
    std::uint32_t frame_sequence = 0U;  // FrameInfo::sequence of the frame
    std::uint32_t offset_bytes = 0U;    // where the data goes in the packed frame
    Span<const std::uint8_t> data{};
};

// Big-endian field access (byte by byte).
void putU16(std::uint8_t* out, std::uint16_t v) noexcept;
void putU32(std::uint8_t* out, std::uint32_t v) noexcept;
void putU64(std::uint8_t* out, std::uint64_t v) noexcept;
void putF64(std::uint8_t* out, double v) noexcept;
[[nodiscard]] std::uint16_t getU16(const std::uint8_t* in) noexcept;
[[nodiscard]] std::uint32_t getU32(const std::uint8_t* in) noexcept;
[[nodiscard]] std::uint64_t getU64(const std::uint8_t* in) noexcept;
[[nodiscard]] double getF64(const std::uint8_t* in) noexcept;

// Writes the 24 header bytes (magic, fields, header CRC) into out.
void encodeHeader(const Header& header, std::uint8_t* out) noexcept;
// Reads the fields of a header whose magic and header CRC were checked.
[[nodiscard]] Header decodeHeaderFields(const std::uint8_t* in) noexcept;

// Writes header + payload into out; returns the message size, or 0 when out is too
// small or the payload longer than kMaxPayloadBytes (payload_crc32 is computed here).
[[nodiscard]] std::size_t encodeMessage(MessageType type, std::uint32_t sequence,
                                        Span<const std::uint8_t> payload, Span<std::uint8_t> out) noexcept;

// Payload codecs. encode* write exactly the fixed payload size into out (which must
// hold it); decode* check the size and field ranges and return kCorruptData (bad size,
// kind, bit depth, pixel format) or kUnsupported (a frame beyond the limits above).
void encodeCameraDescription(const CameraDescription& camera, std::uint8_t* out) noexcept;
[[nodiscard]] Status decodeCameraDescription(Span<const std::uint8_t> payload, CameraDescription& out) noexcept;
void encodePose(const PoseEstimate& pose, std::uint8_t* out) noexcept;
[[nodiscard]] Status decodePose(Span<const std::uint8_t> payload, PoseEstimate& out) noexcept;
void encodeFrameBegin(const FrameBegin& frame, std::uint8_t* out) noexcept;
[[nodiscard]] Status decodeFrameBegin(Span<const std::uint8_t> payload, FrameBegin& out) noexcept;
void encodeFrameChunkPrefix(std::uint32_t frame_sequence, std::uint32_t offset_bytes, std::uint8_t* out) noexcept;
[[nodiscard]] Status decodeFrameChunk(Span<const std::uint8_t> payload, FrameChunk& out) noexcept;

// The payload size a type requires (kFrameChunk: its minimum, prefix + 1 byte); false for
// an unknown type. `exact` is false for kFrameChunk (variable length).
[[nodiscard]] bool payloadSizeFor(std::uint8_t type, std::size_t& size, bool& exact) noexcept;

}  // namespace vtm::hal::link
