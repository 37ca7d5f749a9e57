#include "assert_capture.hpp"

namespace vtm::test {
namespace {
std::int32_t g_count = 0;
AssertInfo g_last{"", 0, "", 0, 0};
void record(const AssertInfo& info) {
    ++g_count;
    g_last = info;
}
}  // namespace

AssertCapture::AssertCapture() noexcept : previous_(setAssertHook(&record)) {
    g_count = 0;
    g_last = AssertInfo{"", 0, "", 0, 0};
}
AssertCapture::~AssertCapture() { (void)setAssertHook(previous_); }
std::int32_t AssertCapture::count() const noexcept { return g_count; }
const AssertInfo& AssertCapture::last() const noexcept { return g_last; }

}  // namespace vtm::test
