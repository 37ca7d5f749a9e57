// LinkSession / LinkCamera / LinkOdometry over a scripted byte stream and a manual
// clock: frames and poses arrive intact, every fault reaches the caller as its Status
// and counter, the session recovers with the next frame, and the run path never
// allocates.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "hal/link/link_session.hpp"
#include "link_stream_builder.hpp"
#include "no_heap_guard.hpp"

namespace vtm::hal::link {
namespace {

using test::StreamBuilder;

// Hands out the script in pieces of at most piece_bytes; when it is exhausted, waits
// out the timeout on the manual clock (kTimeout), as a silent socket would.
class ScriptedStream final : public ByteStream {
public:
    ScriptedStream(ManualClock& clock, std::vector<std::uint8_t> bytes, std::size_t piece_bytes)
        : clock_(clock), bytes_(std::move(bytes)), piece_(piece_bytes) {}
    Status receive(std::uint8_t* buffer, std::size_t capacity, std::uint32_t timeout_ms,
                   std::size_t& received) override {
        received = 0U;
        if (pos_ >= bytes_.size() && closes_) {
            return Status(StatusCode::kNoData, "scripted: closed");
        }
        if (pos_ >= bytes_.size()) {
            clock_.advance(static_cast<std::uint64_t>(timeout_ms) * 1000000ULL);
            waited_ms_ += timeout_ms;
            return Status(StatusCode::kTimeout, "scripted: silent");
        }
        received = std::min({capacity, piece_, bytes_.size() - pos_});
        std::copy(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_),
                  bytes_.begin() + static_cast<std::ptrdiff_t>(pos_ + received), buffer);
        pos_ += received;
        clock_.advance(1000U);  // 1 us per read
        return Status::ok();
    }
    std::uint64_t waited_ms_ = 0U;
    bool closes_ = false;  // at the end of the script: the peer closed (kNoData), not silence

private:
    ManualClock& clock_;
    std::vector<std::uint8_t> bytes_;
    std::size_t piece_;
    std::size_t pos_ = 0U;
};

constexpr std::int32_t kW = 40;
constexpr std::int32_t kH = 30;

class SessionTest : public ::testing::Test {
protected:
    void start(const StreamBuilder& b, std::size_t piece = 4096U, std::uint32_t timeout_ms = 500U) {
        stream_ = std::make_unique<ScriptedStream>(clock_, b.bytes, piece);
        LinkSession::Config config;
        config.timeout_ms = timeout_ms;
        ASSERT_TRUE(session_->init(config, *stream_, clock_).isOk());
    }
    // Camera, then per frame: its pose, then the frame in chunks of 333 bytes.
    static StreamBuilder frames(std::uint32_t count) {
        StreamBuilder b;
        b.camera(test::testCamera(kW, kH, 8));
        for (std::uint32_t s = 1U; s <= count; ++s) {
            const FrameInfo info = test::testFrameInfo(s, kW, kH, 8);
            b.pose(test::testPose(info.timestamp_ns, 0.5 * s));
            b.frame(info, test::testPixels8(s, kW, kH), 333U);
        }
        return b;
    }

