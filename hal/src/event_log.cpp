#include "hal/event_log.hpp"

namespace vtm::hal {

void EventLog::record(std::uint64_t timestamp_ns, Severity severity, std::uint16_t id, std::int64_t a0,
                      std::int64_t a1, std::int64_t a2, std::int64_t a3) noexcept {
    Event e;
    e.timestamp_ns = timestamp_ns;
    e.id = id;
    e.severity = severity;
    e.args[0] = a0;
    e.args[1] = a1;
    e.args[2] = a2;
    e.args[3] = a3;
    ring_.push(e);
}

void EventLog::recordStatus(std::uint64_t timestamp_ns, std::uint16_t id, const Status& status) noexcept {
    record(timestamp_ns, status.isOk() ? Severity::kInfo : Severity::kError, id,
           static_cast<std::int64_t>(status.code()), status.detail());
}

}  // namespace vtm::hal
