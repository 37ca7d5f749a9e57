// Line-by-line reading of the driver's text files (frame manifest, pose log) through
// POSIX open/read into fixed buffers, plus the field parsers both formats share.
// Used at init only; nothing here allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/file/file_limits.hpp"
#include "vtm/core/status.hpp"
#include "vtm/core/text_number.hpp"

namespace vtm::hal::detail {

// The reason texts a TextFile reports, so that each format names itself ("manifest: ...",
// "pose log: ..."). Every member is a string literal.
struct TextFileReasons {
    const char* open_failed;     // kIoError, detail = errno
    const char* read_failed;     // kIoError, detail = errno
    const char* line_too_long;   // kUnsupported, detail = line number
    const char* too_many_lines;  // kUnsupported, detail = line number
    const char* nul_byte;        // kCorruptData, detail = line number
};

class TextFile {
public:
    explicit TextFile(const TextFileReasons& reasons) noexcept : reasons_(reasons) {}
    ~TextFile();
    TextFile(const TextFile&) = delete;
    TextFile& operator=(const TextFile&) = delete;

    [[nodiscard]] Status open(const char* path) noexcept;
    // Reads the next line (without its line end) into line(). kNoData at the end of the
    // file; the errors of TextFileReasons otherwise.
    [[nodiscard]] Status nextLine() noexcept;
    // The current line, NUL-terminated, writable (the tokenizer splits it in place).
    [[nodiscard]] char* line() noexcept { return line_; }
    // 1-based number of the current line.
    [[nodiscard]] std::int64_t lineNumber() const noexcept { return static_cast<std::int64_t>(line_number_); }

private:
    [[nodiscard]] Status refill() noexcept;

    static constexpr std::size_t kChunkBytes = 4096U;

    TextFileReasons reasons_;
    int fd_ = -1;
    bool eof_ = false;
    std::size_t chunk_len_ = 0U;
    std::size_t chunk_pos_ = 0U;
    std::size_t line_number_ = 0U;
    char chunk_[kChunkBytes] = {};
    char line_[file_limits::kMaxLineChars + 1U] = {};
};

// Whitespace-separated fields of one line, split in place (separators become NUL).
struct LineTokens {
    const char* token[file_limits::kMaxLineTokens] = {};
    std::size_t count = 0U;
    bool too_many = false;  // the line has more than kMaxLineTokens fields
};
[[nodiscard]] LineTokens splitLine(char* line) noexcept;

// True when the line holds no field or its first field starts with '#'.
[[nodiscard]] bool isBlankOrComment(const LineTokens& tokens) noexcept;

[[nodiscard]] bool textEquals(const char* a, const char* b) noexcept;

// Numbers: the one parser of flight code (vtm/core/text_number.hpp).
using ::vtm::text::parseReal;
using ::vtm::text::parseUnsigned;

// Length of a NUL-terminated string, or limit + 1 if it is longer than limit.
[[nodiscard]] std::size_t boundedLength(const char* text, std::size_t limit) noexcept;

}  // namespace vtm::hal::detail
