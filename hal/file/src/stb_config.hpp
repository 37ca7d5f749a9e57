// How hal/file configures stb_image (Debian package libstb-dev, public domain). Every
// translation unit that includes <stb_image.h> includes this header first, so the
// declarations and the one implementation (stb_image_impl.cpp) agree.
//
//  - PNG only, from memory only (no stdio: files are read by file_bytes.cpp, which does
//    not allocate), no float/HDR paths (they call pow/ldexp), no SIMD;
//  - its allocations go to the fixed PNG pool (png_decode.cpp) instead of the heap;
//  - its internal assertions go to VTM_ASSERT;
//  - failure strings off: the driver reports its own Status reasons (string literals),
//    and stb's only non-literal reason is a writable static array.
#pragma once

#include <cstddef>

#include "hal/file/file_limits.hpp"
#include "vtm/core/assert.hpp"

namespace vtm::hal::detail {

// The PNG pool as an allocator (png_decode.cpp). A bump allocator: a block is never
// released individually; the whole pool is reset before every decode.
void* pngPoolAllocate(std::size_t bytes) noexcept;
void* pngPoolReallocate(void* block, std::size_t old_bytes, std::size_t new_bytes) noexcept;
void pngPoolRelease(void* block) noexcept;

}  // namespace vtm::hal::detail

#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#define STBI_NO_SIMD
#define STBI_NO_FAILURE_STRINGS
#define STBI_MAX_DIMENSIONS (::vtm::hal::file_limits::kMaxFrameWidthPx)
#define STBI_MALLOC(bytes) (::vtm::hal::detail::pngPoolAllocate(bytes))
#define STBI_REALLOC_SIZED(block, old_bytes, new_bytes) \
    (::vtm::hal::detail::pngPoolReallocate((block), (old_bytes), (new_bytes)))
#define STBI_FREE(block) (::vtm::hal::detail::pngPoolRelease(block))
#define STBI_ASSERT(cond) VTM_ASSERT(cond)
