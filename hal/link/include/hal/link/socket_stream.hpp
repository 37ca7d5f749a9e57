// SocketStream: the HIL link's byte stream over a connected stream socket (loopback TCP
// or a Unix-domain socket), read with poll() timeouts. The flight side connects; the
// simulator (`vtm-sim serve`) listens. POSIX calls only: no heap, no name resolution
// (the TCP address is a dotted IPv4 literal), works under qemu-user.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/link/byte_stream.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::link {

class SocketStream final : public ByteStream {
public:
    SocketStream() noexcept = default;
    ~SocketStream();
    SocketStream(const SocketStream&) = delete;
    SocketStream& operator=(const SocketStream&) = delete;
    SocketStream(SocketStream&&) = delete;
    SocketStream& operator=(SocketStream&&) = delete;

    // Connects to ipv4 ("127.0.0.1") : port, retrying every 10 ms while the connection is
    // refused (the server may still be starting) until timeout_ms has passed.
    // kInvalidArgument (not a dotted IPv4 address, port 0), kTimeout, kIoError (errno).
    [[nodiscard]] Status connectTcp(const char* ipv4, std::uint16_t port, std::uint32_t timeout_ms) noexcept;
    // The same for a Unix-domain stream socket at `path` (at most 107 characters).
    [[nodiscard]] Status connectUnix(const char* path, std::uint32_t timeout_ms) noexcept;
    // Takes over an already connected socket (tests: one end of a socketpair()).
    void adopt(int fd) noexcept;
    void close() noexcept;
    [[nodiscard]] bool isOpen() const noexcept { return fd_ >= 0; }

    [[nodiscard]] Status receive(std::uint8_t* buffer, std::size_t capacity, std::uint32_t timeout_ms,
                                 std::size_t& received) noexcept override;

private:
    template <typename Address>
    [[nodiscard]] Status connectWithRetry(int family, const Address& address, std::uint32_t timeout_ms) noexcept;

    int fd_ = -1;
};

}  // namespace vtm::hal::link
