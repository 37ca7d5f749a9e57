// LinkDecoder and the protocol codecs: valid streams round trip; every kind of damage is
// rejected with its Status and counter, and decoding resumes at the next valid message.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "vtm/core/crc32.hpp"
#include "hal/link/decoder.hpp"
#include "link_stream_builder.hpp"
#include "no_heap_guard.hpp"

namespace vtm::hal::link {
namespace {

using test::StreamBuilder;

struct Decoded {
    MessageType type;
    std::uint32_t sequence;
    std::vector<std::uint8_t> payload;
};

struct Result {
    std::vector<Decoded> messages;
    std::vector<StatusCode> faults;
};

// Feeds `bytes` in pieces of at most `piece` bytes and collects everything.
Result decodeAll(LinkDecoder& decoder, const std::vector<std::uint8_t>& bytes, std::size_t piece) {
    Result r;
    std::size_t pos = 0U;
    while (pos < bytes.size() || decoder.hasPending()) {
        const std::size_t n = std::min(piece, bytes.size() - pos);
        std::size_t off = 0U;
        do {
            std::size_t used = 0U;
            bool ready = false;
            const Status s = decoder.push(Span<const std::uint8_t>(bytes.data() + pos + off, n - off), used, ready);
            off += used;
            if (!s.isOk()) {
                r.faults.push_back(s.code());
            }
            if (ready) {
                const Message& m = decoder.message();
                r.messages.push_back({m.header.type, m.header.sequence,
                                      std::vector<std::uint8_t>(m.payload.begin(), m.payload.end())});
            }
        } while (off < n || decoder.hasPending());
        pos += n;
    }
    return r;
}

class DecoderTest : public ::testing::Test {
protected:
    std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(kMaxPayloadBytes);
    LinkDecoder decoder_{Span<std::uint8_t>(buffer_.data(), buffer_.size())};

