#include <gtest/gtest.h>

#include <cstdint>

#include "assert_capture.hpp"
#include "no_heap_guard.hpp"
#include "vtm/core/arena.hpp"

namespace vtm {
namespace {

bool isAligned(const void* p, std::size_t a) { return (reinterpret_cast<std::uintptr_t>(p) % a) == 0U; }

TEST(Arena, HandsOutAlignedZeroFilledDisjointBlocks) {
    static StaticArena<1024> arena;
    arena.reset();
    auto* a = static_cast<std::uint8_t*>(arena.allocate(3, 1));
    auto* b = static_cast<std::uint8_t*>(arena.allocate(40, 32));
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_TRUE(isAligned(b, 32));
    EXPECT_GE(b, a + 3);
    for (int i = 0; i < 40; ++i) {
        EXPECT_EQ(b[i], 0U);
    }
    EXPECT_LE(arena.usedBytes(), 3U + 31U + 40U);
    EXPECT_EQ(arena.remainingBytes(), arena.capacityBytes() - arena.usedBytes());
}

TEST(Arena, ReturnsNullWhenExhaustedWithoutAsserting) {
    test::AssertCapture capture;
    StaticArena<64> arena;
    EXPECT_NE(arena.allocate(48), nullptr);
    EXPECT_EQ(arena.allocate(32), nullptr);
    EXPECT_EQ(arena.allocateArray<std::uint32_t>(static_cast<std::size_t>(-1) / 2U).data(), nullptr);
    EXPECT_EQ(capture.count(), 0);  // exhaustion is a configuration matter, reported by status
}

TEST(Arena, AllocationAfterFreezeIsAnAssertionFailure) {
    test::AssertCapture capture;
    StaticArena<256> arena;
    ASSERT_NE(arena.allocate(16), nullptr);
    arena.freeze();
    EXPECT_TRUE(arena.frozen());
    EXPECT_EQ(arena.allocate(16), nullptr);
    EXPECT_EQ(capture.count(), 1);
    EXPECT_TRUE(arena.allocateArray<float>(4).empty());
    EXPECT_EQ(capture.count(), 2);
}

TEST(Arena, NonPowerOfTwoAlignmentIsAnAssertionFailure) {
    test::AssertCapture capture;
    StaticArena<256> arena;
    EXPECT_EQ(arena.allocate(8, 12), nullptr);
    EXPECT_EQ(capture.count(), 1);
}

TEST(Arena, HighWaterMarkSurvivesReset) {
    StaticArena<512> arena;
    ASSERT_NE(arena.allocate(300, 1), nullptr);
    const std::size_t peak = arena.highWaterBytes();
    EXPECT_GE(peak, 300U);
    arena.reset();
    EXPECT_EQ(arena.usedBytes(), 0U);
    ASSERT_NE(arena.allocate(10, 1), nullptr);
    EXPECT_EQ(arena.highWaterBytes(), peak);
}

TEST(Arena, BlockBytesBoundsTheWorstCasePadding) {
    // A workspace formula built from blockBytes() must always fit, whatever the pool's
    // base address: try every misalignment of the pool.
    alignas(64) static std::byte pool[512];
    for (std::size_t offset = 0; offset < 64; ++offset) {
        Arena arena(pool + offset, Arena::blockBytes(100, 64) + Arena::blockBytes(7, 16));
        EXPECT_NE(arena.allocate(100, 64), nullptr) << offset;
        EXPECT_NE(arena.allocate(7, 16), nullptr) << offset;
    }
}

TEST(Arena, AllocationsTouchNoHeap) {
    static StaticArena<4096> arena;
    arena.reset();
    test::NoHeapScope guard;
    for (int i = 0; i < 10; ++i) {
        EXPECT_FALSE(arena.allocateArray<double>(20).empty());
    }
    EXPECT_EQ(guard.heapCalls(), 0U);
}

// arrayBytes<T> is enough for allocateArray<T> from a pool that starts at any offset.
TEST(Arena, ArrayBytesCoversTheWorstAlignmentPadding) {
    alignas(64) std::byte storage[256 + 64];
    for (std::size_t offset = 0; offset < 16; ++offset) {
        Arena arena(storage + offset, Arena::arrayBytes<double>(10));
        EXPECT_EQ(arena.allocateArray<double>(10).size(), 10U) << offset;
        Arena small(storage + offset, 10 * sizeof(double) - 1);
        EXPECT_TRUE(small.allocateArray<double>(10).empty()) << offset;
    }
}

// construct<T>: objects with default member initialisers (and over-aligned ones) come out
// initialised and aligned; constructBytes<T> is enough from any pool offset; a pool one
// byte short gives nullptr.
struct alignas(32) Initialised {
    double value = 2.5;
    std::int32_t count = 7;
};

TEST(Arena, ConstructInitialisesObjectsAndConstructBytesSuffice) {
    alignas(64) std::byte storage[512 + 64];
    for (std::size_t offset = 0; offset < 16; ++offset) {
        Arena arena(storage + offset, Arena::constructBytes<Initialised>(5));
        test::NoHeapScope guard;
        Initialised* objects = arena.construct<Initialised>(5);
        ASSERT_NE(objects, nullptr) << offset;
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(objects) % 32U, 0U);
        for (int i = 0; i < 5; ++i) {
            EXPECT_EQ(objects[i].value, 2.5);
            EXPECT_EQ(objects[i].count, 7);
        }
        EXPECT_EQ(guard.heapCalls(), 0U);
        Arena small(storage + offset, 5 * sizeof(Initialised) - 1);
        EXPECT_EQ(small.construct<Initialised>(5), nullptr) << offset;
    }
}

}  // namespace
}  // namespace vtm
