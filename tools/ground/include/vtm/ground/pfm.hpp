// PFM (portable float map), one channel, exactly as the Middlebury stereo evaluation
// writes disparity maps:
//
//   "Pf\n<width> <height>\n-1\n" followed by width * height float32 values,
//   rows from the BOTTOM row of the image to the top, each row left to right.
//
// The sign of the scale gives the byte order of the floats: negative = little endian,
// positive = big endian; its magnitude carries no meaning for disparities. We always
// write little endian ("-1") whatever the host's byte order, and read both. Pixels
// without a value are +inf (Middlebury's convention for "no disparity").
// Colour PFMs ("PF") are refused.
#pragma once

#include <string>
#include <vector>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

// PFM file contents from a one-channel float image (top row first in memory).
std::vector<unsigned char> encodePfm(const FloatImage& image);
// Image from PFM bytes; `name` (usually the path) goes into error messages.
Result<FloatImage> decodePfm(const std::vector<unsigned char>& bytes, const std::string& name);

Result<FloatImage> readPfm(const std::string& path);
Outcome writePfm(const std::string& path, const FloatImage& image);

// True when the file starts with a PFM signature ("Pf" or "PF" and white space).
bool looksLikePfm(const std::string& path);

}  // namespace vtm::ground
