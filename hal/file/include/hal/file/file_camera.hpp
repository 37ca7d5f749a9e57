// hal::Camera playing back a recording: frames listed in a text manifest
// (hal/file/frame_manifest.hpp, docs/hal-file.md), each a binary PGM (P5) or a PNG file.
// The desk, HIL and regression runs feed recorded data through the same interface as the
// simulator and the flight cameras.
//
// Memory: the manifest is parsed at init() into this object (fixed capacity, about
// 150 KiB: declare it static or inside a statically allocated owner); frames are read and
// decoded in two static buffers shared by every FileCamera of the program
// (file_limits::kMaxFrameFileBytes + kPngPoolBytes). Nothing allocates, at init or after.
// One capture at a time per program: the shared buffers are not guarded against threads.
#pragma once

#include <cstdint>

#include "hal/camera.hpp"
#include "hal/file/file_limits.hpp"
#include "hal/file/frame_manifest.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

namespace detail {
class FrameTarget;  // the output buffer as the decoders see it (src/frame_target.hpp)
}  // namespace detail

// A final driver, statically allocated and never deleted through hal::Camera (whose
// destructor is protected): its implicit public destructor needs no virtual.
class FileCamera final : public Camera {
public:
    struct Config {
        // The manifest file, NUL-terminated, 1..kMaxPathChars (255) characters. Frame
        // paths in it are relative to its directory. Only read during init().
        const char* manifest_path = nullptr;

        // kInvalidConfig naming the field when it is out of range.
        [[nodiscard]] Status validate() const noexcept;
    };

    FileCamera() noexcept = default;

    // Validates the config and loads the manifest (loadFrameManifest: its errors, with the
    // line number in detail()). On failure the camera stays uninitialised.
    [[nodiscard]] Status init(const Config& config) noexcept;

    [[nodiscard]] Status describe(CameraDescription& out) const noexcept override;

    // The next frame of the manifest, for a camera of bit_depth 8 (else kUnsupported:
    // use capture16). `out` must be exactly width_px x height_px (kSizeMismatch).
    // kNoData at the end of the recording. A frame whose file is missing or damaged gives
    // kIoError / kCorruptData / kUnsupported / kSizeMismatch with the reason, and playback
    // moves on to the next frame. Buffer errors and kUnsupported do not consume a frame.
    [[nodiscard]] Status capture(const ImageView<std::uint8_t>& out, FrameInfo& info) noexcept override;

    // The same for a camera of bit_depth 9..16 (else kUnsupported: use capture). Samples
    // are delivered as stored in the file and must be <= 2^bit_depth - 1.
    [[nodiscard]] Status capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) noexcept override;

    // Plays the recording again from its first frame.
    void rewind() noexcept { next_frame_ = 0U; }
    // Frames in the manifest, and the index of the one the next capture plays.
    [[nodiscard]] std::size_t frameCount() const noexcept { return manifest_.frames.size(); }
    [[nodiscard]] std::size_t nextFrameIndex() const noexcept { return next_frame_; }

    // Most bytes of the shared PNG decoder pool (file_limits::kPngPoolBytes) in use at once
    // during any PNG decode so far in this program / during the most recent PNG decode.
    // For memory budgets and for the test of the pool formula.
    [[nodiscard]] static std::size_t decoderPoolHighWaterBytes() noexcept;
    [[nodiscard]] static std::size_t decoderPoolLastDecodeBytes() noexcept;

private:
    template <typename Pixel>
    [[nodiscard]] Status checkOutput(const ImageView<Pixel>& out) const noexcept;
    [[nodiscard]] Status playNext(const detail::FrameTarget& target, FrameInfo& info) noexcept;
    [[nodiscard]] Status composePath(const FrameRecord& frame) noexcept;

    FrameManifest manifest_{};
    std::size_t next_frame_ = 0U;
    bool initialized_ = false;
    // "<directory>/<frame path>" of the frame being read.
    char frame_path_[file_limits::kMaxPathChars + 1U + file_limits::kMaxFramePathChars + 1U] = {};
};

}  // namespace vtm::hal