    ManualClock clock_;
    std::unique_ptr<ScriptedStream> stream_;
    std::unique_ptr<LinkSession> session_ = std::make_unique<LinkSession>();  // ~150 KiB
    LinkCamera camera_{*session_};
    LinkOdometry odometry_{*session_};
    std::vector<std::uint8_t> pixels_ = std::vector<std::uint8_t>(kW * kH);
    ImageView<std::uint8_t> out_{pixels_.data(), kW, kH};
};

TEST_F(SessionTest, FramesAndPosesArriveBitExact) {
    StreamBuilder b = frames(3U);
    b.endOfStream();
    start(b, 1000U);
    CameraDescription d;
    ASSERT_TRUE(camera_.describe(d).isOk());
    EXPECT_EQ(d.width_px, kW);
    EXPECT_EQ(d.model.fx_px, test::testCamera(kW, kH, 8).model.fx_px);
    for (std::uint32_t s = 1U; s <= 3U; ++s) {
        FrameInfo info;
        ASSERT_TRUE(camera_.capture(out_, info).isOk()) << s;
        const FrameInfo want = test::testFrameInfo(s, kW, kH, 8);
        EXPECT_EQ(info.sequence, s);
        EXPECT_EQ(info.timestamp_ns, want.timestamp_ns);
        EXPECT_EQ(info.exposure_us, want.exposure_us);
        EXPECT_EQ(pixels_, test::testPixels8(s, kW, kH)) << "frame " << s;
        PoseEstimate p;
        ASSERT_TRUE(odometry_.poseAt(info.timestamp_ns, p).isOk());
        EXPECT_EQ(p.position_m[0], 0.5 * s);
    }
    FrameInfo info;
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kNoData);
    EXPECT_TRUE(session_->endOfStream());
    EXPECT_EQ(session_->counters().frames_ok, 3U);
    EXPECT_EQ(session_->counters().totalFaults(), 0U);
}

TEST_F(SessionTest, PoseBetweenTwoReceivedPosesIsInterpolated) {
    start(frames(2U));
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    const FrameInfo f1 = test::testFrameInfo(1U, kW, kH, 8);
    const FrameInfo f2 = test::testFrameInfo(2U, kW, kH, 8);
    PoseEstimate p;
    ASSERT_TRUE(odometry_.poseAt((f1.timestamp_ns + f2.timestamp_ns) / 2U, p).isOk());
    EXPECT_DOUBLE_EQ(p.position_m[0], 0.75);  // halfway between 0.5 and 1.0
    EXPECT_DOUBLE_EQ(p.position_m[1], -2.5);
    EXPECT_NEAR(p.attitude_wxyz[0], 0.6, 1e-15);
    EXPECT_EQ(odometry_.poseAt(f1.timestamp_ns - 1U, p).code(), StatusCode::kNoData);
    EXPECT_EQ(odometry_.poseAt(f1.timestamp_ns - 1U, p).detail(), -1);
}

TEST_F(SessionTest, PosesTooFarApartAreNotInterpolated) {
    stream_ = std::make_unique<ScriptedStream>(clock_, frames(2U).bytes, 4096U);
    LinkSession::Config config;
    config.max_interpolation_gap_ns = 50000000U;  // 50 ms; the frames are 100 ms apart
    ASSERT_TRUE(session_->init(config, *stream_, clock_).isOk());
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    const FrameInfo f1 = test::testFrameInfo(1U, kW, kH, 8);
    PoseEstimate p;
    const Status s = odometry_.poseAt(f1.timestamp_ns + 1000U, p);
    EXPECT_EQ(s.code(), StatusCode::kNoData);
    EXPECT_EQ(s.detail(), 100000000);
    EXPECT_TRUE(odometry_.poseAt(f1.timestamp_ns, p).isOk());  // exact poses still answer
}

TEST_F(SessionTest, PoseAtReadsAheadUntilThePoseArrives) {
    start(frames(1U));
    PoseEstimate p;
    const FrameInfo f1 = test::testFrameInfo(1U, kW, kH, 8);
    // Newer than anything sent before the frame: reads up to the frame's begin, keeps it.
    EXPECT_EQ(odometry_.poseAt(f1.timestamp_ns + 1U, p).code(), StatusCode::kNoData);
    ASSERT_TRUE(odometry_.poseAt(f1.timestamp_ns, p).isOk());  // before any capture
    EXPECT_EQ(p.position_m[0], 0.5);
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());  // the frame read ahead is not lost
    EXPECT_EQ(pixels_, test::testPixels8(1U, kW, kH));
}