    // A small stream of every message type; payloads as given to the builder.
    static StreamBuilder sampleStream() {
        StreamBuilder b;
        b.camera(test::testCamera(16, 8, 8));
        b.pose(test::testPose(1000U, 1.5));
        b.frame(test::testFrameInfo(1U, 16, 8, 8), test::testPixels8(1U, 16, 8), 50U);
        b.heartbeat(77U);
        b.endOfStream();
        return b;
    }
    static std::vector<std::uint8_t> payloadOf(const StreamBuilder& b, std::size_t i) {
        std::vector<std::uint8_t> m = b.messageBytes(i);
        return std::vector<std::uint8_t>(m.begin() + kHeaderBytes, m.end());
    }
};

TEST(Protocol, HeaderBytesAreBigEndianAsTheIcdSays) {
    Header h;
    h.type = MessageType::kPose;
    h.flags = 0x0102U;
    h.sequence = 0x0A0B0C0DU;
    h.payload_length = 352U;
    h.payload_crc32 = 0xDEADBEEFU;
    std::uint8_t out[kHeaderBytes];
    encodeHeader(h, out);
    const std::uint8_t expected[20] = {'V', 'T', 'M', 'L', 1, 2, 1, 2, 0x0A, 0x0B, 0x0C, 0x0D,
                                       0, 0, 0x01, 0x60, 0xDE, 0xAD, 0xBE, 0xEF};
    EXPECT_EQ(std::memcmp(out, expected, 20U), 0);
    const std::uint32_t crc = crc32(expected, 20U);
    EXPECT_EQ(out[20], crc >> 24U);
    EXPECT_EQ(out[23], crc & 0xFFU);
    // A real as its binary64 pattern, most significant byte first: 1.0 = 0x3FF0000000000000.
    std::uint8_t f[8];
    putF64(f, 1.0);
    EXPECT_EQ(f[0], 0x3FU);
    EXPECT_EQ(f[1], 0xF0U);
    EXPECT_EQ(f[7], 0x00U);
}

TEST(Protocol, PayloadCodecsRoundTripEveryField) {
    const CameraDescription cam = test::testCamera(1024, 768, 12);
    std::vector<std::uint8_t> p(kCameraDescriptionBytes);
    encodeCameraDescription(cam, p.data());
    CameraDescription back;
    ASSERT_TRUE(decodeCameraDescription(Span<const std::uint8_t>(p.data(), p.size()), back).isOk());
    EXPECT_EQ(std::memcmp(&back.model.fx_px, &cam.model.fx_px, 9 * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(back.model.c, cam.model.c, 18 * sizeof(double)), 0);
    EXPECT_EQ(back.width_px, 1024);
    EXPECT_EQ(back.height_px, 768);
    EXPECT_EQ(back.bit_depth, 12U);
    EXPECT_EQ(back.camera_id, 3U);
    EXPECT_EQ(back.model.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(back.model.width_px, 1024U);

    const PoseEstimate pose = test::testPose(123456789012345ULL, -3.25);
    std::vector<std::uint8_t> q(kPoseBytes);
    encodePose(pose, q.data());
    PoseEstimate pback;
    ASSERT_TRUE(decodePose(Span<const std::uint8_t>(q.data(), q.size()), pback).isOk());
    EXPECT_EQ(pback.timestamp_ns, pose.timestamp_ns);
    EXPECT_EQ(std::memcmp(pback.position_m, pose.position_m, sizeof(pose.position_m)), 0);
    EXPECT_EQ(std::memcmp(pback.attitude_wxyz, pose.attitude_wxyz, sizeof(pose.attitude_wxyz)), 0);
    EXPECT_EQ(std::memcmp(pback.covariance, pose.covariance, sizeof(pose.covariance)), 0);
}

TEST(Protocol, FrameBeginRefusesInconsistentOrOversizedFrames) {
    FrameBegin f;
    f.info = test::testFrameInfo(1U, 2048, 2048, 12);
    f.bytes_per_pixel = 2U;
    f.pixel_bytes = 2048U * 2048U * 2U;
    std::uint8_t p[kFrameBeginBytes];
    encodeFrameBegin(f, p);
    FrameBegin back;
    EXPECT_TRUE(decodeFrameBegin(Span<const std::uint8_t>(p, sizeof(p)), back).isOk());
    f.info.width_px = 4096;  // 4096 x 2048 x 2 bytes: beyond the frame limit
    f.pixel_bytes = 4096U * 2048U * 2U;
    encodeFrameBegin(f, p);
    EXPECT_EQ(decodeFrameBegin(Span<const std::uint8_t>(p, sizeof(p)), back).code(), StatusCode::kUnsupported);
    f.info.width_px = 100;
    f.pixel_bytes = 7U;  // not width * height * 2
    encodeFrameBegin(f, p);
    EXPECT_EQ(decodeFrameBegin(Span<const std::uint8_t>(p, sizeof(p)), back).code(), StatusCode::kCorruptData);
    f.info.bit_depth = 8U;  // 8 bits in 2 bytes per pixel
    encodeFrameBegin(f, p);
    EXPECT_EQ(decodeFrameBegin(Span<const std::uint8_t>(p, sizeof(p)), back).code(), StatusCode::kCorruptData);
}

TEST_F(DecoderTest, ValidStreamRoundTripsInOnePush) {
    const StreamBuilder b = sampleStream();
    const Result r = decodeAll(decoder_, b.bytes, b.bytes.size());
    EXPECT_TRUE(r.faults.empty());
    ASSERT_EQ(r.messages.size(), b.messages.size());
    for (std::size_t i = 0U; i < b.messages.size(); ++i) {
        EXPECT_EQ(r.messages[i].sequence, i + 1U);
        EXPECT_EQ(r.messages[i].payload, payloadOf(b, i)) << "message " << i;
    }
    EXPECT_EQ(r.messages.front().type, MessageType::kCameraDescription);
    EXPECT_EQ(r.messages.back().type, MessageType::kEndOfStream);
    EXPECT_EQ(decoder_.counters().messages_ok, b.messages.size());
    EXPECT_EQ(decoder_.counters().totalFaults(), 0U);
}

TEST_F(DecoderTest, SplitAtEveryByteBoundaryGivesTheSameMessages) {
    const StreamBuilder b = sampleStream();
    // Two pieces cut at every position, and one byte at a time.
    for (std::size_t cut = 0U; cut <= b.bytes.size(); ++cut) {
        decoder_.reset();
        Result r;
        for (const auto& part : {std::vector<std::uint8_t>(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(cut)),
                                 std::vector<std::uint8_t>(b.bytes.begin() + static_cast<std::ptrdiff_t>(cut), b.bytes.end())}) {
            const Result piece = decodeAll(decoder_, part, part.size() + 1U);
            r.messages.insert(r.messages.end(), piece.messages.begin(), piece.messages.end());
            r.faults.insert(r.faults.end(), piece.faults.begin(), piece.faults.end());
        }
        ASSERT_TRUE(r.faults.empty()) << "cut at " << cut;
        ASSERT_EQ(r.messages.size(), b.messages.size()) << "cut at " << cut;
        EXPECT_EQ(r.messages[2].payload, payloadOf(b, 2)) << "cut at " << cut;
    }
    decoder_.reset();
    const Result bytewise = decodeAll(decoder_, b.bytes, 1U);
    EXPECT_TRUE(bytewise.faults.empty());
    EXPECT_EQ(bytewise.messages.size(), b.messages.size());
}

TEST_F(DecoderTest, CorruptedByteAnywhereIsRejectedCountedAndTheNextMessageStillArrives) {
    StreamBuilder b;
    b.heartbeat(1U);
    b.pose(test::testPose(5000U, 2.0));  // the message that gets damaged
    b.heartbeat(3U);
    b.heartbeat(4U);
    const test::MessageSpan victim = b.messages[1];
    for (std::size_t at = victim.begin; at < victim.begin + victim.size; ++at) {
        std::vector<std::uint8_t> bytes = b.bytes;
        bytes[at] ^= 0x10U;
        decoder_.reset();
        decoder_.counters() = LinkCounters{};
        const Result r = decodeAll(decoder_, bytes, 97U);
        const std::size_t offset = at - victim.begin;
        ASSERT_EQ(r.faults.size(), 1U) << "byte " << offset;
        EXPECT_EQ(r.faults[0], StatusCode::kCorruptData) << "byte " << offset;
        // Messages 1, 3 and 4 arrive; the damaged one does not.
        ASSERT_EQ(r.messages.size(), 3U) << "byte " << offset;
        EXPECT_EQ(r.messages[0].sequence, 1U);
        EXPECT_EQ(r.messages[1].sequence, 3U);
        EXPECT_EQ(r.messages[2].sequence, 4U);
        const LinkCounters& c = decoder_.counters();
        const LinkFault expected = offset < 4U            ? LinkFault::kBadMagic
                                   : offset < kHeaderBytes ? LinkFault::kHeaderCrc
                                                           : LinkFault::kPayloadCrc;
        EXPECT_EQ(c.count(expected), 1U) << "byte " << offset;
        EXPECT_EQ(c.totalFaults(), 1U) << "byte " << offset;
        EXPECT_EQ(c.messages_lost, 1U) << "byte " << offset;  // the gap 1 -> 3
    }
}

TEST_F(DecoderTest, GarbageBeforeAValidMessageIsSkippedOnceAndCounted) {
    StreamBuilder b;
    b.heartbeat(1U);
    std::vector<std::uint8_t> bytes = {'V', 'T', 'M', 0x00, 'V', 'V', 'T', 'x', 0xFF, 'L', 'M'};
    const std::size_t garbage = bytes.size();
    bytes.insert(bytes.end(), b.bytes.begin(), b.bytes.end());
    const Result r = decodeAll(decoder_, bytes, 5U);
    ASSERT_EQ(r.faults.size(), 1U);
    EXPECT_EQ(r.faults[0], StatusCode::kCorruptData);
    ASSERT_EQ(r.messages.size(), 1U);
    EXPECT_EQ(r.messages[0].type, MessageType::kHeartbeat);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kBadMagic), 1U);
    EXPECT_EQ(decoder_.counters().bytes_skipped, garbage);
}

TEST_F(DecoderTest, HeaderStartingInsideARejectedHeaderIsFound) {
    // A damaged header whose bytes 5.. hold the start of the real next message.
    StreamBuilder b;
    b.heartbeat(1U);
    std::vector<std::uint8_t> bytes = {'V', 'T', 'M', 'L', 1};
    bytes.insert(bytes.end(), b.bytes.begin(), b.bytes.end());
    const Result r = decodeAll(decoder_, bytes, bytes.size());
    ASSERT_EQ(r.messages.size(), 1U);
    EXPECT_EQ(r.messages[0].sequence, 1U);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kHeaderCrc), 1U);
}

