#include "vtm/ground/image_io.hpp"

#include <cstdint>

#include "file_bytes.hpp"
#include "pnm_decode.hpp"
#include "stb_codec.hpp"

namespace vtm::ground {
namespace {

// Reads and decodes a file; the error names the file.
Result<detail::DecodedImage> decodeFile(const std::string& path) {
    Result<detail::Bytes> bytes = detail::readFileBytes(path);
    if (!bytes.ok) {
        return Result<detail::DecodedImage>::failure(bytes.error);
    }
    detail::DecodedImage decoded;
    std::string reason;
    const unsigned char* data = bytes.value.data();
    const std::size_t size = bytes.value.size();
    if (detail::isBinaryPnm(data, size)) {
        if (!detail::decodePnm(data, size, decoded, reason)) {
            return Result<detail::DecodedImage>::failure(path + ": " + reason);
        }
        return Result<detail::DecodedImage>::success(std::move(decoded));
    }
    if (!detail::decodeImage(data, size, decoded, reason)) {
        return Result<detail::DecodedImage>::failure(
            path + ": not a readable PNG, PGM/PPM (P5/P6), JPEG or BMP image (stb_image: " + reason + ")");
    }
    return Result<detail::DecodedImage>::success(std::move(decoded));
}

// BT.601 luma in 1/256 units, rounded to nearest: the weights sum to 256, so white stays
// 255 and the result always fits 8 bits. Same formula as hal/file/src/png_decode.cpp.
std::uint8_t lumaOf(const std::uint8_t* rgb) {
    const unsigned luma = (77U * rgb[0] + 150U * rgb[1] + 29U * rgb[2] + 128U) >> 8U;
    return static_cast<std::uint8_t>(luma);
}

GreyImage toGrey(const detail::DecodedImage& d) {
    GreyImage grey(d.width, d.height);
    const auto ch = static_cast<std::size_t>(d.channels);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
        const std::uint8_t* px = &d.bytes[i * ch];
        // 1: grey, 2: grey + alpha (alpha ignored), 3/4: RGB(A).
        grey.pixels[i] = (ch >= 3U) ? lumaOf(px) : px[0];
    }
    return grey;
}

}  // namespace

Result<GreyImage> loadGrey8(const std::string& path) {
    Result<detail::DecodedImage> d = decodeFile(path);
    if (!d.ok) {
        return Result<GreyImage>::failure(d.error);
    }
    if (d.value.sixteen_bit) {
        return Result<GreyImage>::failure(path + ": 16-bit image; an 8-bit image is needed here");
    }
    return Result<GreyImage>::success(toGrey(d.value));
}

Result<Grey16Image> loadGrey16(const std::string& path) {
    Result<detail::DecodedImage> d = decodeFile(path);
    if (!d.ok) {
        return Result<Grey16Image>::failure(d.error);
    }
    if (d.value.channels != 1) {
        return Result<Grey16Image>::failure(path + ": " + std::to_string(d.value.channels) +
                                            " channels; a one-channel (grey) image is needed here");
    }
    Grey16Image out(d.value.width, d.value.height);
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        out.pixels[i] = d.value.sixteen_bit ? d.value.words[i] : d.value.bytes[i];
    }
    return Result<Grey16Image>::success(std::move(out));
}

Outcome writePng(const std::string& path, const GreyImage& image) {
    if (image.empty() || (image.channels != 1 && image.channels != 3)) {
        return Outcome::failure(path + ": cannot write an empty image or one with " +
                                std::to_string(image.channels) + " channels as PNG (1 or 3)");
    }
    detail::Bytes png;
    if (!detail::encodePng(image.pixels.data(), image.width, image.height, image.channels, png)) {
        return Outcome::failure(path + ": PNG encoding failed");
    }
    return detail::writeFileBytes(path, png);
}

}  // namespace vtm::ground
