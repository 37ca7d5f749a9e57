// hal::Clock on POSIX: CLOCK_MONOTONIC. The clock of desk, HIL and qemu runs.
#pragma once

#include "hal/clock.hpp"

namespace vtm::hal {

class MonotonicClock final : public Clock {
public:
    [[nodiscard]] std::uint64_t monotonicNs() const override;
};

}  // namespace vtm::hal
