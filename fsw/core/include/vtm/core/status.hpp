// Status: the result of every operation whose failure comes from outside the program
// (input data, configuration, hardware). Programmer errors use VTM_ASSERT instead.
//
// A Status is a code, a reason and one integer detail. The reason is a string literal
// with static storage (never built at run time, never freed) that names the input and
// what is wrong with it, e.g. "window_px: must be odd, 3..31" with detail = the value.
// The class is [[nodiscard]]: ignoring a Status is a compile error under -Werror; a
// caller that really means to ignore one writes (void)call().
#pragma once

#include <cstdint>

#include "vtm/core/platform.hpp"

namespace vtm {

// Explicit values: they appear in telemetry (EventLog arguments) and must not move.
enum class StatusCode : std::uint8_t {
    kOk = 0,
    kInvalidArgument = 1,   // an argument is out of its documented range
    kInvalidConfig = 2,     // a Config field failed validate()
    kOutOfMemory = 3,       // the arena (sized from the config) cannot hold the request
    kSizeMismatch = 4,      // image / buffer dimensions disagree
    kNoData = 5,            // nothing to return (no frame, no pose, no valid pixel)
    kTimeout = 6,           // a device or link did not answer in time
    kCorruptData = 7,       // bytes that do not parse, bad checksum, NaN in a pose
    kNotInitialized = 8,    // run-path call before a successful init()
    kDegenerate = 9,        // geometry or texture does not allow an answer
    kUnsupported = 10,      // a valid request this implementation does not serve
    kIoError = 11,          // the operating system refused a file or socket operation
    kOutOfOrder = 12,       // timestamps or sequence numbers went backwards
};

// Short stable name of a code ("ok", "invalid_argument", ...), for reports.
[[nodiscard]] const char* statusCodeName(StatusCode code) noexcept;

class [[nodiscard]] Status {
public:
    constexpr Status() noexcept = default;
    constexpr Status(StatusCode code, const char* reason, std::int64_t detail = 0) noexcept
        : code_(code), reason_(reason != nullptr ? reason : ""), detail_(detail) {}

    [[nodiscard]] static constexpr Status ok() noexcept { return Status{}; }

    [[nodiscard]] constexpr bool isOk() const noexcept { return code_ == StatusCode::kOk; }
    [[nodiscard]] constexpr StatusCode code() const noexcept { return code_; }
    // Never null; "" for ok().
    [[nodiscard]] constexpr const char* reason() const noexcept { return reason_; }
    // The offending value (a size, an index, a field value); 0 when there is none.
    [[nodiscard]] constexpr std::int64_t detail() const noexcept { return detail_; }

private:
    StatusCode code_ = StatusCode::kOk;
    const char* reason_ = "";
    std::int64_t detail_ = 0;
};

}  // namespace vtm

// Returns from the enclosing function if expr yields a non-ok Status.
#define VTM_RETURN_IF_ERROR(expr)                  \
    do {                                           \
        const ::vtm::Status vtm_status_ = (expr);  \
        if (!vtm_status_.isOk()) {                 \
            return vtm_status_;                    \
        }                                          \
    } while (false)
