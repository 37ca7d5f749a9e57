// A double as text that reads back to the same bits ("%.17g"): the one formatter of the
// ground's text files (camera models, simulator outputs, panorama stations).
#pragma once

#include <cstdio>
#include <string>

namespace vtm::ground {

inline std::string exactNumber(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}

}  // namespace vtm::ground
