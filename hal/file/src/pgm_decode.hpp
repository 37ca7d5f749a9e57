// Binary PGM (Netpbm "P5") decoding, hand-written and strict: the header must be
// complete and well formed, maxval 1..65535 (1 byte per sample up to 255, else 2 bytes
// big-endian), the raster complete, every sample <= maxval.
#pragma once

#include <cstddef>
#include <cstdint>

#include "frame_target.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::detail {

// Decodes the PGM in bytes[0, size) into target; samples are delivered as stored (not
// rescaled by maxval). Only the first image of a multi-image file is read.
[[nodiscard]] Status decodePgm(const std::uint8_t* bytes, std::size_t size, const FrameTarget& target) noexcept;

}  // namespace vtm::hal::detail
