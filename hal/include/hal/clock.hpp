// hal::Clock: monotonic time for timestamps and stage timing.
#pragma once

#include <cstdint>

namespace vtm::hal {

class Clock {
public:
    // Nanoseconds since an arbitrary fixed origin; never decreases.
    [[nodiscard]] virtual std::uint64_t monotonicNs() const = 0;

protected:
    // Not deletable through the interface, hence no virtual destructor: a virtual one
    // makes every driver emit a deleting destructor that references operator delete
    // (the heap-symbol check rejects it). Drivers are statically allocated and final.
    Clock() = default;
    ~Clock() = default;
    Clock(const Clock&) = default;
    Clock& operator=(const Clock&) = default;
    Clock(Clock&&) = default;
    Clock& operator=(Clock&&) = default;
};

// A clock that moves only when told to: for tests and for replaying recorded data.
class ManualClock final : public Clock {
public:
    [[nodiscard]] std::uint64_t monotonicNs() const override { return now_ns_; }
    // Advances by dt_ns (time never goes backwards).
    void advance(std::uint64_t dt_ns) noexcept { now_ns_ += dt_ns; }

private:
    std::uint64_t now_ns_ = 0U;
};

}  // namespace vtm::hal
