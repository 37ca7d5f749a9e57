// VTM_ASSERT: for broken invariants only (programmer errors), never for input data,
// configuration or hardware results — those are Status returns (docs/flight-rules.md).
//
// A failed assertion calls the installed hook with the file, line, expression text and
// up to two integer arguments. The default hook halts (std::abort). Tests install a
// hook that records the failure and returns; code after an assertion must therefore
// stay memory-safe when execution continues (return a neutral value, touch nothing).
// Assertions stay on in every build type: they are cheap and they are the last line of
// defence on a flight processor.
#pragma once

#include <cstdint>

#include "vtm/core/platform.hpp"

namespace vtm {

struct AssertInfo {
    const char* file;
    std::int32_t line;
    const char* expression;
    std::int64_t arg0;
    std::int64_t arg1;
};

using AssertHook = void (*)(const AssertInfo& info);

// Installs a hook; returns the previous one. nullptr restores the default (abort).
AssertHook setAssertHook(AssertHook hook) noexcept;

// Called by VTM_ASSERT; returns only if the installed hook returns.
void assertFailed(const char* file, std::int32_t line, const char* expression,
                  std::int64_t arg0 = 0, std::int64_t arg1 = 0) noexcept;

}  // namespace vtm

#define VTM_ASSERT(cond, ...)                                                            \
    ((cond) ? static_cast<void>(0)                                                       \
            : ::vtm::assertFailed(__FILE__, __LINE__, #cond, ##__VA_ARGS__))
