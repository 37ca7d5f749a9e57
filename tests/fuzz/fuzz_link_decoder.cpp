// libFuzzer target (1): the HIL link receiver. The input is a byte stream: first the
// LinkDecoder alone, fed in pieces whose sizes come from the input itself (every split
// must behave), every complete message's payload through its codec; then a LinkSession
// with LinkCamera/LinkOdometry reading the same bytes from a scripted stream on a
// manual clock. Properties: no crash, no sanitizer report, no assertion; counters agree.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hal/link/decoder.hpp"
#include "hal/link/link_session.hpp"
#include "vtm/core/assert.hpp"

namespace {

using namespace vtm;
using namespace vtm::hal::link;

void abortOnAssert(const AssertInfo&) { std::abort(); }

class BytesStream final : public ByteStream {
public:
    BytesStream(hal::ManualClock& clock, const std::uint8_t* data, std::size_t size)
        : clock_(clock), data_(data), size_(size) {}
    Status receive(std::uint8_t* buffer, std::size_t capacity, std::uint32_t timeout_ms,
                   std::size_t& received) override {
        received = 0U;
        if (pos_ >= size_) {
            clock_.advance(static_cast<std::uint64_t>(timeout_ms) * 1000000ULL);
            return Status(StatusCode::kTimeout, "fuzz: silent");
        }
        const std::size_t piece = 1U + (data_[pos_] % 97U) * 13U;  // varied read sizes
        received = std::min({capacity, piece, size_ - pos_});
        for (std::size_t i = 0U; i < received; ++i) {
            buffer[i] = data_[pos_ + i];
        }
        pos_ += received;
        return Status::ok();
    }

private:
    hal::ManualClock& clock_;
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t pos_ = 0U;
};

void decodePayload(const Message& m) {
    switch (m.header.type) {
        case MessageType::kCameraDescription: {
            hal::CameraDescription d;
            (void)decodeCameraDescription(m.payload, d);
            break;
        }
        case MessageType::kPose: {
            hal::PoseEstimate p;
            if (decodePose(m.payload, p).isOk()) {
                (void)hal::validatePose(p);
            }
            break;
        }
        case MessageType::kFrameBegin: {
            FrameBegin f;
            (void)decodeFrameBegin(m.payload, f);
            break;
        }
        case MessageType::kFrameChunk: {
            FrameChunk c;
            (void)decodeFrameChunk(m.payload, c);
            break;
        }
        default: break;
    }
}

void fuzzDecoder(const std::uint8_t* data, std::size_t size) {
    static std::uint8_t payload[kMaxPayloadBytes];
    // A small buffer too (every third input): lengths between it and the protocol
    // maximum must be refused as oversized.
    const std::size_t capacity = (size > 0U && data[0] % 3U == 0U) ? 1024U : sizeof(payload);
    LinkDecoder decoder(Span<std::uint8_t>(payload, capacity));
    std::size_t pos = 0U;
    std::uint64_t messages = 0U;
    while (pos < size || decoder.hasPending()) {
        const std::size_t piece = std::min<std::size_t>(size - pos, 1U + (pos < size ? data[pos] : 0U));
        std::size_t off = 0U;
        do {
            std::size_t used = 0U;
            bool ready = false;
            (void)decoder.push(Span<const std::uint8_t>(data + pos + off, piece - off), used, ready);
            off += used;
            if (ready) {
                ++messages;
                decodePayload(decoder.message());
            }
        } while (off < piece || decoder.hasPending());
        pos += piece;
    }
    if (decoder.counters().messages_ok != messages) {
        std::abort();
    }
}

void fuzzSession(const std::uint8_t* data, std::size_t size) {
    static LinkSession session;
    static LinkCamera camera{session};
    static LinkOdometry odometry{session};
    static std::uint8_t px8[64 * 64];
    static std::uint16_t px16[64 * 64];
    hal::ManualClock clock;
    BytesStream stream(clock, data, size);
    LinkSession::Config config;
    config.timeout_ms = 10U;
    if (!session.init(config, stream, clock).isOk()) {
        std::abort();
    }
    hal::CameraDescription d;
    const bool described = camera.describe(d).isOk();
    const std::int32_t w = described ? std::min(d.width_px, 64) : 16;
    const std::int32_t h = described ? std::min(d.height_px, 64) : 16;
    for (int i = 0; i < 8; ++i) {
        hal::FrameInfo info;
        Status s = camera.capture(ImageView<std::uint8_t>(px8, w, h), info);
        if (s.code() == StatusCode::kUnsupported) {
            s = camera.capture16(ImageView<std::uint16_t>(px16, w, h), info);
        }
        hal::PoseEstimate pose;
        (void)odometry.poseAt(s.isOk() ? info.timestamp_ns : static_cast<std::uint64_t>(i) * 1000U, pose);
        if (s.code() == StatusCode::kTimeout || s.code() == StatusCode::kNoData || s.code() == StatusCode::kIoError) {
            break;
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)setAssertHook(abortOnAssert);
    fuzzDecoder(data, size);
    fuzzSession(data, size);
    return 0;
}
