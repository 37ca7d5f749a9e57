#include "png_decode.hpp"

#include <cstring>

#include "stb_config.hpp"
// stb_config.hpp first: it configures the declarations below.
#include <stb_image.h>

namespace vtm::hal::detail {
namespace {

using file_limits::kPngPoolAlignment;
using file_limits::kPngPoolBytes;

static_assert(kPngPoolBytes % kPngPoolAlignment == 0U, "pool size must be a whole number of alignment units");
static_assert(file_limits::kMaxFrameFileBytes <= 0x7FFFFFFFU, "stb_image takes the PNG length as an int");

// ---- the pool ------------------------------------------------------------------------
// A bump allocator over one static array. stb_image's peak is three or four live blocks
// (file_limits.hpp gives the sizes); freeing is deferred to reset(), before each decode.
// The last block may grow in place, which is what stb_image does with its IDAT buffer and
// its inflate output: without that, every doubling would keep the old copy alive.
// The bytes live in their own zero-initialised array so that they land in .bss; the
// bookkeeping next to them has non-zero initial values (.data).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the static decoder pool
alignas(kPngPoolAlignment) std::uint8_t g_pool_bytes[kPngPoolBytes];
struct PngPool {
    static constexpr std::size_t kNoBlock = ~std::size_t{0};
    std::uint8_t* bytes;
    std::size_t used;
    std::size_t last_offset;
    std::size_t peak;        // most bytes in use during the current (or last) decode
    std::size_t high_water;  // most bytes in use during any decode
    std::size_t refused_bytes;  // size of the request that did not fit (0: none)
};
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the pool's bookkeeping
PngPool g_pool{g_pool_bytes, 0U, PngPool::kNoBlock, 0U, 0U, 0U};

std::size_t roundUpToAlignment(std::size_t bytes) noexcept {
    return (bytes + (kPngPoolAlignment - 1U)) & ~(kPngPoolAlignment - 1U);
}

void pngPoolReset() noexcept {
    g_pool.used = 0U;
    g_pool.last_offset = PngPool::kNoBlock;
    g_pool.peak = 0U;
    g_pool.refused_bytes = 0U;
}

// Sets the end of the last block (at `offset`) so that it holds `bytes`; nullptr if the
// pool cannot hold them. `used` stays a multiple of the alignment, and bytes <= remaining
// implies round-up(bytes) <= remaining because the pool size is one too.
void* placeBlock(std::size_t offset, std::size_t bytes) noexcept {
    if (bytes > kPngPoolBytes - offset) {
        g_pool.refused_bytes = bytes;
        return nullptr;
    }
    g_pool.last_offset = offset;
    g_pool.used = offset + roundUpToAlignment(bytes);
    g_pool.peak = (g_pool.used > g_pool.peak) ? g_pool.used : g_pool.peak;
    g_pool.high_water = (g_pool.used > g_pool.high_water) ? g_pool.used : g_pool.high_water;
    return &g_pool.bytes[offset];
}

}  // namespace

void* pngPoolAllocate(std::size_t bytes) noexcept { return placeBlock(g_pool.used, bytes); }

void* pngPoolReallocate(void* block, std::size_t old_bytes, std::size_t new_bytes) noexcept {
    if (block == nullptr) {
        return pngPoolAllocate(new_bytes);
    }
    // Pointer equality is defined for any two pointers: no address arithmetic is needed to
    // recognise the last block.
    if (g_pool.last_offset != PngPool::kNoBlock && block == &g_pool.bytes[g_pool.last_offset]) {
        return placeBlock(g_pool.last_offset, new_bytes);
    }
    void* fresh = pngPoolAllocate(new_bytes);
    if (fresh != nullptr) {
        std::memcpy(fresh, block, (old_bytes < new_bytes) ? old_bytes : new_bytes);
    }
    return fresh;
}

void pngPoolRelease(void* block) noexcept {
    // Nothing to do: a bump allocator releases everything at the next reset.
    (void)block;
}

std::size_t pngPoolHighWaterBytes() noexcept { return g_pool.high_water; }
std::size_t pngPoolLastDecodeBytes() noexcept { return g_pool.peak; }

namespace {

// ---- header --------------------------------------------------------------------------
constexpr std::uint8_t kSignature[8] = {0x89U, 'P', 'N', 'G', '\r', '\n', 0x1AU, '\n'};

struct PngHeader {
    std::uint32_t width = 0U;
    std::uint32_t height = 0U;
    std::uint8_t depth = 0U;
    std::uint8_t colour = 0U;  // 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
    std::uint8_t interlace = 0U;
};

std::uint32_t bigEndian32(const std::uint8_t* p) noexcept {
    return (std::uint32_t{p[0]} << 24U) | (std::uint32_t{p[1]} << 16U) | (std::uint32_t{p[2]} << 8U) |
           std::uint32_t{p[3]};
}

// PNG specification, table 11.1: the bit depths each colour type allows.
bool depthFitsColour(std::uint8_t depth, std::uint8_t colour) noexcept {
    const bool low = depth == 1U || depth == 2U || depth == 4U;
    const bool eight_or_16 = depth == 8U || depth == 16U;
    switch (colour) {
        case 0U: return low || eight_or_16;
        case 3U: return low || depth == 8U;
        case 2U:
        case 4U:
        case 6U: return eight_or_16;
        default: return false;
    }
}

// The IHDR chunk must come first, right after the signature (PNG specification 5.6).
Status readHeader(const std::uint8_t* bytes, std::size_t size, PngHeader& h) noexcept {
    if (size < 33U || bigEndian32(bytes + 8) != 13U || std::memcmp(bytes + 12, "IHDR", 4U) != 0) {
        return Status(StatusCode::kCorruptData, "PNG: IHDR chunk missing or truncated", static_cast<std::int64_t>(size));
    }
    h.width = bigEndian32(bytes + 16);
    h.height = bigEndian32(bytes + 20);
    h.depth = bytes[24];
    h.colour = bytes[25];
    h.interlace = bytes[28];
    if (bytes[26] != 0U || bytes[27] != 0U || h.interlace > 1U) {
        return Status(StatusCode::kCorruptData, "PNG: IHDR compression, filter or interlace method invalid");
    }
    if (!depthFitsColour(h.depth, h.colour)) {
        return Status(StatusCode::kCorruptData, "PNG: IHDR bit depth and colour type do not combine", h.depth);
    }
    if (h.width == 0U || h.height == 0U) {
        return Status(StatusCode::kCorruptData, "PNG: width or height is zero");
    }
    return Status::ok();
}

// stb_image copies a first IDAT of length 0 to a null buffer (memcpy(NULL, p, 0): undefined
// behaviour, found by fuzz_file_readers); no encoder writes one, so such a file is refused
// before stb_image sees it. Walks the chunk list after IHDR up to IEND or the end of data.
Status checkChunks(const std::uint8_t* bytes, std::size_t size) noexcept {
    std::size_t pos = 33U;  // signature 8 + IHDR 25
    // bound: each pass moves pos on by at least 12 bytes or ends
    while (pos + 8U <= size) {
        const std::uint32_t length = bigEndian32(bytes + pos);
        if (std::memcmp(bytes + pos + 4U, "IDAT", 4U) == 0 && length == 0U) {
            return Status(StatusCode::kCorruptData, "PNG: empty IDAT chunk", static_cast<std::int64_t>(pos));
        }
        if (std::memcmp(bytes + pos + 4U, "IEND", 4U) == 0 || length > size - pos - 8U) {
            break;  // the end, or a chunk cut short: stb_image reports that
        }
        pos += 12U + static_cast<std::size_t>(length);
    }
    return Status::ok();
}

Status checkHeader(const PngHeader& h, const FrameTarget& target) noexcept {
    if (h.interlace != 0U) {
        return Status(StatusCode::kUnsupported, "PNG: interlaced (Adam7) frames are not supported");
    }
    if (h.depth == 16U && (h.colour == 2U || h.colour == 6U)) {
        return Status(StatusCode::kUnsupported, "PNG: 16-bit colour frames are not supported", h.colour);
    }
    if (h.width != static_cast<std::uint32_t>(target.width())) {
        return Status(StatusCode::kSizeMismatch, kWidthMismatch, h.width);
    }
    if (h.height != static_cast<std::uint32_t>(target.height())) {
        return Status(StatusCode::kSizeMismatch, kHeightMismatch, h.height);
    }
    if (h.depth == 16U && !target.wide()) {
        return Status(StatusCode::kSizeMismatch, kWideSamplesFor8Bit, h.depth);
    }
    return Status::ok();
}

// ---- pixels --------------------------------------------------------------------------
// Grey value of one decoded pixel of `channels` samples (grey, grey+alpha, RGB, RGBA).
// ITU-R BT.601 luma weights in 1/256 units, rounded to nearest: 77 + 150 + 29 = 256, so
// a grey colour keeps its value and 8-bit input stays within 0..255.
template <typename Sample>
std::uint32_t greyOf(const Sample* px, int channels) noexcept {
    if (channels <= 2) {
        return px[0];
    }
    return (77U * px[0] + 150U * px[1] + 29U * px[2] + 128U) >> 8U;
}

template <typename Sample>
Status storeGrey(const void* pixels, int channels, const FrameTarget& target) noexcept {
    const auto* base = static_cast<const Sample*>(pixels);
    const std::size_t row_samples = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(channels);
    for (std::int32_t y = 0; y < target.height(); ++y) {
        const Sample* row = base + static_cast<std::size_t>(y) * row_samples;
        VTM_RETURN_IF_ERROR(target.fillRow(y, [row, channels](std::int32_t x) {
            return greyOf(row + static_cast<std::ptrdiff_t>(x) * channels, channels);
        }));
    }
    return Status::ok();
}

}  // namespace

bool hasPngSignature(const std::uint8_t* bytes, std::size_t size) noexcept {
    return size >= sizeof(kSignature) && std::memcmp(bytes, kSignature, sizeof(kSignature)) == 0;
}

Status decodePng(const std::uint8_t* bytes, std::size_t size, const FrameTarget& target) noexcept {
    PngHeader h;
    VTM_RETURN_IF_ERROR(readHeader(bytes, size, h));
    VTM_RETURN_IF_ERROR(checkHeader(h, target));
    VTM_RETURN_IF_ERROR(checkChunks(bytes, size));
    pngPoolReset();
    int width = 0;
    int height = 0;
    int channels = 0;
    // No conversion requested (0 channels): stb_image would otherwise allocate a second
    // image and use its own grey formula.
    const int length = static_cast<int>(size);
    const void* pixels = (h.depth == 16U)
                             ? static_cast<const void*>(stbi_load_16_from_memory(bytes, length, &width, &height, &channels, 0))
                             : static_cast<const void*>(stbi_load_from_memory(bytes, length, &width, &height, &channels, 0));
    if (pixels == nullptr) {
        if (g_pool.refused_bytes != 0U) {
            return Status(StatusCode::kCorruptData, "PNG: data inflates beyond the static pool",
                          static_cast<std::int64_t>(g_pool.refused_bytes));
        }
        return Status(StatusCode::kCorruptData, "PNG: stb_image rejected the data (corrupt stream)");
    }
    // stb_image returns the IHDR size and 1..4 channels for a successful decode.
    const bool shape_ok = width == target.width() && height == target.height() && channels >= 1 && channels <= 4;
    VTM_ASSERT(shape_ok, width, channels);
    if (!shape_ok) {
        return Status(StatusCode::kCorruptData, "PNG: decoded shape differs from IHDR", channels);
    }
    return (h.depth == 16U) ? storeGrey<std::uint16_t>(pixels, channels, target)
                            : storeGrey<std::uint8_t>(pixels, channels, target);
}

}  // namespace vtm::hal::detail