TEST_F(SessionTest, SixteenBitFrameArrivesBitExact) {
    StreamBuilder b;
    b.camera(test::testCamera(kW, kH, 12));
    const FrameInfo info = test::testFrameInfo(7U, kW, kH, 12);
    std::vector<std::uint16_t> want(kW * kH);
    std::vector<std::uint8_t> packed;
    for (std::size_t i = 0U; i < want.size(); ++i) {
        want[i] = static_cast<std::uint16_t>((i * 37U) % 4096U);
        packed.push_back(static_cast<std::uint8_t>(want[i] >> 8U));
        packed.push_back(static_cast<std::uint8_t>(want[i] & 0xFFU));
    }
    b.frame(info, packed, 600U);
    start(b);
    std::vector<std::uint16_t> got(kW * kH);
    FrameInfo out;
    EXPECT_EQ(camera_.capture(out_, out).code(), StatusCode::kUnsupported);
    ASSERT_TRUE(camera_.capture16(ImageView<std::uint16_t>(got.data(), kW, kH), out).isOk());
    EXPECT_EQ(got, want);
    EXPECT_EQ(out.bit_depth, 12U);
}

TEST_F(SessionTest, WrongOutputBufferIsRefusedWithoutConsumingAFrame) {
    start(frames(1U));
    std::vector<std::uint8_t> small(10U * 10U);
    FrameInfo info;
    EXPECT_EQ(camera_.capture(ImageView<std::uint8_t>(small.data(), 10, 10), info).code(), StatusCode::kSizeMismatch);
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 1U);
}

TEST_F(SessionTest, FrameOfTheWrongSizeIsRefusedAndTheNextOneArrives) {
    StreamBuilder b;
    b.camera(test::testCamera(kW, kH, 8));
    b.frame(test::testFrameInfo(1U, kW + 2, kH, 8), test::testPixels8(1U, kW + 2, kH), 500U);
    b.frame(test::testFrameInfo(2U, kW, kH, 8), test::testPixels8(2U, kW, kH), 500U);
    start(b);
    FrameInfo info;
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(session_->counters().count(LinkFault::kFrameSize), 1U);
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 2U);
    EXPECT_EQ(pixels_, test::testPixels8(2U, kW, kH));
}

TEST_F(SessionTest, MissingChunkIsACorruptFrameAndTheNextOneArrives) {
    const StreamBuilder b = frames(2U);
    // Drop the second chunk of frame 1 (message 4: camera, pose, begin, chunk, chunk...).
    std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[4].begin));
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[5].begin), b.bytes.end());
    StreamBuilder cut;
    cut.bytes = bytes;
    start(cut);
    FrameInfo info;
    const Status s = camera_.capture(out_, info);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_EQ(session_->counters().count(LinkFault::kFrameIncomplete), 1U);
    EXPECT_EQ(session_->counters().messages_lost, 1U);
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 2U);
    EXPECT_EQ(pixels_, test::testPixels8(2U, kW, kH));
}

TEST_F(SessionTest, CorruptChunkIsRejectedAndTheNextFrameArrives) {
    StreamBuilder b = frames(2U);
    b.bytes[b.messages[5].begin + 40U] ^= 0xFFU;  // a pixel byte of frame 1
    start(b, 77U);
    FrameInfo info;
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kCorruptData);
    EXPECT_EQ(session_->counters().count(LinkFault::kPayloadCrc), 1U);
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 2U);
    EXPECT_EQ(pixels_, test::testPixels8(2U, kW, kH));
    EXPECT_GT(session_->counters().orphan_chunks, 0U);  // the rest of frame 1, dropped
}

TEST_F(SessionTest, TruncatedFrameThenSilenceTimesOutWithinTheTimeout) {
    const StreamBuilder b = frames(1U);
    StreamBuilder cut;
    cut.bytes.assign(b.bytes.begin(), b.bytes.end() - 100);
    start(cut, 4096U, 250U);
    FrameInfo info;
    const std::uint64_t t0 = clock_.monotonicNs();
    const Status s = camera_.capture(out_, info);
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_EQ(session_->counters().count(LinkFault::kTimeout), 1U);
    const std::uint64_t waited_ns = clock_.monotonicNs() - t0;
    EXPECT_GE(waited_ns, 250U * 1000000ULL);
    EXPECT_LE(waited_ns, 251U * 1000000ULL);  // manual clock: no more than the timeout (+ reads)
}

