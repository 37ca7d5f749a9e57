#include "no_heap_guard.hpp"

#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
// volatile: the counters must be read and written as the program says, even when the
// optimiser can see that a test body does nothing else with them.
volatile std::uint64_t g_allocations = 0U;
volatile std::uint64_t g_releases = 0U;

void countAllocation() noexcept { g_allocations = g_allocations + 1U; }
void countRelease(const void* p) noexcept {
    if (p != nullptr) {
        g_releases = g_releases + 1U;
    }
}
}  // namespace

extern "C" {
void* __real_malloc(std::size_t size);
void __real_free(void* p);
void* __real_calloc(std::size_t n, std::size_t size);
void* __real_realloc(void* p, std::size_t size);
void* __real_aligned_alloc(std::size_t alignment, std::size_t size);
int __real_posix_memalign(void** out, std::size_t alignment, std::size_t size);
void* __real_memalign(std::size_t alignment, std::size_t size);

void* __wrap_malloc(std::size_t size) {
    countAllocation();
    return __real_malloc(size);
}
void __wrap_free(void* p) {
    countRelease(p);
    __real_free(p);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
    countAllocation();
    return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t size) {
    countAllocation();
    return __real_realloc(p, size);
}
void* __wrap_aligned_alloc(std::size_t alignment, std::size_t size) {
    countAllocation();
    return __real_aligned_alloc(alignment, size);
}
int __wrap_posix_memalign(void** out, std::size_t alignment, std::size_t size) {
    countAllocation();
    return __real_posix_memalign(out, alignment, size);
}
void* __wrap_memalign(std::size_t alignment, std::size_t size) {
    countAllocation();
    return __real_memalign(alignment, size);
}
}  // extern "C"

namespace {
void* allocateOrThrow(std::size_t size) {
    countAllocation();
    void* p = __real_malloc(size == 0U ? 1U : size);
    if (p == nullptr) {
        throw std::bad_alloc();
    }
    return p;
}
void* allocateAlignedOrThrow(std::size_t size, std::align_val_t alignment) {
    countAllocation();
    void* p = nullptr;
    const std::size_t a = static_cast<std::size_t>(alignment) < sizeof(void*) ? sizeof(void*)
                                                                              : static_cast<std::size_t>(alignment);
    if (__real_posix_memalign(&p, a, size == 0U ? 1U : size) != 0) {
        throw std::bad_alloc();
    }
    return p;
}
void release(void* p) noexcept {
    countRelease(p);
    __real_free(p);
}
}  // namespace

void* operator new(std::size_t size) { return allocateOrThrow(size); }
void* operator new[](std::size_t size) { return allocateOrThrow(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    countAllocation();
    return __real_malloc(size == 0U ? 1U : size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    countAllocation();
    return __real_malloc(size == 0U ? 1U : size);
}
void* operator new(std::size_t size, std::align_val_t a) { return allocateAlignedOrThrow(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocateAlignedOrThrow(size, a); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }

namespace vtm::test {

std::uint64_t heapAllocationCount() noexcept { return g_allocations; }
std::uint64_t heapReleaseCount() noexcept { return g_releases; }

NoHeapScope::NoHeapScope() noexcept : allocations_at_start_(g_allocations), releases_at_start_(g_releases) {}

std::uint64_t NoHeapScope::heapCalls() const noexcept {
    return (g_allocations - allocations_at_start_) + (g_releases - releases_at_start_);
}

}  // namespace vtm::test
