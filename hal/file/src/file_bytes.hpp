// Whole-file reads for frame files: POSIX open/read/close, which (unlike stdio's fopen,
// which mallocs its FILE and buffer) never touch the heap, into a caller's fixed buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <sys/types.h>

#include "vtm/core/status.hpp"

namespace vtm::hal::detail {

// One read() with EINTR retried a bounded number of times (a signal storm cannot hold
// init in an unbounded loop): bytes read (0 at end of file) or -1 with errno set.
[[nodiscard]] ssize_t readSome(int fd, void* into, std::size_t bytes) noexcept;

// Reads the file at `path` into buffer[0, capacity) and sets `size` to its length.
// kIoError: "frame: cannot open file" / "frame: read failed" (detail = errno).
// kUnsupported: "frame: file larger than kMaxFrameFileBytes" (detail = capacity).
[[nodiscard]] Status readWholeFile(const char* path, std::uint8_t* buffer, std::size_t capacity,
                                   std::size_t& size) noexcept;

}  // namespace vtm::hal::detail
