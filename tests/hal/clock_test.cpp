#include <gtest/gtest.h>

#include "hal/clock.hpp"
#include "hal/posix/monotonic_clock.hpp"

namespace vtm::hal {
namespace {

TEST(MonotonicClock, NeverGoesBackwards) {
    const MonotonicClock clock;
    std::uint64_t previous = clock.monotonicNs();
    EXPECT_GT(previous, 0U);
    for (int i = 0; i < 1000; ++i) {
        const std::uint64_t now = clock.monotonicNs();
        EXPECT_GE(now, previous);
        previous = now;
    }
}

TEST(ManualClock, MovesOnlyWhenAdvanced) {
    ManualClock clock;
    EXPECT_EQ(clock.monotonicNs(), 0U);
    clock.advance(1500);
    EXPECT_EQ(clock.monotonicNs(), 1500U);
    const Clock& base = clock;
    EXPECT_EQ(base.monotonicNs(), 1500U);
}

}  // namespace
}  // namespace vtm::hal