TEST_F(DecoderTest, TruncatedMessageLosesOnlyItselfThanksToTheRescan) {
    StreamBuilder b;
    b.heartbeat(1U);
    b.pose(test::testPose(10U, 1.0));  // cut after 100 of its 376 bytes
    b.heartbeat(3U);
    b.pose(test::testPose(20U, 2.0));
    b.heartbeat(5U);
    std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[1].begin + 100U));
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[2].begin), b.bytes.end());
    const Result r = decodeAll(decoder_, bytes, 64U);
    ASSERT_EQ(r.faults.size(), 1U);
    EXPECT_EQ(r.faults[0], StatusCode::kCorruptData);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kPayloadCrc), 1U);
    ASSERT_EQ(r.messages.size(), 4U);
    EXPECT_EQ(r.messages[1].sequence, 3U);
    EXPECT_EQ(r.messages[2].sequence, 4U);
    EXPECT_EQ(r.messages[2].payload, payloadOf(b, 3));
    EXPECT_EQ(r.messages[3].sequence, 5U);
}

TEST_F(DecoderTest, TruncatedMessageAtTheEndWaitsForMoreBytes) {
    StreamBuilder b;
    b.pose(test::testPose(10U, 1.0));
    const std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.end() - 1);
    const Result r = decodeAll(decoder_, bytes, bytes.size());
    EXPECT_TRUE(r.faults.empty());
    EXPECT_TRUE(r.messages.empty());
    EXPECT_TRUE(decoder_.midMessage());
}

