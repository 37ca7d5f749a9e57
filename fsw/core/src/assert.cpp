#include "vtm/core/assert.hpp"

#include <cstdlib>

namespace vtm {
namespace {

// Flight default: stop. Nothing is printed (flight code has no console); a debugger or
// the core dump shows the AssertInfo on the stack.
void haltOnAssert(const AssertInfo& /*info*/) { std::abort(); }

// The one mutable global of fsw/core: the hook is replaceable by design (tests install
// AssertCapture; a flight build may route to its fault-protection entry point).
AssertHook g_hook = &haltOnAssert;  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables)

}  // namespace

AssertHook setAssertHook(AssertHook hook) noexcept {
    const AssertHook previous = g_hook;
    g_hook = (hook != nullptr) ? hook : &haltOnAssert;
    return previous;
}

void assertFailed(const char* file, std::int32_t line, const char* expression, std::int64_t arg0,
                  std::int64_t arg1) noexcept {
    const AssertInfo info{file, line, expression, arg0, arg1};
    g_hook(info);
}

}  // namespace vtm
