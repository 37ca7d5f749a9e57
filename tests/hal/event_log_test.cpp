#include <gtest/gtest.h>

#include "hal/event_log.hpp"
#include "no_heap_guard.hpp"

namespace vtm::hal {
namespace {

TEST(EventLog, KeepsEventsInOrderWithArguments) {
    static EventLog log;
    log.record(10, Severity::kInfo, 7, 1, 2, 3, 4);
    log.recordStatus(20, 8, Status(StatusCode::kTimeout, "camera: no frame", 250));
    ASSERT_EQ(log.size(), 2U);
    EXPECT_EQ(log.at(0).id, 7);
    EXPECT_EQ(log.at(0).args[3], 4);
    EXPECT_EQ(log.at(1).severity, Severity::kError);
    EXPECT_EQ(log.at(1).args[0], static_cast<std::int64_t>(StatusCode::kTimeout));
    EXPECT_EQ(log.at(1).args[1], 250);
    Event e;
    ASSERT_TRUE(log.pop(e));
    EXPECT_EQ(e.timestamp_ns, 10U);
    ASSERT_TRUE(log.pop(e));
    EXPECT_FALSE(log.pop(e));
}

TEST(EventLog, FullRingDropsOldestWithoutAllocating) {
    static EventLog log;
    test::NoHeapScope guard;
    const std::size_t extra = 10;
    for (std::size_t i = 0; i < EventLog::kCapacity + extra; ++i) {
        log.record(i, Severity::kDebug, 1, static_cast<std::int64_t>(i));
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_EQ(log.size(), EventLog::kCapacity);
    EXPECT_EQ(log.dropped(), extra);
    EXPECT_EQ(log.at(0).args[0], static_cast<std::int64_t>(extra));
    log.recordStatus(0, 2, Status::ok());
    EXPECT_EQ(log.at(log.size() - 1).severity, Severity::kInfo);
}

}  // namespace
}  // namespace vtm::hal