TEST_F(DecoderTest, OversizedLengthIsRejectedWithoutReadingThePayload) {
    // A header with a valid CRC announcing 1 GB, then (no payload) a valid heartbeat.
    std::uint8_t header[kHeaderBytes];
    Header h;
    h.type = MessageType::kFrameChunk;
    h.sequence = 1U;
    h.payload_length = 1000000000U;
    encodeHeader(h, header);
    StreamBuilder b;
    b.next_sequence = 2U;
    b.heartbeat(1U);
    std::vector<std::uint8_t> bytes(header, header + kHeaderBytes);
    bytes.insert(bytes.end(), b.bytes.begin(), b.bytes.end());
    const Result r = decodeAll(decoder_, bytes, bytes.size());
    ASSERT_EQ(r.faults.size(), 1U);
    EXPECT_EQ(r.faults[0], StatusCode::kUnsupported);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kOversized), 1U);
    ASSERT_EQ(r.messages.size(), 1U);
    EXPECT_EQ(r.messages[0].sequence, 2U);
}

TEST_F(DecoderTest, ReplayedSequenceIsRefusedAsOutOfOrder) {
    StreamBuilder b;
    b.heartbeat(1U);
    b.heartbeat(2U);
    const std::vector<std::uint8_t> first = b.messageBytes(0);
    std::vector<std::uint8_t> bytes = b.bytes;
    bytes.insert(bytes.end(), first.begin(), first.end());  // message 1 again
    b.heartbeat(3U);
    const std::vector<std::uint8_t> third = b.messageBytes(2);
    bytes.insert(bytes.end(), third.begin(), third.end());
    const Result r = decodeAll(decoder_, bytes, 13U);
    ASSERT_EQ(r.faults.size(), 1U);
    EXPECT_EQ(r.faults[0], StatusCode::kOutOfOrder);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kReplay), 1U);
    ASSERT_EQ(r.messages.size(), 3U);
    EXPECT_EQ(r.messages[2].sequence, 3U);
}

