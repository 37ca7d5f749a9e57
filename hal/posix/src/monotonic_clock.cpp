#include "hal/posix/monotonic_clock.hpp"

#include <ctime>

namespace vtm::hal {

std::uint64_t MonotonicClock::monotonicNs() const {
    timespec ts{};
    // CLOCK_MONOTONIC cannot fail on Linux with a valid pointer; a zero time is the
    // neutral answer if it ever did.
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) {
        return 0U;
    }
    return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000U + static_cast<std::uint64_t>(ts.tv_nsec);
}

}  // namespace vtm::hal
