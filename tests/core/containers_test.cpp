#include <gtest/gtest.h>

#include "assert_capture.hpp"
#include "no_heap_guard.hpp"
#include "vtm/core/fixed_vector.hpp"
#include "vtm/core/ring_buffer.hpp"
#include "vtm/core/span.hpp"

namespace vtm {
namespace {

TEST(FixedVector, RefusesToGrowPastCapacity) {
    FixedVector<int, 3> v;
    EXPECT_TRUE(v.push_back(1));
    EXPECT_TRUE(v.push_back(2));
    EXPECT_TRUE(v.push_back(3));
    EXPECT_TRUE(v.full());
    EXPECT_FALSE(v.push_back(4));
    EXPECT_EQ(v.size(), 3U);
    EXPECT_EQ(v[2], 3);
    int sum = 0;
    for (const int x : v) {
        sum += x;
    }
    EXPECT_EQ(sum, 6);
}

TEST(FixedVector, ClearAndTruncateResetStorage) {
    FixedVector<int, 4> v;
    for (int i = 1; i <= 4; ++i) {
        ASSERT_TRUE(v.push_back(i));
    }
    v.truncate(2);
    EXPECT_EQ(v.size(), 2U);
    ASSERT_TRUE(v.push_back(9));
    EXPECT_EQ(v[2], 9);
    v.pop_back();
    EXPECT_EQ(v.size(), 2U);
    v.clear();
    EXPECT_TRUE(v.empty());
}

TEST(FixedVector, IndexPastSizeIsAnAssertion) {
    test::AssertCapture capture;
    FixedVector<int, 4> v;
    ASSERT_TRUE(v.push_back(5));
    EXPECT_EQ(v[3], 5);  // falls back to element 0, never reads stale storage
    EXPECT_EQ(capture.count(), 1);
    v.pop_back();
    v.pop_back();
    EXPECT_EQ(capture.count(), 2);
}

TEST(FixedVector, UseTouchesNoHeap) {
    test::NoHeapScope guard;
    FixedVector<double, 64> v;
    for (int i = 0; i < 100; ++i) {
        (void)v.push_back(i * 0.5);
    }
    EXPECT_EQ(v.size(), 64U);
    EXPECT_EQ(guard.heapCalls(), 0U);
}

TEST(RingBuffer, OverwritesOldestAndCountsDrops) {
    RingBuffer<int, 3> r;
    for (int i = 0; i < 5; ++i) {
        r.push(i);
    }
    EXPECT_EQ(r.size(), 3U);
    EXPECT_EQ(r.dropped(), 2U);
    EXPECT_EQ(r.at(0), 2);
    EXPECT_EQ(r.at(2), 4);
    int out = -1;
    ASSERT_TRUE(r.pop(out));
    EXPECT_EQ(out, 2);
    ASSERT_TRUE(r.pop(out));
    ASSERT_TRUE(r.pop(out));
    EXPECT_EQ(out, 4);
    EXPECT_FALSE(r.pop(out));
    EXPECT_EQ(out, 4);
}

TEST(Span, SubspanAndBounds) {
    int data[5] = {1, 2, 3, 4, 5};
    const Span<int> s(data, 5);
    const Span<int> mid = s.subspan(1, 3);
    EXPECT_EQ(mid.size(), 3U);
    EXPECT_EQ(mid[0], 2);
    const Span<const int> c = mid;
    EXPECT_EQ(c[2], 4);
    test::AssertCapture capture;
    EXPECT_TRUE(s.subspan(4, 2).empty());
    EXPECT_EQ(s[7], 1);
    EXPECT_EQ(capture.count(), 2);
}

}  // namespace
}  // namespace vtm