TEST_F(DecoderTest, SequenceWrapsAroundAndGapsAreCounted) {
    StreamBuilder b;
    b.next_sequence = 0xFFFFFFFEU;
    b.heartbeat(1U);       // 0xFFFFFFFE
    b.heartbeat(2U);       // 0xFFFFFFFF
    b.heartbeat(3U);       // 0 (wrap: newer)
    b.next_sequence = 5U;  // 1..4 lost
    b.heartbeat(4U);
    const Result r = decodeAll(decoder_, b.bytes, b.bytes.size());
    EXPECT_TRUE(r.faults.empty());
    EXPECT_EQ(r.messages.size(), 4U);
    EXPECT_EQ(decoder_.counters().count(LinkFault::kSequenceGap), 1U);
    EXPECT_EQ(decoder_.counters().messages_lost, 4U);
}

TEST_F(DecoderTest, UnknownVersionTypeAndWrongLengthAreRefused) {
    StreamBuilder b;
    b.raw(static_cast<std::uint8_t>(MessageType::kHeartbeat), std::vector<std::uint8_t>(8U), 2U);  // version 2
    b.raw(99U, std::vector<std::uint8_t>(5U));                                                     // unknown type
    b.raw(static_cast<std::uint8_t>(MessageType::kPose), std::vector<std::uint8_t>(10U));          // pose of 10 bytes
    b.raw(static_cast<std::uint8_t>(MessageType::kFrameChunk), std::vector<std::uint8_t>(8U));     // chunk without data
    b.heartbeat(5U);
    const Result r = decodeAll(decoder_, b.bytes, 7U);
    ASSERT_EQ(r.faults.size(), 4U);
    EXPECT_EQ(r.faults[0], StatusCode::kUnsupported);
    EXPECT_EQ(r.faults[1], StatusCode::kCorruptData);
    EXPECT_EQ(r.faults[2], StatusCode::kCorruptData);
    EXPECT_EQ(r.faults[3], StatusCode::kCorruptData);
    const LinkCounters& c = decoder_.counters();
    EXPECT_EQ(c.count(LinkFault::kBadVersion), 1U);
    EXPECT_EQ(c.count(LinkFault::kBadType), 1U);
    EXPECT_EQ(c.count(LinkFault::kBadLength), 2U);
    ASSERT_EQ(r.messages.size(), 1U);
    EXPECT_EQ(r.messages[0].sequence, 5U);
}

TEST_F(DecoderTest, DecodingAllocatesNothing) {
    const StreamBuilder b = sampleStream();
    std::size_t count = 0U;
    {
        vtm::test::NoHeapScope guard;
        std::size_t pos = 0U;
        while (pos < b.bytes.size()) {
            std::size_t used = 0U;
            bool ready = false;
            const Status s = decoder_.push(Span<const std::uint8_t>(b.bytes.data() + pos, b.bytes.size() - pos), used, ready);
            EXPECT_TRUE(s.isOk());
            count += ready ? 1U : 0U;
            pos += used;
        }
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(count, b.messages.size());
}

}  // namespace
}  // namespace vtm::hal::link
