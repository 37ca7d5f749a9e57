// Reading and writing ordinary image files (PNG, PGM/PPM, JPEG, BMP) on the ground, via
// stb_image / stb_image_write (Debian libstb-dev, public domain).
#pragma once

#include <string>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

// An 8-bit grey image from a PNG, binary PGM/PPM (P5/P6), JPEG or BMP file. Colour is
// converted with the integer BT.601 luma (77 R + 150 G + 29 B + 128) >> 8 (weights sum
// to 256), the same formula as the flight playback driver (hal/file), so ground and
// flight see the same grey levels; alpha is ignored. 16-bit files are refused (the
// stereo matcher takes 8-bit images; say so rather than drop bits silently).
Result<GreyImage> loadGrey8(const std::string& path);

// The raw grey levels of a one-channel 8- or 16-bit PNG or PGM, unscaled (an 8-bit 200
// stays 200): for ground-truth disparity maps whose levels are disparity * scale.
// Colour files are refused (ground truth has one channel).
Result<Grey16Image> loadGrey16(const std::string& path);

// Writes an 8-bit grey (channels 1) or RGB (channels 3) image as PNG.
Outcome writePng(const std::string& path, const GreyImage& image);

}  // namespace vtm::ground
