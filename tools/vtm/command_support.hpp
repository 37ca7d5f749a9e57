// What every vtm command shares: the one way it reports a failure, and its wall clock.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "vtm/core/math.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::tools {

constexpr double kDegPerRad = 180.0 / math::kPi;

// Prints "vtm COMMAND: MESSAGE" on stderr and returns `code` (an exit code of
// vtm/ground/exit_codes.hpp), so a command ends with `return failCommand(...)`.
inline int failCommand(const char* command, int code, const std::string& message) {
    std::fprintf(stderr, "vtm %s: %s\n", command, message.c_str());
    return code;
}

// Seconds of wall time since `t0`, for the timings a command prints.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// "WIDTHxHEIGHT" of an image, for messages about sizes.
inline std::string sizeText(const ground::GreyImage& img) {
    return std::to_string(img.width) + "x" + std::to_string(img.height);
}

}  // namespace vtm::tools
