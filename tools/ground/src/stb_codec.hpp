// The only door to stb_image / stb_image_write in vtm_ground (stb_codec.cpp). stb is
// compiled there with STB_IMAGE_STATIC / STB_IMAGE_WRITE_STATIC, so its symbols are
// local to that one object and cannot clash with hal/file's own stb_image build (which
// uses a static allocator and is linked into the same `vtm` executable).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "decoded_image.hpp"

namespace vtm::ground::detail {

// Decodes PNG, JPEG or BMP from memory; false with stb's reason otherwise. (PGM/PPM go
// to pnm_decode.hpp: stb_image 2.27 reads 16-bit samples in the wrong byte order.)
bool decodeImage(const unsigned char* data, std::size_t size, DecodedImage& out, std::string& reason);

// Encodes 8-bit pixels (1 or 3 channels, packed rows) as PNG. false if stb fails.
bool encodePng(const std::uint8_t* pixels, int width, int height, int channels,
               std::vector<unsigned char>& png);

}  // namespace vtm::ground::detail