TEST_F(SessionTest, InvalidPoseIsCountedAndReportedForItsTime) {
    StreamBuilder b;
    b.camera(test::testCamera(kW, kH, 8));
    PoseEstimate bad = test::testPose(5000U, 1.0);
    bad.position_m[2] = std::nan("");
    b.pose(test::testPose(4000U, 1.0));
    b.pose(bad);
    b.pose(test::testPose(3000U, 1.0));  // time going backwards
    b.frame(test::testFrameInfo(1U, kW, kH, 8), test::testPixels8(1U, kW, kH), 5000U);
    start(b);
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());  // pose problems do not fail the camera
    EXPECT_EQ(session_->counters().count(LinkFault::kBadPose), 2U);
    PoseEstimate p;
    EXPECT_EQ(odometry_.poseAt(3000U, p).code(), StatusCode::kOutOfOrder);
    ASSERT_TRUE(odometry_.poseAt(4000U, p).isOk());
}

TEST_F(SessionTest, ReplayedMessagesAreCountedAndDroppedWithoutLosingAFrame) {
    StreamBuilder b = frames(1U);
    // Frame 1's first chunk again after the frame (between frames), then frame 2 with its
    // begin and its second chunk each sent twice (inside the frame).
    const std::vector<std::uint8_t> chunk = b.messageBytes(3);
    b.bytes.insert(b.bytes.end(), chunk.begin(), chunk.end());
    const std::size_t first_of_frame2 = b.messages.size();
    b.frame(test::testFrameInfo(2U, kW, kH, 8), test::testPixels8(2U, kW, kH), 333U);
    const std::vector<std::uint8_t> begin2 = b.messageBytes(first_of_frame2);
    const std::vector<std::uint8_t> chunk2 = b.messageBytes(first_of_frame2 + 2U);
    std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[first_of_frame2 + 1U].begin));
    bytes.insert(bytes.end(), begin2.begin(), begin2.end());
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[first_of_frame2 + 1U].begin),
                 b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[first_of_frame2 + 3U].begin));
    bytes.insert(bytes.end(), chunk2.begin(), chunk2.end());
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[first_of_frame2 + 3U].begin), b.bytes.end());
    StreamBuilder replayed;
    replayed.bytes = bytes;
    start(replayed, 50U);
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 1U);
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 2U);
    EXPECT_EQ(pixels_, test::testPixels8(2U, kW, kH));
    EXPECT_EQ(session_->counters().count(LinkFault::kReplay), 3U);
    EXPECT_EQ(session_->counters().totalFaults(), 3U);
    EXPECT_EQ(session_->counters().frames_ok, 2U);
}

TEST_F(SessionTest, GarbageInsideAFrameCostsNoFrame) {
    const StreamBuilder b = frames(1U);
    std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[4].begin));
    for (int i = 0; i < 37; ++i) {
        bytes.push_back(static_cast<std::uint8_t>(i * 29 + 5));
    }
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[4].begin), b.bytes.end());
    StreamBuilder g;
    g.bytes = bytes;
    start(g, 64U);
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(pixels_, test::testPixels8(1U, kW, kH));
    EXPECT_EQ(session_->counters().count(LinkFault::kBadMagic), 1U);
    EXPECT_EQ(session_->counters().totalFaults(), 1U);
}

TEST_F(SessionTest, GarbageBetweenFramesIsSkippedWithOneFault) {
    const StreamBuilder b = frames(2U);
    std::vector<std::uint8_t> bytes(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[8].begin));
    for (int i = 0; i < 500; ++i) {
        bytes.push_back(static_cast<std::uint8_t>(i * 31));
    }
    bytes.insert(bytes.end(), b.bytes.begin() + static_cast<std::ptrdiff_t>(b.messages[8].begin), b.bytes.end());
    StreamBuilder g;
    g.bytes = bytes;
    start(g, 128U);
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    ASSERT_TRUE(camera_.capture(out_, info).isOk());  // the garbage damaged no message
    EXPECT_EQ(info.sequence, 2U);
    EXPECT_EQ(pixels_, test::testPixels8(2U, kW, kH));
    EXPECT_EQ(session_->counters().count(LinkFault::kBadMagic), 1U);
}

