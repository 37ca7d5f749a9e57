#include "hal/file/frame_manifest.hpp"

#include "text_lines.hpp"

namespace vtm::hal {
namespace {

using detail::LineTokens;
using detail::parseReal;
using detail::parseUnsigned;
using detail::textEquals;
using file_limits::kMaxFrameHeightPx;
using file_limits::kMaxFrameWidthPx;

constexpr detail::TextFileReasons kReasons{
    "manifest: cannot open file", "manifest: read failed", "manifest: line longer than kMaxLineChars (2047)",
    "manifest: more than kMaxTextLines (65536) lines", "manifest: NUL byte in a line"};

// Which header keys have been seen; all but `model` are required before the first frame.
struct HeaderSeen {
    bool camera_id = false;
    bool width = false;
    bool height = false;
    bool bit_depth = false;
    bool model = false;
    std::int64_t model_line = 0;  // where the model was given, for its validation error
};

Status corrupt(const char* reason, std::int64_t line) noexcept {
    return Status(StatusCode::kCorruptData, reason, line);
}

// "<key> <unsigned integer in [lo, hi]>".
bool readKeyValue(const LineTokens& t, std::uint64_t lo, std::uint64_t hi, std::uint64_t& value) noexcept {
    return t.count == 2U && parseUnsigned(t.token[1], hi, value) && value >= lo;
}

// A frame side: a positive integer, within the driver's capacity.
Status readSide(const LineTokens& t, std::int64_t line, std::int32_t max_px, const char* bad, const char* too_big,
                std::int32_t& out) noexcept {
    std::uint64_t v = 0U;
    if (!readKeyValue(t, 1U, 0xFFFFFFFFU, v)) {
        return corrupt(bad, line);
    }
    if (v > static_cast<std::uint64_t>(max_px)) {
        return Status(StatusCode::kUnsupported, too_big, line);
    }
    out = static_cast<std::int32_t>(v);
    return Status::ok();
}

void copyVector(const double* from, double* to) noexcept {
    for (std::size_t i = 0U; i < 3U; ++i) {
        to[i] = from[i];
    }
}

// "model pinhole fx fy cx cy k1 k2 k3 p1 p2" | "model cahv C A H V" | "model cahvor C A H V O R".
Status readModel(const LineTokens& t, std::int64_t line, CameraModel& m) noexcept {
    double v[18] = {};
    std::size_t needed = 0U;
    if (t.count >= 2U && textEquals(t.token[1], "pinhole")) {
        m.kind = CameraModelKind::kPinholeBrown;
        needed = 9U;
    } else if (t.count >= 2U && textEquals(t.token[1], "cahv")) {
        m.kind = CameraModelKind::kCahv;
        needed = 12U;
    } else if (t.count >= 2U && textEquals(t.token[1], "cahvor")) {
        m.kind = CameraModelKind::kCahvor;
        needed = 18U;
    } else {
        return corrupt("manifest: model kind must be pinhole, cahv or cahvor", line);
    }
    if (t.count != needed + 2U) {
        return corrupt("manifest: model has the wrong number of values (pinhole 9, cahv 12, cahvor 18)", line);
    }
    for (std::size_t i = 0U; i < needed; ++i) {
        // v - v == 0 exactly for finite v; NaN and infinities give NaN.
        if (!parseReal(t.token[i + 2U], v[i]) || !(v[i] - v[i] == 0.0)) {
            return corrupt("manifest: model value is not a finite number", line);
        }
    }
    if (m.kind == CameraModelKind::kPinholeBrown) {
        double* const fields[9] = {&m.fx_px, &m.fy_px, &m.cx_px, &m.cy_px, &m.k1, &m.k2, &m.k3, &m.p1, &m.p2};
        for (std::size_t i = 0U; i < 9U; ++i) {
            *fields[i] = v[i];
        }
        return Status::ok();
    }
    double* const vectors[6] = {m.c, m.a, m.h, m.v, m.o, m.r};
    for (std::size_t k = 0U; k < needed / 3U; ++k) {
        copyVector(&v[3U * k], vectors[k]);
    }
    // The model's own rules (fx > 0, unit A and O, invertible distortion, ...) need the
    // image size: validateCameraModel() runs in finishHeader().
    return Status::ok();
}

// Each header key at most once, and only before the first frame line.
Status markSeen(bool& seen, std::int64_t line) noexcept {
    if (seen) {
        return corrupt("manifest: key given twice", line);
    }
    seen = true;
    return Status::ok();
}

Status readHeaderLine(const LineTokens& t, std::int64_t line, HeaderSeen& seen, CameraDescription& cam) noexcept {
    const char* key = t.token[0];
    std::uint64_t v = 0U;
    if (textEquals(key, "camera_id")) {
        VTM_RETURN_IF_ERROR(markSeen(seen.camera_id, line));
        if (!readKeyValue(t, 0U, 255U, v)) {
            return corrupt("manifest: camera_id must be one integer 0..255", line);
        }
        cam.camera_id = static_cast<std::uint8_t>(v);
    } else if (textEquals(key, "width_px")) {
        VTM_RETURN_IF_ERROR(markSeen(seen.width, line));
        return readSide(t, line, kMaxFrameWidthPx, "manifest: width_px must be one positive integer",
                        "manifest: width_px above kMaxFrameWidthPx (4096)", cam.width_px);
    } else if (textEquals(key, "height_px")) {
        VTM_RETURN_IF_ERROR(markSeen(seen.height, line));
        return readSide(t, line, kMaxFrameHeightPx, "manifest: height_px must be one positive integer",
                        "manifest: height_px above kMaxFrameHeightPx (4096)", cam.height_px);
    } else if (textEquals(key, "bit_depth")) {
        VTM_RETURN_IF_ERROR(markSeen(seen.bit_depth, line));
        if (!readKeyValue(t, 8U, 16U, v)) {
            return corrupt("manifest: bit_depth must be one integer 8..16", line);
        }
        cam.bit_depth = static_cast<std::uint8_t>(v);
    } else if (textEquals(key, "model")) {
        VTM_RETURN_IF_ERROR(markSeen(seen.model, line));
        seen.model_line = line;
        return readModel(t, line, cam.model);
    } else {
        return corrupt("manifest: unknown key", line);
    }
    return Status::ok();
}

// Called at the first frame line (or the end of the file): the required keys are there
// and the frame fits the driver's buffers.
Status finishHeader(const HeaderSeen& seen, std::int64_t line, CameraDescription& cam) noexcept {
    if (!seen.camera_id) {
        return corrupt("manifest: camera_id missing before the first frame line", line);
    }
    if (!seen.width) {
        return corrupt("manifest: width_px missing before the first frame line", line);
    }
    if (!seen.height) {
        return corrupt("manifest: height_px missing before the first frame line", line);
    }
    if (!seen.bit_depth) {
        return corrupt("manifest: bit_depth missing before the first frame line", line);
    }
    const auto pixels = static_cast<std::size_t>(cam.width_px) * static_cast<std::size_t>(cam.height_px);
    if (pixels > file_limits::kMaxFramePixels) {
        return Status(StatusCode::kUnsupported, "manifest: width_px * height_px above kMaxFramePixels (1048576)", line);
    }
    cam.model.width_px = static_cast<std::uint16_t>(cam.width_px);
    cam.model.height_px = static_cast<std::uint16_t>(cam.height_px);
    if (seen.model) {
        // One set of rules for every camera model (vtm/core/camera_model.hpp): its reason
        // names the field; the manifest reports it as corrupt data on the model's line.
        const Status valid = validateCameraModel(cam.model);
        if (!valid.isOk()) {
            return corrupt(valid.reason(), seen.model_line);
        }
    }
    return Status::ok();
}

Status readFrameFields(const LineTokens& t, std::int64_t line, FrameRecord& r) noexcept {
    std::uint64_t v = 0U;
    if (t.count != 5U) {
        return corrupt("manifest: frame line needs: frame <sequence> <timestamp_ns> <exposure_us> <path>", line);
    }
    if (!parseUnsigned(t.token[1], 0xFFFFFFFFU, v)) {
        return corrupt("manifest: frame sequence is not an integer 0..4294967295", line);
    }
    r.sequence = static_cast<std::uint32_t>(v);
    if (!parseUnsigned(t.token[2], ~std::uint64_t{0}, r.timestamp_ns)) {
        return corrupt("manifest: frame timestamp_ns is not an integer 0..18446744073709551615", line);
    }
    if (!parseUnsigned(t.token[3], 0xFFFFFFFFU, v)) {
        return corrupt("manifest: frame exposure_us is not an integer 0..4294967295", line);
    }
    r.exposure_us = static_cast<std::uint32_t>(v);
    const char* path = t.token[4];
    if (path[0] == '/') {
        return corrupt("manifest: frame path is absolute (must be relative to the manifest)", line);
    }
    const std::size_t length = detail::boundedLength(path, file_limits::kMaxFramePathChars);
    if (length > file_limits::kMaxFramePathChars) {
        return Status(StatusCode::kUnsupported, "manifest: frame path longer than kMaxFramePathChars (127)", line);
    }
    for (std::size_t i = 0U; i <= length; ++i) {
        r.path[i] = path[i];  // the NUL included
    }
    return Status::ok();
}


// Appends a frame after checking its order against the previous one.
Status appendFrame(const FrameRecord& r, std::int64_t line, FrameManifest& m) noexcept {
    if (!m.frames.empty()) {
        const FrameRecord& previous = m.frames[m.frames.size() - 1U];
        if (r.sequence <= previous.sequence) {
            return Status(StatusCode::kOutOfOrder, "manifest: frame sequence not greater than the previous frame's",
                          line);
        }
        if (r.timestamp_ns <= previous.timestamp_ns) {
            return Status(StatusCode::kOutOfOrder,
                          "manifest: frame timestamp_ns not greater than the previous frame's", line);
        }
    }
    if (!m.frames.push_back(r)) {
        return Status(StatusCode::kUnsupported, "manifest: more than kMaxFrames (1024) frame lines", line);
    }
    return Status::ok();
}

// directory = path up to its last '/' ("." when there is none, "/" for a file in the root).
void setDirectory(const char* path, std::size_t length, FrameManifest& m) noexcept {
    std::size_t cut = length;
    for (std::size_t i = 0U; i < length; ++i) {
        if (path[i] == '/') {
            cut = i;
        }
    }
    if (cut == length) {
        m.directory[0] = '.';
        m.directory[1] = '\0';
        return;
    }
    const std::size_t keep = (cut == 0U) ? 1U : cut;
    for (std::size_t i = 0U; i < keep; ++i) {
        m.directory[i] = path[i];
    }
    m.directory[keep] = '\0';
}

Status readFirstLine(detail::TextFile& file) noexcept {
    const Status got = file.nextLine();
    if (!got.isOk() && got.code() != StatusCode::kNoData) {
        return got;
    }
    const LineTokens t = detail::splitLine(file.line());
    if (!got.isOk() || t.count != 2U || !textEquals(t.token[0], "vtm-frames")) {
        return corrupt("manifest: first line must be 'vtm-frames 1'", 1);
    }
    if (!textEquals(t.token[1], "1")) {
        return Status(StatusCode::kUnsupported, "manifest: version other than 1", 1);
    }
    return Status::ok();
}

// One line after the first: a header key before the first frame, a frame line after.
Status readLine(const LineTokens& t, std::int64_t line, HeaderSeen& seen, bool& in_frames, FrameManifest& m) noexcept {
    if (t.too_many) {
        return corrupt("manifest: line has more than kMaxLineTokens (48) fields", line);
    }
    if (detail::isBlankOrComment(t)) {
        return Status::ok();
    }
    if (!textEquals(t.token[0], "frame")) {
        if (in_frames) {
            return corrupt("manifest: header key after the first frame line", line);
        }
        return readHeaderLine(t, line, seen, m.camera);
    }
    if (!in_frames) {
        VTM_RETURN_IF_ERROR(finishHeader(seen, line, m.camera));
        in_frames = true;
    }
    FrameRecord r;
    VTM_RETURN_IF_ERROR(readFrameFields(t, line, r));
    return appendFrame(r, line, m);
}

}  // namespace

Status loadFrameManifest(const char* path, FrameManifest& out) noexcept {
    out.camera = CameraDescription{};
    out.frames.clear();
    const std::size_t length = detail::boundedLength(path, file_limits::kMaxPathChars);
    if (length > file_limits::kMaxPathChars) {
        return Status(StatusCode::kInvalidArgument, "manifest: path longer than kMaxPathChars (255)");
    }
    setDirectory(path, length, out);
    detail::TextFile file(kReasons);
    VTM_RETURN_IF_ERROR(file.open(path));
    VTM_RETURN_IF_ERROR(readFirstLine(file));
    HeaderSeen seen;
    bool in_frames = false;
    // TextFile ends the file after kMaxTextLines lines, which bounds this loop.
    for (std::size_t n = 1U; n <= file_limits::kMaxTextLines; ++n) {
        const Status got = file.nextLine();
        if (got.code() == StatusCode::kNoData) {
            break;
        }
        VTM_RETURN_IF_ERROR(got);
        const LineTokens t = detail::splitLine(file.line());
        VTM_RETURN_IF_ERROR(readLine(t, file.lineNumber(), seen, in_frames, out));
    }
    if (!in_frames) {
        VTM_RETURN_IF_ERROR(finishHeader(seen, file.lineNumber() + 1, out.camera));
        return Status(StatusCode::kNoData, "manifest: no frame line", file.lineNumber() + 1);
    }
    return Status::ok();
}

}  // namespace vtm::hal
