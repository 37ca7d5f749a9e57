#include "hal/link/protocol.hpp"

#include <cstring>

#include "vtm/core/crc32.hpp"

namespace vtm::hal::link {

void putU16(std::uint8_t* out, std::uint16_t v) noexcept {
    out[0] = static_cast<std::uint8_t>(v >> 8U);
    out[1] = static_cast<std::uint8_t>(v);
}
void putU32(std::uint8_t* out, std::uint32_t v) noexcept {
    for (std::size_t i = 0U; i < 4U; ++i) {
        out[i] = static_cast<std::uint8_t>(v >> (24U - 8U * i));
    }
}
void putU64(std::uint8_t* out, std::uint64_t v) noexcept {
    for (std::size_t i = 0U; i < 8U; ++i) {
        out[i] = static_cast<std::uint8_t>(v >> (56U - 8U * i));
    }
}
void putF64(std::uint8_t* out, double v) noexcept {
    std::uint64_t bits = 0U;
    static_assert(sizeof(bits) == sizeof(v), "binary64 expected");
    std::memcpy(&bits, &v, sizeof(bits));
    putU64(out, bits);
}
std::uint16_t getU16(const std::uint8_t* in) noexcept {
    return static_cast<std::uint16_t>((static_cast<std::uint32_t>(in[0]) << 8U) | in[1]);
}
std::uint32_t getU32(const std::uint8_t* in) noexcept {
    std::uint32_t v = 0U;
    for (std::size_t i = 0U; i < 4U; ++i) {
        v = (v << 8U) | in[i];
    }
    return v;
}
std::uint64_t getU64(const std::uint8_t* in) noexcept {
    std::uint64_t v = 0U;
    for (std::size_t i = 0U; i < 8U; ++i) {
        v = (v << 8U) | in[i];
    }
    return v;
}
double getF64(const std::uint8_t* in) noexcept {
    const std::uint64_t bits = getU64(in);
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
}

void encodeHeader(const Header& header, std::uint8_t* out) noexcept {
    std::memcpy(out, kMagic, sizeof(kMagic));
    out[4] = header.version;
    out[5] = static_cast<std::uint8_t>(header.type);
    putU16(out + 6, header.flags);
    putU32(out + 8, header.sequence);
    putU32(out + 12, header.payload_length);
    putU32(out + 16, header.payload_crc32);
    putU32(out + 20, crc32(out, 20U));
}

Header decodeHeaderFields(const std::uint8_t* in) noexcept {
    Header h;
    h.version = in[4];
    h.type = static_cast<MessageType>(in[5]);
    h.flags = getU16(in + 6);
    h.sequence = getU32(in + 8);
    h.payload_length = getU32(in + 12);
    h.payload_crc32 = getU32(in + 16);
    return h;
}

std::size_t encodeMessage(MessageType type, std::uint32_t sequence, Span<const std::uint8_t> payload,
                          Span<std::uint8_t> out) noexcept {
    if (payload.size() > kMaxPayloadBytes || out.size() < kHeaderBytes + payload.size()) {
        return 0U;
    }
    Header h;
    h.type = type;
    h.sequence = sequence;
    h.payload_length = static_cast<std::uint32_t>(payload.size());
    h.payload_crc32 = payload.empty() ? 0U : crc32(payload.data(), payload.size());
    encodeHeader(h, out.data());
    if (!payload.empty()) {
        std::memcpy(out.data() + kHeaderBytes, payload.data(), payload.size());
    }
    return kHeaderBytes + payload.size();
}

namespace {

// The 27 reals of a camera model in wire order.
struct ModelReals {
    double* slot[27];
};
ModelReals modelReals(CameraModel& m) noexcept {
    ModelReals r{{&m.fx_px, &m.fy_px, &m.cx_px, &m.cy_px, &m.k1, &m.k2, &m.k3, &m.p1, &m.p2,
                  &m.c[0], &m.c[1], &m.c[2], &m.a[0], &m.a[1], &m.a[2], &m.h[0], &m.h[1], &m.h[2],
                  &m.v[0], &m.v[1], &m.v[2], &m.o[0], &m.o[1], &m.o[2], &m.r[0], &m.r[1], &m.r[2]}};
    return r;
}

std::int32_t toI32(std::uint32_t v) noexcept {
    // Two's complement reinterpretation without implementation-defined conversion.
    return (v <= 0x7FFFFFFFU) ? static_cast<std::int32_t>(v)
                              : -static_cast<std::int32_t>(~v) - 1;
}

}  // namespace

void encodeCameraDescription(const CameraDescription& camera, std::uint8_t* out) noexcept {
    out[0] = camera.camera_id;
    out[1] = camera.bit_depth;
    out[2] = static_cast<std::uint8_t>(camera.model.kind);
    out[3] = 0U;
    putU32(out + 4, static_cast<std::uint32_t>(camera.width_px));
    putU32(out + 8, static_cast<std::uint32_t>(camera.height_px));
    putU16(out + 12, camera.model.width_px);
    putU16(out + 14, camera.model.height_px);
    CameraModel copy = camera.model;
    const ModelReals reals = modelReals(copy);
    for (std::size_t i = 0U; i < 27U; ++i) {
        putF64(out + 16U + 8U * i, *reals.slot[i]);
    }
}

Status decodeCameraDescription(Span<const std::uint8_t> payload, CameraDescription& out) noexcept {
    if (payload.size() != kCameraDescriptionBytes) {
        return Status(StatusCode::kCorruptData, "link: camera description payload has the wrong length",
                      static_cast<std::int64_t>(payload.size()));
    }
    const std::uint8_t* in = payload.data();
    CameraDescription d;
    d.camera_id = in[0];
    d.bit_depth = in[1];
    if (d.bit_depth < 1U || d.bit_depth > 16U) {
        return Status(StatusCode::kCorruptData, "link: camera description bit_depth not in 1..16", d.bit_depth);
    }
    if (in[2] > static_cast<std::uint8_t>(CameraModelKind::kCahvor)) {
        return Status(StatusCode::kCorruptData, "link: camera description model kind unknown", in[2]);
    }
    d.model.kind = static_cast<CameraModelKind>(in[2]);
    d.width_px = toI32(getU32(in + 4));
    d.height_px = toI32(getU32(in + 8));
    if (d.width_px < 1 || d.width_px > kMaxFrameSidePx || d.height_px < 1 || d.height_px > kMaxFrameSidePx) {
        return Status(StatusCode::kUnsupported, "link: camera description size not in 1..4096 px",
                      (d.width_px < 1 || d.width_px > kMaxFrameSidePx) ? d.width_px : d.height_px);
    }
    d.model.width_px = getU16(in + 12);
    d.model.height_px = getU16(in + 14);
    const ModelReals reals = modelReals(d.model);
    for (std::size_t i = 0U; i < 27U; ++i) {
        *reals.slot[i] = getF64(in + 16U + 8U * i);
    }
    out = d;
    return Status::ok();
}

void encodePose(const PoseEstimate& pose, std::uint8_t* out) noexcept {
    putU64(out, pose.timestamp_ns);
    std::uint8_t* p = out + 8;
    for (const double v : pose.position_m) {
        putF64(p, v);
        p += 8;
    }
    for (const double v : pose.attitude_wxyz) {
        putF64(p, v);
        p += 8;
    }
    for (const double v : pose.covariance) {
        putF64(p, v);
        p += 8;
    }
}

Status decodePose(Span<const std::uint8_t> payload, PoseEstimate& out) noexcept {
    if (payload.size() != kPoseBytes) {
        return Status(StatusCode::kCorruptData, "link: pose payload has the wrong length",
                      static_cast<std::int64_t>(payload.size()));
    }
    const std::uint8_t* p = payload.data();
    out.timestamp_ns = getU64(p);
    p += 8;
    for (double& v : out.position_m) {
        v = getF64(p);
        p += 8;
    }
    for (double& v : out.attitude_wxyz) {
        v = getF64(p);
        p += 8;
    }
    for (double& v : out.covariance) {
        v = getF64(p);
        p += 8;
    }
    return Status::ok();
}

void encodeFrameBegin(const FrameBegin& frame, std::uint8_t* out) noexcept {
    putU32(out, frame.info.sequence);
    putU64(out + 4, frame.info.timestamp_ns);
    putU32(out + 12, frame.info.exposure_us);
    out[16] = frame.info.camera_id;
    out[17] = frame.info.bit_depth;
    out[18] = frame.bytes_per_pixel;
    out[19] = 0U;
    putU32(out + 20, static_cast<std::uint32_t>(frame.info.width_px));
    putU32(out + 24, static_cast<std::uint32_t>(frame.info.height_px));
    putU32(out + 28, frame.pixel_bytes);
}

Status decodeFrameBegin(Span<const std::uint8_t> payload, FrameBegin& out) noexcept {
    if (payload.size() != kFrameBeginBytes) {
        return Status(StatusCode::kCorruptData, "link: frame begin payload has the wrong length",
                      static_cast<std::int64_t>(payload.size()));
    }
    const std::uint8_t* in = payload.data();
    FrameBegin f;
    f.info.sequence = getU32(in);
    f.info.timestamp_ns = getU64(in + 4);
    f.info.exposure_us = getU32(in + 12);
    f.info.camera_id = in[16];
    f.info.bit_depth = in[17];
    f.bytes_per_pixel = in[18];
    f.info.width_px = toI32(getU32(in + 20));
    f.info.height_px = toI32(getU32(in + 24));
    f.pixel_bytes = getU32(in + 28);
    const std::uint32_t needed_bpp = (f.info.bit_depth > 8U) ? 2U : 1U;
    if (f.info.bit_depth < 1U || f.info.bit_depth > 16U || f.bytes_per_pixel != needed_bpp) {
        return Status(StatusCode::kCorruptData, "link: frame begin bit_depth/bytes_per_pixel inconsistent",
                      f.info.bit_depth);
    }
    if (f.info.width_px < 1 || f.info.width_px > kMaxFrameSidePx || f.info.height_px < 1 ||
        f.info.height_px > kMaxFrameSidePx) {
        return Status(StatusCode::kUnsupported, "link: frame begin size not in 1..4096 px", f.info.width_px);
    }
    const std::uint64_t bytes = static_cast<std::uint64_t>(f.info.width_px) *
                                static_cast<std::uint64_t>(f.info.height_px) * needed_bpp;
    if (bytes > kMaxFramePixelBytes) {
        return Status(StatusCode::kUnsupported, "link: frame larger than 2048 x 2048 x 2 bytes",
                      static_cast<std::int64_t>(bytes));
    }
    if (bytes != f.pixel_bytes) {
        return Status(StatusCode::kCorruptData, "link: frame begin pixel_bytes != width * height * bpp",
                      static_cast<std::int64_t>(f.pixel_bytes));
    }
    out = f;
    return Status::ok();
}

void encodeFrameChunkPrefix(std::uint32_t frame_sequence, std::uint32_t offset_bytes, std::uint8_t* out) noexcept {
    putU32(out, frame_sequence);
    putU32(out + 4, offset_bytes);
}

Status decodeFrameChunk(Span<const std::uint8_t> payload, FrameChunk& out) noexcept {
    if (payload.size() <= kFrameChunkPrefixBytes || payload.size() > kMaxPayloadBytes) {
        return Status(StatusCode::kCorruptData, "link: frame chunk payload has the wrong length",
                      static_cast<std::int64_t>(payload.size()));
    }
    out.frame_sequence = getU32(payload.data());
    out.offset_bytes = getU32(payload.data() + 4);
    out.data = payload.subspan(kFrameChunkPrefixBytes, payload.size() - kFrameChunkPrefixBytes);
    return Status::ok();
}

bool payloadSizeFor(std::uint8_t type, std::size_t& size, bool& exact) noexcept {
    exact = true;
    switch (static_cast<MessageType>(type)) {
        case MessageType::kCameraDescription: size = kCameraDescriptionBytes; return true;
        case MessageType::kPose: size = kPoseBytes; return true;
        case MessageType::kFrameBegin: size = kFrameBeginBytes; return true;
        case MessageType::kFrameChunk:
            size = kFrameChunkPrefixBytes + 1U;
            exact = false;
            return true;
        case MessageType::kHeartbeat: size = kHeartbeatBytes; return true;
        case MessageType::kEndOfStream: size = kEndOfStreamBytes; return true;
        default: return false;
    }
}

}  // namespace vtm::hal::link
