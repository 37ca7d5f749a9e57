// Binary PGM (P5) and PPM (P6), 8- or 16-bit, decoded here rather than by stb_image:
// Netpbm stores 16-bit samples big endian, which stb_image 2.27 (Debian 12) ignores,
// and a truncated file must be an error, not an image with made-up pixels.
// Samples are kept as stored (not rescaled by maxval): ground truth levels are data.
#pragma once

#include <cstddef>
#include <string>

#include "decoded_image.hpp"

namespace vtm::ground::detail {

// True when the bytes start with "P5" or "P6".
bool isBinaryPnm(const unsigned char* data, std::size_t size);
// false with a reason when the header is malformed or the pixels are cut short.
bool decodePnm(const unsigned char* data, std::size_t size, DecodedImage& out, std::string& reason);

}  // namespace vtm::ground::detail
