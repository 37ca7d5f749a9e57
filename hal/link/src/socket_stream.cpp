#include "hal/link/socket_stream.hpp"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

namespace vtm::hal::link {
namespace {

std::uint64_t nowNs() noexcept {
    timespec ts{};
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

void sleepMs(long ms) noexcept {
    timespec ts{};
    ts.tv_sec = 0;
    ts.tv_nsec = ms * 1000000L;
    (void)nanosleep(&ts, nullptr);
}

}  // namespace

SocketStream::~SocketStream() { close(); }

void SocketStream::close() noexcept {
    if (fd_ >= 0) {
        (void)::close(fd_);
        fd_ = -1;
    }
}

void SocketStream::adopt(int fd) noexcept {
    close();
    fd_ = fd;
}

template <typename Address>
Status SocketStream::connectWithRetry(int family, const Address& address, std::uint32_t timeout_ms) noexcept {
    close();
    const std::uint64_t deadline = nowNs() + static_cast<std::uint64_t>(timeout_ms) * 1000000ULL;
    // bound: one attempt per 10 ms until the deadline (timeout_ms / 10 + 1 attempts).
    for (;;) {
        const int fd = ::socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (fd < 0) {
            return Status(StatusCode::kIoError, "link: socket() failed", errno);
        }
        // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
        if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0) {
            fd_ = fd;
            return Status::ok();
        }
        const int err = errno;
        (void)::close(fd);
        const bool retry = err == ECONNREFUSED || err == ENOENT || err == EAGAIN || err == EINTR;
        if (!retry) {
            return Status(StatusCode::kIoError, "link: connect() failed", err);
        }
        if (nowNs() >= deadline) {
            return Status(StatusCode::kTimeout, "link: no server accepted the connection in time",
                          static_cast<std::int64_t>(timeout_ms));
        }
        sleepMs(10);
    }
}

Status SocketStream::connectTcp(const char* ipv4, std::uint16_t port, std::uint32_t timeout_ms) noexcept {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    if (ipv4 == nullptr || port == 0U || ::inet_pton(AF_INET, ipv4, &addr.sin_addr) != 1) {
        return Status(StatusCode::kInvalidArgument, "link: TCP address must be a dotted IPv4 literal and port 1..65535",
                      port);
    }
    return connectWithRetry(AF_INET, addr, timeout_ms);
}

Status SocketStream::connectUnix(const char* path, std::uint32_t timeout_ms) noexcept {
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    const std::size_t len = (path == nullptr) ? 0U : ::strnlen(path, sizeof(addr.sun_path));
    if (len == 0U || len >= sizeof(addr.sun_path)) {
        return Status(StatusCode::kInvalidArgument, "link: Unix socket path must have 1..107 characters",
                      static_cast<std::int64_t>(len));
    }
    std::memcpy(addr.sun_path, path, len);
    return connectWithRetry(AF_UNIX, addr, timeout_ms);
}

Status SocketStream::receive(std::uint8_t* buffer, std::size_t capacity, std::uint32_t timeout_ms,
                             std::size_t& received) noexcept {
    received = 0U;
    if (fd_ < 0) {
        return Status(StatusCode::kNotInitialized, "link: socket not connected");
    }
    pollfd p{};
    p.fd = fd_;
    p.events = POLLIN;
    const int timeout = (timeout_ms > 0x7FFFFFFFU) ? 0x7FFFFFFF : static_cast<int>(timeout_ms);
    const int ready = ::poll(&p, 1U, timeout);
    if (ready < 0) {
        return (errno == EINTR) ? Status(StatusCode::kTimeout, "link: poll() interrupted")
                                : Status(StatusCode::kIoError, "link: poll() failed", errno);
    }
    if (ready == 0) {
        return Status(StatusCode::kTimeout, "link: no bytes before the timeout", static_cast<std::int64_t>(timeout_ms));
    }
    const ssize_t n = ::recv(fd_, buffer, capacity, 0);
    if (n < 0) {
        const int err = errno;
        return (err == EINTR || err == EAGAIN) ? Status(StatusCode::kTimeout, "link: recv() interrupted")
                                               : Status(StatusCode::kIoError, "link: recv() failed", err);
    }
    if (n == 0) {
        return Status(StatusCode::kNoData, "link: peer closed the connection");
    }
    received = static_cast<std::size_t>(n);
    return Status::ok();
}

}  // namespace vtm::hal::link
