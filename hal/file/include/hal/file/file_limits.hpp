// Capacities of the file-playback driver (hal/file). They are build-time constants in
// one place because the driver's static memory is a formula of them
// (docs/hal-file.md, "Memory"); a smaller build changes the numbers here and nowhere else.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vtm::hal::file_limits {

// Largest frame the driver plays back: each side up to 4096 px, at most 1 Mpx in total
// (a 1024 x 1024 navigation camera, or a 2048 x 512 strip).
inline constexpr std::int32_t kMaxFrameWidthPx = 4096;
inline constexpr std::int32_t kMaxFrameHeightPx = 4096;
inline constexpr std::size_t kMaxFramePixels = std::size_t{1024} * 1024U;

// Largest frame file (PGM or PNG), bytes: a 16-bit PGM of the largest frame plus 4 KiB
// of header and comments. Larger files are refused before they are read past this size.
inline constexpr std::size_t kMaxFrameFileBytes = 2U * kMaxFramePixels + 4096U;

// Decoded PNG bytes per pixel the decoder pool is sized for: 8-bit RGBA or 16-bit
// grey + alpha. 16-bit colour PNGs (6 or 8 bytes per pixel) are refused.
inline constexpr std::size_t kMaxPngBytesPerPixel = 4U;
// Alignment of every block of the PNG decoder pool (stb_image stores uint16 samples).
inline constexpr std::size_t kPngPoolAlignment = 16U;
// The PNG decoder pool, bytes. stb_image holds three blocks at its peak (non-interlaced
// PNG, no format conversion requested):
//   IDAT bytes, concatenated in a buffer that doubles from 4 KiB   <= 2 * kMaxFrameFileBytes
//   inflated scanlines, one filter byte per row                     <= 4 * kMaxFramePixels + kMaxFrameHeightPx
//   the unfiltered image (or, for a palette PNG, index image + RGBA <= 1 + 4 bytes per pixel
//                         expansion, which the same two terms cover)  <= 4 * kMaxFramePixels
// plus one alignment unit of padding per block.
inline constexpr std::size_t kPngPoolBytes =
    2U * kMaxFrameFileBytes +
    (kMaxPngBytesPerPixel * kMaxFramePixels + static_cast<std::size_t>(kMaxFrameHeightPx)) +
    kMaxPngBytesPerPixel * kMaxFramePixels + 4U * kPngPoolAlignment;

// Text files (frame manifest, pose log).
inline constexpr std::size_t kMaxPathChars = 255U;       // Config paths, without the NUL
inline constexpr std::size_t kMaxFramePathChars = 127U;  // a frame path in the manifest, without the NUL
inline constexpr std::size_t kMaxLineChars = 2047U;      // one line, without the line end
inline constexpr std::size_t kMaxTextLines = 65536U;     // lines per file, comments included
inline constexpr std::size_t kMaxLineTokens = 48U;       // whitespace-separated fields per line

// Records kept after init.
inline constexpr std::size_t kMaxFrames = 1024U;  // frame lines per manifest
inline constexpr std::size_t kMaxPoses = 4096U;   // pose lines per pose log

}  // namespace vtm::hal::file_limits
