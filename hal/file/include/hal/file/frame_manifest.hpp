// The frame manifest of a recording: which camera, which frames, in which files.
// Format (docs/hal-file.md, "Frame manifest"):
//
//   vtm-frames 1
//   # comment lines and blank lines anywhere
//   camera_id 2
//   width_px 1024
//   height_px 1024
//   bit_depth 12
//   model pinhole 800 800 511.5 511.5 -0.1 0.01 0 0 0      (optional)
//   frame 17 1000000000 2500 frames/left_000017.pgm
//
// loadFrameManifest() parses it into fixed-capacity storage at init; nothing allocates.
#pragma once

#include <cstdint>

#include "hal/camera.hpp"
#include "hal/file/file_limits.hpp"
#include "vtm/core/fixed_vector.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

// One `frame` line.
struct FrameRecord {
    std::uint32_t sequence = 0U;      // strictly increasing along the manifest (gaps allowed)
    std::uint64_t timestamp_ns = 0U;  // strictly increasing along the manifest
    std::uint32_t exposure_us = 0U;
    char path[file_limits::kMaxFramePathChars + 1U] = {};  // relative to the manifest's directory
};

struct FrameManifest {
    CameraDescription camera{};
    FixedVector<FrameRecord, file_limits::kMaxFrames> frames{};
    // Directory of the manifest file ("." when the path has no '/'), without a trailing '/'.
    char directory[file_limits::kMaxPathChars + 1U] = {};
};

// Parses the manifest at `path` (at most kMaxPathChars characters) into `out`, which is
// cleared first. Errors name the problem in reason() and carry the 1-based line number
// in detail() (errno for kIoError): kIoError (cannot open/read), kCorruptData (malformed
// line or value), kUnsupported (beyond file_limits, or a version other than 1),
// kOutOfOrder (frame sequence or timestamp not increasing), kNoData (no frame line).
[[nodiscard]] Status loadFrameManifest(const char* path, FrameManifest& out) noexcept;

}  // namespace vtm::hal
