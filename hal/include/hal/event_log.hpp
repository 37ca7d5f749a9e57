// hal::EventLog: the flight code's only output channel for diagnostics. A fixed-size
// ring of small binary events (severity, id, four integer arguments, time); nothing is
// formatted on board. Ground tools drain and render it. When the ring is full the
// oldest event is overwritten and counted (dropped()), so logging never blocks and
// never allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/ring_buffer.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

enum class Severity : std::uint8_t {
    kDebug = 0,
    kInfo = 1,
    kWarning = 2,
    kError = 3,
    kFatal = 4,
};

struct Event {
    std::uint64_t timestamp_ns = 0U;
    std::uint16_t id = 0U;        // event identifier (docs/ lists them per module)
    Severity severity = Severity::kDebug;
    std::int64_t args[4] = {0, 0, 0, 0};
};

class EventLog {
public:
    static constexpr std::size_t kCapacity = 256U;

    void record(std::uint64_t timestamp_ns, Severity severity, std::uint16_t id, std::int64_t a0 = 0,
                std::int64_t a1 = 0, std::int64_t a2 = 0, std::int64_t a3 = 0) noexcept;
    // Records a prepared event (callers that fill all four arguments: one reference
    // argument instead of eight scalars, which some ABIs pass on the stack).
    void record(const Event& event) noexcept { ring_.push(event); }
    // Records a Status: args = {code, detail, 0, 0}; severity kError unless ok.
    void recordStatus(std::uint64_t timestamp_ns, std::uint16_t id, const Status& status) noexcept;

    // Oldest event out; false when empty.
    [[nodiscard]] bool pop(Event& out) noexcept { return ring_.pop(out); }
    [[nodiscard]] std::size_t size() const noexcept { return ring_.size(); }
    [[nodiscard]] const Event& at(std::size_t i) const noexcept { return ring_.at(i); }
    [[nodiscard]] std::uint64_t dropped() const noexcept { return ring_.dropped(); }

private:
    RingBuffer<Event, kCapacity> ring_{};
};

}  // namespace vtm::hal