TEST_F(SessionTest, ReconnectCarriesOnWithTheNewStreamAndKeepsCountersAndPoses) {
    LinkSession::Config config;
    EXPECT_EQ(session_->reconnect(*std::make_unique<ScriptedStream>(clock_, std::vector<std::uint8_t>{}, 1U)).code(),
              StatusCode::kNotInitialized);
    // The first connection closes in the middle of frame 2's third chunk.
    const StreamBuilder first = frames(2U);
    ASSERT_GT(first.messages.size(), 10U);
    const std::size_t cut = first.messages[10].begin + 5U;
    auto old_stream = std::make_unique<ScriptedStream>(
        clock_, std::vector<std::uint8_t>(first.bytes.begin(), first.bytes.begin() + static_cast<std::ptrdiff_t>(cut)), 64U);
    old_stream->closes_ = true;
    ASSERT_TRUE(session_->init(config, *old_stream, clock_).isOk());
    FrameInfo info;
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 1U);
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kIoError);
    EXPECT_EQ(session_->counters().count(LinkFault::kStreamError), 1U);
    // The new stream numbers its messages from 1 again and starts with the description.
    StreamBuilder second;
    second.camera(test::testCamera(kW, kH, 8));
    const FrameInfo third = test::testFrameInfo(3U, kW, kH, 8);
    second.pose(test::testPose(third.timestamp_ns, 1.5));
    second.frame(third, test::testPixels8(3U, kW, kH), 333U);
    second.endOfStream();
    ScriptedStream new_stream(clock_, second.bytes, 100U);
    ASSERT_TRUE(session_->reconnect(new_stream).isOk());
    ASSERT_TRUE(camera_.capture(out_, info).isOk());
    EXPECT_EQ(info.sequence, 3U);
    EXPECT_EQ(pixels_, test::testPixels8(3U, kW, kH));
    PoseEstimate p;
    ASSERT_TRUE(odometry_.poseAt(test::testFrameInfo(1U, kW, kH, 8).timestamp_ns, p).isOk());  // kept
    EXPECT_EQ(p.position_m[0], 0.5);
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kNoData);
    const LinkCounters& c = session_->counters();
    EXPECT_EQ(c.reconnects, 1U);
    EXPECT_EQ(c.frames_ok, 2U);
    EXPECT_EQ(c.count(LinkFault::kReplay), 0U);  // sequence 1 again is a new stream, not a replay
    EXPECT_EQ(c.count(LinkFault::kStreamError), 1U);
}

TEST_F(SessionTest, CaptureAndPoseAtAllocateNothing) {
    StreamBuilder b = frames(4U);
    b.endOfStream();
    start(b, 999U);
    vtm::test::NoHeapScope guard;
    for (int i = 0; i < 4; ++i) {
        FrameInfo info;
        ASSERT_TRUE(camera_.capture(out_, info).isOk());
        PoseEstimate p;
        ASSERT_TRUE(odometry_.poseAt(info.timestamp_ns, p).isOk());
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
}

TEST_F(SessionTest, ConfigIsValidated) {
    StreamBuilder b;
    stream_ = std::make_unique<ScriptedStream>(clock_, b.bytes, 1U);
    LinkSession::Config config;
    config.timeout_ms = 0U;
    EXPECT_EQ(session_->init(config, *stream_, clock_).code(), StatusCode::kInvalidConfig);
    FrameInfo info;
    EXPECT_EQ(camera_.capture(out_, info).code(), StatusCode::kNotInitialized);
}

}  // namespace
}  // namespace vtm::hal::link
