// The one translation unit that compiles stb_image's implementation (configured by
// stb_config.hpp). stb_image is third-party C written for many compilers: it does not
// follow our -Wconversion/-Wsign-conversion/-Wold-style-cast policy, so this file alone
// is compiled with warnings off (hal/file/CMakeLists.txt). Our own code around it
// (png_decode.cpp) keeps the full flight warning set.
#include "stb_config.hpp"

#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
