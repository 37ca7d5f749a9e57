// ByteStream: where the HIL link's bytes come from. SocketStream (socket_stream.hpp) is
// the real one; tests script their own.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/status.hpp"

namespace vtm::hal::link {

class ByteStream {
public:
    // Reads up to `capacity` bytes into buffer, waiting at most timeout_ms for the first
    // one; sets `received`. Ok: received >= 1. kTimeout: nothing arrived in time.
    // kNoData: the peer closed the stream. kIoError: the operating system refused
    // (detail = errno).
    [[nodiscard]] virtual Status receive(std::uint8_t* buffer, std::size_t capacity, std::uint32_t timeout_ms,
                                         std::size_t& received) = 0;

protected:
    // Not deletable through the interface (no heap, no virtual destructor needed).
    ByteStream() = default;
    ~ByteStream() = default;
    ByteStream(const ByteStream&) = default;
    ByteStream& operator=(const ByteStream&) = default;
    ByteStream(ByteStream&&) = default;
    ByteStream& operator=(ByteStream&&) = default;
};

}  // namespace vtm::hal::link
