// The no-heap guard. Every test executable is linked with -Wl,--wrap=malloc,... and
// with replacements of every global operator new/delete (no_heap_guard.cpp), so each
// heap call from any object in the program — flight libraries, Eigen, libstdc++ —
// bumps a volatile counter. A NoHeapScope around a run path proves it allocates
// nothing:
//
//   vtm::test::NoHeapScope guard;
//   ASSERT_TRUE(module.process(...).isOk());
//   EXPECT_EQ(guard.heapCalls(), 0U);
#pragma once

#include <cstdint>

namespace vtm::test {

// Heap calls since program start: allocations (malloc, calloc, realloc, aligned_alloc,
// posix_memalign, memalign, operator new in all forms) and releases of non-null blocks.
[[nodiscard]] std::uint64_t heapAllocationCount() noexcept;
[[nodiscard]] std::uint64_t heapReleaseCount() noexcept;

class NoHeapScope {
public:
    NoHeapScope() noexcept;
    NoHeapScope(const NoHeapScope&) = delete;
    NoHeapScope& operator=(const NoHeapScope&) = delete;
    // Allocations plus releases since construction.
    [[nodiscard]] std::uint64_t heapCalls() const noexcept;

private:
    std::uint64_t allocations_at_start_;
    std::uint64_t releases_at_start_;
};

}  // namespace vtm::test
