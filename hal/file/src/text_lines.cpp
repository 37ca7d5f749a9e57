#include "text_lines.hpp"

#include <cerrno>
#include <fcntl.h>
#include <unistd.h>

#include "file_bytes.hpp"

namespace vtm::hal::detail {
namespace {

bool isFieldSeparator(char c) noexcept {
    // '\r' too: a manifest written on Windows ends its lines with "\r\n".
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

}  // namespace

TextFile::~TextFile() {
    if (fd_ >= 0) {
        // A read-only descriptor has nothing to flush: a close error changes nothing.
        (void)::close(fd_);
    }
}

Status TextFile::open(const char* path) noexcept {
    fd_ = ::open(path, O_RDONLY | O_CLOEXEC);  // NOLINT(cppcoreguidelines-pro-type-vararg): POSIX open(), no mode
    if (fd_ < 0) {
        return Status(StatusCode::kIoError, reasons_.open_failed, errno);
    }
    return Status::ok();
}

Status TextFile::refill() noexcept {
    const ssize_t n = readSome(fd_, chunk_, kChunkBytes);
    if (n < 0) {
        return Status(StatusCode::kIoError, reasons_.read_failed, errno);
    }
    chunk_len_ = static_cast<std::size_t>(n);
    chunk_pos_ = 0U;
    eof_ = (n == 0);
    return Status::ok();
}

Status TextFile::nextLine() noexcept {
    std::size_t length = 0U;
    bool any = false;
    // Each pass consumes one character or refills the chunk; a line longer than
    // kMaxLineChars ends the loop with an error, so the bound is two passes per character.
    for (std::size_t pass = 0U; pass < 2U * (file_limits::kMaxLineChars + 2U); ++pass) {
        if (chunk_pos_ == chunk_len_) {
            if (eof_) {
                break;
            }
            VTM_RETURN_IF_ERROR(refill());
            continue;
        }
        const char c = chunk_[chunk_pos_];
        ++chunk_pos_;
        any = true;
        if (c == '\n') {
            break;
        }
        if (c == '\0') {
            return Status(StatusCode::kCorruptData, reasons_.nul_byte, static_cast<std::int64_t>(line_number_ + 1U));
        }
        if (length == file_limits::kMaxLineChars) {
            return Status(StatusCode::kUnsupported, reasons_.line_too_long,
                          static_cast<std::int64_t>(line_number_ + 1U));
        }
        line_[length] = c;
        ++length;
    }
    if (!any) {
        return Status(StatusCode::kNoData, "text file: end of file");
    }
    if (line_number_ == file_limits::kMaxTextLines) {
        return Status(StatusCode::kUnsupported, reasons_.too_many_lines,
                      static_cast<std::int64_t>(line_number_ + 1U));
    }
    line_[length] = '\0';
    ++line_number_;
    return Status::ok();
}

LineTokens splitLine(char* line) noexcept {
    LineTokens tokens;
    std::size_t i = 0U;
    // The line is at most kMaxLineChars long and NUL-terminated (TextFile guarantees both).
    for (; i <= file_limits::kMaxLineChars && line[i] != '\0'; ++i) {
        const bool starts_field = !isFieldSeparator(line[i]) && (i == 0U || line[i - 1U] == '\0');
        if (isFieldSeparator(line[i])) {
            line[i] = '\0';
        } else if (starts_field) {
            if (tokens.count == file_limits::kMaxLineTokens) {
                tokens.too_many = true;
                break;
            }
            tokens.token[tokens.count] = &line[i];
            ++tokens.count;
        }
    }
    return tokens;
}

bool isBlankOrComment(const LineTokens& tokens) noexcept {
    return tokens.count == 0U || tokens.token[0][0] == '#';
}

bool textEquals(const char* a, const char* b) noexcept {
    for (std::size_t i = 0U; i <= file_limits::kMaxLineChars; ++i) {
        if (a[i] != b[i]) {
            return false;
        }
        if (a[i] == '\0') {
            return true;
        }
    }
    return false;
}

std::size_t boundedLength(const char* text, std::size_t limit) noexcept {
    for (std::size_t i = 0U; i <= limit; ++i) {
        if (text[i] == '\0') {
            return i;
        }
    }
    return limit + 1U;
}

}  // namespace vtm::hal::detail
