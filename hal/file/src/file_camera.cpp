#include "hal/file/file_camera.hpp"

#include "file_bytes.hpp"
#include "frame_target.hpp"
#include "pgm_decode.hpp"
#include "png_decode.hpp"
#include "text_lines.hpp"

namespace vtm::hal {
namespace {

using file_limits::kMaxFrameFileBytes;

// The bytes of the frame file being decoded. Static and shared by every FileCamera: one
// frame is decoded at a time, and a per-camera copy would multiply the largest buffer.
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the driver's static buffer
alignas(16) std::uint8_t g_frame_file[kMaxFrameFileBytes];

// The format is told by the file's first bytes, not by its name.
Status decodeFrame(const std::uint8_t* bytes, std::size_t size, const detail::FrameTarget& target) noexcept {
    if (detail::hasPngSignature(bytes, size)) {
        return detail::decodePng(bytes, size, target);
    }
    if (size >= 2U && bytes[0] == 'P' && bytes[1] == '5') {
        return detail::decodePgm(bytes, size, target);
    }
    return Status(StatusCode::kCorruptData, "frame: not a binary PGM (P5) or PNG file", static_cast<std::int64_t>(size));
}

// Copies text[0, length) to out[at...]; returns the position after it.
std::size_t appendText(char* out, std::size_t at, const char* text, std::size_t length) noexcept {
    for (std::size_t i = 0U; i < length; ++i) {
        out[at + i] = text[i];
    }
    return at + length;
}

}  // namespace

Status FileCamera::Config::validate() const noexcept {
    if (manifest_path == nullptr) {
        return Status(StatusCode::kInvalidConfig, "FileCamera::Config: manifest_path is null");
    }
    const std::size_t length = detail::boundedLength(manifest_path, file_limits::kMaxPathChars);
    if (length == 0U) {
        return Status(StatusCode::kInvalidConfig, "FileCamera::Config: manifest_path is empty");
    }
    if (length > file_limits::kMaxPathChars) {
        return Status(StatusCode::kInvalidConfig, "FileCamera::Config: manifest_path longer than kMaxPathChars (255)",
                      static_cast<std::int64_t>(length));
    }
    return Status::ok();
}

Status FileCamera::init(const Config& config) noexcept {
    initialized_ = false;
    next_frame_ = 0U;
    VTM_RETURN_IF_ERROR(config.validate());
    VTM_RETURN_IF_ERROR(loadFrameManifest(config.manifest_path, manifest_));
    initialized_ = true;
    return Status::ok();
}

Status FileCamera::describe(CameraDescription& out) const noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "FileCamera: describe before a successful init()");
    }
    out = manifest_.camera;
    return Status::ok();
}

template <typename Pixel>
Status FileCamera::checkOutput(const ImageView<Pixel>& out) const noexcept {
    if (!out.valid()) {
        return Status(StatusCode::kInvalidArgument, "FileCamera: output view is empty or malformed");
    }
    const CameraDescription& cam = manifest_.camera;
    if (!out.sameSize(cam.width_px, cam.height_px)) {
        return Status(StatusCode::kSizeMismatch, "FileCamera: output buffer size differs from the camera's",
                      out.width() != cam.width_px ? out.width() : out.height());
    }
    return Status::ok();
}

Status FileCamera::capture(const ImageView<std::uint8_t>& out, FrameInfo& info) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "FileCamera: capture before a successful init()");
    }
    if (manifest_.camera.bit_depth > 8U) {
        return Status(StatusCode::kUnsupported, "FileCamera: camera has more than 8 bits per pixel: use capture16",
                      manifest_.camera.bit_depth);
    }
    VTM_RETURN_IF_ERROR(checkOutput(out));
    return playNext(detail::FrameTarget(out), info);
}

Status FileCamera::capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "FileCamera: capture16 before a successful init()");
    }
    if (manifest_.camera.bit_depth <= 8U) {
        return Status(StatusCode::kUnsupported, "FileCamera: camera has 8 bits per pixel: use capture",
                      manifest_.camera.bit_depth);
    }
    VTM_RETURN_IF_ERROR(checkOutput(out));
    return playNext(detail::FrameTarget(out, manifest_.camera.bit_depth), info);
}

std::size_t FileCamera::decoderPoolHighWaterBytes() noexcept { return detail::pngPoolHighWaterBytes(); }
std::size_t FileCamera::decoderPoolLastDecodeBytes() noexcept { return detail::pngPoolLastDecodeBytes(); }

Status FileCamera::composePath(const FrameRecord& frame) noexcept {
    // Both parts were length-checked at init; frame_path_ holds the longest of each.
    const std::size_t dir_length = detail::boundedLength(manifest_.directory, file_limits::kMaxPathChars);
    const std::size_t rel_length = detail::boundedLength(frame.path, file_limits::kMaxFramePathChars);
    VTM_ASSERT(dir_length <= file_limits::kMaxPathChars && rel_length <= file_limits::kMaxFramePathChars,
               static_cast<std::int64_t>(dir_length), static_cast<std::int64_t>(rel_length));
    if (dir_length > file_limits::kMaxPathChars || rel_length > file_limits::kMaxFramePathChars) {
        return Status(StatusCode::kInvalidArgument, "FileCamera: frame path too long");
    }
    std::size_t at = appendText(frame_path_, 0U, manifest_.directory, dir_length);
    at = appendText(frame_path_, at, "/", 1U);
    at = appendText(frame_path_, at, frame.path, rel_length);
    frame_path_[at] = '\0';
    return Status::ok();
}

Status FileCamera::playNext(const detail::FrameTarget& target, FrameInfo& info) noexcept {
    if (next_frame_ >= manifest_.frames.size()) {
        return Status(StatusCode::kNoData, "FileCamera: end of the recording",
                      static_cast<std::int64_t>(manifest_.frames.size()));
    }
    const FrameRecord& frame = manifest_.frames[next_frame_];
    // Consumed whatever happens next: a missing or damaged file is reported once and the
    // following capture plays the following frame, as a camera that dropped one would.
    ++next_frame_;
    VTM_RETURN_IF_ERROR(composePath(frame));
    std::size_t size = 0U;
    VTM_RETURN_IF_ERROR(detail::readWholeFile(frame_path_, g_frame_file, kMaxFrameFileBytes, size));
    VTM_RETURN_IF_ERROR(decodeFrame(g_frame_file, size, target));
    const CameraDescription& cam = manifest_.camera;
    info.sequence = frame.sequence;
    info.timestamp_ns = frame.timestamp_ns;
    info.exposure_us = frame.exposure_us;
    info.camera_id = cam.camera_id;
    info.bit_depth = cam.bit_depth;
    info.width_px = cam.width_px;
    info.height_px = cam.height_px;
    return Status::ok();
}

}  // namespace vtm::hal
