#include "file_bytes.hpp"

#include <cerrno>
#include <fcntl.h>
#include <unistd.h>

namespace vtm::hal::detail {
namespace {

// read() interrupted by a signal is retried this many times before it counts as a failure,
// so that a signal storm cannot hold init in an unbounded loop.
constexpr int kMaxInterruptedReads = 16;

// Closes the descriptor on every return path. A read-only descriptor has nothing to
// flush, so a close error changes nothing and is ignored.
class ReadOnlyFd {
public:
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg): POSIX declares open() variadic; no mode is passed
    explicit ReadOnlyFd(const char* path) noexcept : fd_(::open(path, O_RDONLY | O_CLOEXEC)) {}
    ~ReadOnlyFd() {
        if (fd_ >= 0) {
            (void)::close(fd_);
        }
    }
    ReadOnlyFd(const ReadOnlyFd&) = delete;
    ReadOnlyFd& operator=(const ReadOnlyFd&) = delete;
    [[nodiscard]] int get() const noexcept { return fd_; }

private:
    int fd_;
};

}  // namespace

ssize_t readSome(int fd, void* into, std::size_t bytes) noexcept {
    for (int attempt = 0; attempt < kMaxInterruptedReads; ++attempt) {
        const ssize_t n = ::read(fd, into, bytes);
        if (n >= 0 || errno != EINTR) {
            return n;
        }
    }
    return -1;
}

Status readWholeFile(const char* path, std::uint8_t* buffer, std::size_t capacity, std::size_t& size) noexcept {
    const ReadOnlyFd fd(path);
    if (fd.get() < 0) {
        return Status(StatusCode::kIoError, "frame: cannot open file", errno);
    }
    std::size_t filled = 0U;
    // Every pass reads at least one byte or ends the loop, so capacity + 1 passes bound it.
    for (std::size_t pass = 0U; pass <= capacity; ++pass) {
        if (filled == capacity) {
            // Full: one more byte tells a file of exactly `capacity` bytes from a larger one.
            std::uint8_t probe = 0U;
            const ssize_t extra = readSome(fd.get(), &probe, 1U);
            if (extra < 0) {
                return Status(StatusCode::kIoError, "frame: read failed", errno);
            }
            if (extra > 0) {
                return Status(StatusCode::kUnsupported, "frame: file larger than kMaxFrameFileBytes",
                              static_cast<std::int64_t>(capacity));
            }
            break;
        }
        const ssize_t n = readSome(fd.get(), buffer + filled, capacity - filled);
        if (n < 0) {
            return Status(StatusCode::kIoError, "frame: read failed", errno);
        }
        if (n == 0) {
            break;
        }
        filled += static_cast<std::size_t>(n);
    }
    size = filled;
    return Status::ok();
}

}  // namespace vtm::hal::detail
