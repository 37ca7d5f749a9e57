// stb_image and stb_image_write, compiled once for vtm_ground. Third-party C: this file
// alone is compiled with warnings off (tools/ground/CMakeLists.txt); keep it to the two
// thin wrappers below so that no code of ours goes unchecked.
#include "stb_codec.hpp"

#include <climits>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO  // files are read by file_bytes.cpp (errno in the messages)
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_BMP
#include <stb_image.h>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>

namespace vtm::ground::detail {
namespace {

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* p = static_cast<const unsigned char*>(data);
    out->insert(out->end(), p, p + size);
}

}  // namespace

bool decodeImage(const unsigned char* data, std::size_t size, DecodedImage& out, std::string& reason) {
    if (size > static_cast<std::size_t>(INT_MAX)) {
        reason = "file too large for stb_image";
        return false;
    }
    const int n = static_cast<int>(size);
    out.sixteen_bit = stbi_is_16_bit_from_memory(data, n) != 0;
    void* pixels =
        out.sixteen_bit
            ? static_cast<void*>(stbi_load_16_from_memory(data, n, &out.width, &out.height, &out.channels, 0))
            : static_cast<void*>(stbi_load_from_memory(data, n, &out.width, &out.height, &out.channels, 0));
    if (pixels == nullptr) {
        reason = stbi_failure_reason();
        return false;
    }
    const std::size_t count = static_cast<std::size_t>(out.width) * out.height * out.channels;
    if (out.sixteen_bit) {
        const auto* w = static_cast<const std::uint16_t*>(pixels);
        out.words.assign(w, w + count);
    } else {
        const auto* b = static_cast<const std::uint8_t*>(pixels);
        out.bytes.assign(b, b + count);
    }
    stbi_image_free(pixels);
    return true;
}

bool encodePng(const std::uint8_t* pixels, int width, int height, int channels, std::vector<unsigned char>& png) {
    png.clear();
    return stbi_write_png_to_func(appendBytes, &png, width, height, channels, pixels, width * channels) != 0;
}

}  // namespace vtm::ground::detail
