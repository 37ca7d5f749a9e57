// A decoded image file before conversion: samples as stored, any channel count.
#pragma once

#include <cstdint>
#include <vector>

namespace vtm::ground::detail {

struct DecodedImage {
    int width = 0;
    int height = 0;
    int channels = 0;                  // as stored in the file: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
    bool sixteen_bit = false;          // samples in `words`, else in `bytes`
    std::vector<std::uint8_t> bytes;   // width * height * channels, rows from the top
    std::vector<std::uint16_t> words;
};

}  // namespace vtm::ground::detail
