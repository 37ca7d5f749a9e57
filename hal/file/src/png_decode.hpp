// PNG decoding through stb_image with its memory in a fixed static pool
// (file_limits::kPngPoolBytes), reset before every decode: no heap at any time.
//
// Accepted: non-interlaced PNGs of bit depth 1..16 in grey, grey + alpha, palette, RGB
// or RGBA, except 16-bit RGB/RGBA. Colour becomes grey as
//   grey = (77 R + 150 G + 29 B + 128) >> 8   (integers; R = G = B = v gives v),
// alpha is ignored, palette entries are expanded first, 1/2/4-bit grey is scaled to
// 0..255 by stb_image (v * 255 / (2^depth - 1)).
#pragma once

#include <cstddef>
#include <cstdint>

#include "frame_target.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::detail {

// Decodes the PNG in bytes[0, size) (size <= kMaxFrameFileBytes) into target.
[[nodiscard]] Status decodePng(const std::uint8_t* bytes, std::size_t size, const FrameTarget& target) noexcept;

// True when bytes[0, size) starts with the PNG signature.
[[nodiscard]] bool hasPngSignature(const std::uint8_t* bytes, std::size_t size) noexcept;

// Most pool bytes in use at once during any decode so far / during the last decode.
[[nodiscard]] std::size_t pngPoolHighWaterBytes() noexcept;
[[nodiscard]] std::size_t pngPoolLastDecodeBytes() noexcept;

}  // namespace vtm::hal::detail
