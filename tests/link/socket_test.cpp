// The link over real sockets: an in-test server thread feeds LinkCamera over a Unix
// socket and over TCP loopback; a silent server makes capture() return kTimeout after
// (not before) the configured timeout. Runs natively and under qemu-user.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hal/link/link_session.hpp"
#include "hal/link/socket_stream.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "link_stream_builder.hpp"
#include "no_heap_guard.hpp"

namespace vtm::hal::link {
namespace {

using test::StreamBuilder;
constexpr std::int32_t kW = 64;
constexpr std::int32_t kH = 48;

StreamBuilder threeFrames() {
    StreamBuilder b;
    b.camera(test::testCamera(kW, kH, 8));
    for (std::uint32_t s = 1U; s <= 3U; ++s) {
        const FrameInfo info = test::testFrameInfo(s, kW, kH, 8);
        b.pose(test::testPose(info.timestamp_ns, s));
        b.frame(info, test::testPixels8(s, kW, kH), 1000U);
    }
    b.endOfStream();
    return b;
}

// Accepts one client on listen_fd, sends `bytes` in small writes, then waits for
// `hold_ms` before closing (a silent server when bytes is empty). The thread frees its
// memory only once `release` is set, so the client's no-heap check sees only its own calls.
void serveOnce(int listen_fd, const std::vector<std::uint8_t>* bytes_in, int hold_ms, const std::atomic<bool>* release) {
    const std::vector<std::uint8_t>& bytes = *bytes_in;
    const int fd = ::accept(listen_fd, nullptr, nullptr);
    if (fd < 0) {
        return;
    }
    std::size_t pos = 0U;
    while (pos < bytes.size()) {
        const std::size_t n = std::min<std::size_t>(777U, bytes.size() - pos);
        const ssize_t w = ::send(fd, bytes.data() + pos, n, MSG_NOSIGNAL);
        if (w <= 0) {
            break;
        }
        pos += static_cast<std::size_t>(w);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(hold_ms));
    ::close(fd);
    // bound: the test sets release after its last capture
    while (!release->load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

int listenUnix(const std::string& path) {
    ::unlink(path.c_str());
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", path.c_str());
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(fd, 1) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

int listenTcp(std::uint16_t& port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;  // any free port
    socklen_t len = sizeof(addr);
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(fd, 1) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
        ::close(fd);
        return -1;
    }
    port = ntohs(addr.sin_port);
    return fd;
}

std::string unixPath(const char* tag) {
    return "/tmp/vtm_link_test_" + std::to_string(::getpid()) + "_" + tag + ".sock";
}

class SocketTest : public ::testing::Test {
protected:
    void receiveThreeFrames() {
        LinkSession::Config config;
        config.timeout_ms = 5000U;
        ASSERT_TRUE(session_->init(config, stream_, clock_).isOk());
        std::vector<std::uint8_t> px(kW * kH);
        const ImageView<std::uint8_t> out(px.data(), kW, kH);
        for (std::uint32_t s = 1U; s <= 3U; ++s) {
            FrameInfo info;
            Status st;
            PoseEstimate pose;
            {
                vtm::test::NoHeapScope guard;
                st = camera_.capture(out, info);
                EXPECT_TRUE(odometry_.poseAt(info.timestamp_ns, pose).isOk());
                EXPECT_EQ(guard.heapCalls(), 0U);
            }
            ASSERT_TRUE(st.isOk()) << st.reason();
            EXPECT_EQ(info.sequence, s);
            EXPECT_EQ(px, test::testPixels8(s, kW, kH)) << "frame " << s;
            EXPECT_EQ(pose.position_m[0], static_cast<double>(s));
        }
        FrameInfo info;
        EXPECT_EQ(camera_.capture(out, info).code(), StatusCode::kNoData);
        EXPECT_EQ(session_->counters().totalFaults(), 0U);
    }

    std::atomic<bool> release_{false};
    MonotonicClock clock_;
    SocketStream stream_;
    std::unique_ptr<LinkSession> session_ = std::make_unique<LinkSession>();
    LinkCamera camera_{*session_};
    LinkOdometry odometry_{*session_};
};

TEST_F(SocketTest, FramesArriveOverAUnixSocket) {
    const std::string path = unixPath("frames");
    const int lfd = listenUnix(path);
    ASSERT_GE(lfd, 0);
    const std::vector<std::uint8_t> bytes = threeFrames().bytes;
    std::thread server(serveOnce, lfd, &bytes, 0, &release_);
    const Status c = stream_.connectUnix(path.c_str(), 5000U);
    ASSERT_TRUE(c.isOk()) << c.reason() << " " << c.detail();
    receiveThreeFrames();
    release_ = true;
    server.join();
    ::close(lfd);
    ::unlink(path.c_str());
}

TEST_F(SocketTest, FramesArriveOverTcpLoopback) {
    std::uint16_t port = 0U;
    const int lfd = listenTcp(port);
    ASSERT_GE(lfd, 0);
    const std::vector<std::uint8_t> bytes = threeFrames().bytes;
    std::thread server(serveOnce, lfd, &bytes, 0, &release_);
    const Status c = stream_.connectTcp("127.0.0.1", port, 5000U);
    ASSERT_TRUE(c.isOk()) << c.reason() << " " << c.detail();
    receiveThreeFrames();
    release_ = true;
    server.join();
    ::close(lfd);
}

TEST_F(SocketTest, SilentServerGivesTimeoutAfterTheConfiguredTime) {
    const std::string path = unixPath("silent");
    const int lfd = listenUnix(path);
    ASSERT_GE(lfd, 0);
    const std::vector<std::uint8_t> nothing;
    release_ = true;
    std::thread server(serveOnce, lfd, &nothing, 500, &release_);
    ASSERT_TRUE(stream_.connectUnix(path.c_str(), 5000U).isOk());
    LinkSession::Config config;
    config.timeout_ms = 300U;
    ASSERT_TRUE(session_->init(config, stream_, clock_).isOk());
    std::vector<std::uint8_t> px(kW * kH);
    FrameInfo info;
    const std::uint64_t t0 = clock_.monotonicNs();
    const Status s = camera_.capture(ImageView<std::uint8_t>(px.data(), kW, kH), info);
    const std::uint64_t took_ns = clock_.monotonicNs() - t0;
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_GE(took_ns, 300U * 1000000ULL);
    EXPECT_EQ(session_->counters().count(LinkFault::kTimeout), 1U);
    server.join();
    // The server closed without an end-of-stream message: a link error, not a hang.
    EXPECT_EQ(camera_.capture(ImageView<std::uint8_t>(px.data(), kW, kH), info).code(), StatusCode::kIoError);
    ::close(lfd);
    ::unlink(path.c_str());
}

TEST_F(SocketTest, ConnectToNobodyTimesOut) {
    const std::string path = unixPath("nobody");
    ::unlink(path.c_str());
    EXPECT_EQ(stream_.connectUnix(path.c_str(), 50U).code(), StatusCode::kTimeout);
    EXPECT_EQ(stream_.connectTcp("not an address", 1U, 50U).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vtm::hal::link
