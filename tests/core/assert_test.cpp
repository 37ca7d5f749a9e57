#include <gtest/gtest.h>

#include "assert_capture.hpp"
#include "vtm/core/assert.hpp"

namespace vtm {
namespace {

int checkedHalf(int v) {
    VTM_ASSERT(v % 2 == 0, v, 2);
    return v / 2;
}

TEST(Assert, PassingAssertionCallsNoHook) {
    test::AssertCapture capture;
    EXPECT_EQ(checkedHalf(8), 4);
    EXPECT_EQ(capture.count(), 0);
}

TEST(Assert, FailingAssertionReachesTheHookWithArguments) {
    test::AssertCapture capture;
    (void)checkedHalf(7);
    ASSERT_EQ(capture.count(), 1);
    EXPECT_STREQ(capture.last().expression, "v % 2 == 0");
    EXPECT_EQ(capture.last().arg0, 7);
    EXPECT_EQ(capture.last().arg1, 2);
    EXPECT_GT(capture.last().line, 0);
}

TEST(Assert, CaptureRestoresThePreviousHook) {
    {
        test::AssertCapture outer;
        {
            test::AssertCapture inner;
            (void)checkedHalf(1);
            EXPECT_EQ(inner.count(), 1);
        }
    }
    // With no capture alive the default hook (abort) is back: see the death test.
}

TEST(AssertDeathTest, DefaultHookHalts) {
    EXPECT_DEATH((void)checkedHalf(3), "");
}

}  // namespace
}  // namespace vtm
