#include "pose_log.hpp"

#include "text_lines.hpp"

namespace vtm::hal::detail {
namespace {

constexpr TextFileReasons kReasons{
    "pose log: cannot open file", "pose log: read failed", "pose log: line longer than kMaxLineChars (2047)",
    "pose log: more than kMaxTextLines (65536) lines", "pose log: NUL byte in a line"};

// Fields of a pose line: timestamp, position (3), attitude (4), then the covariance as
// 6 diagonal variances or 36 row-major values.
constexpr std::size_t kFieldsWithDiagonal = 1U + 3U + 4U + 6U;
constexpr std::size_t kFieldsWithFullCovariance = 1U + 3U + 4U + 36U;

Status readFirstLine(TextFile& file) noexcept {
    const Status got = file.nextLine();
    if (!got.isOk() && got.code() != StatusCode::kNoData) {
        return got;
    }
    const LineTokens t = splitLine(file.line());
    if (!got.isOk() || t.count != 2U || !textEquals(t.token[0], "vtm-poses")) {
        return Status(StatusCode::kCorruptData, "pose log: first line must be 'vtm-poses 1'", 1);
    }
    if (!textEquals(t.token[1], "1")) {
        return Status(StatusCode::kUnsupported, "pose log: version other than 1", 1);
    }
    return Status::ok();
}

Status readPose(const LineTokens& t, std::int64_t line, PoseEstimate& p) noexcept {
    if (t.too_many || (t.count != kFieldsWithDiagonal && t.count != kFieldsWithFullCovariance)) {
        return Status(StatusCode::kCorruptData,
                      "pose log: a pose line needs 14 or 44 fields (timestamp_ns, x y z, qw qx qy qz, "
                      "6 variances or 36 covariances)",
                      line);
    }
    if (!parseUnsigned(t.token[0], ~std::uint64_t{0}, p.timestamp_ns)) {
        return Status(StatusCode::kCorruptData, "pose log: timestamp_ns is not an integer 0..18446744073709551615",
                      line);
    }
    double v[kFieldsWithFullCovariance - 1U] = {};
    for (std::size_t i = 1U; i < t.count; ++i) {
        if (!parseReal(t.token[i], v[i - 1U])) {
            return Status(StatusCode::kCorruptData, "pose log: pose value is not a number", line);
        }
    }
    for (std::size_t i = 0U; i < 3U; ++i) {
        p.position_m[i] = v[i];
    }
    for (std::size_t i = 0U; i < 4U; ++i) {
        p.attitude_wxyz[i] = v[3U + i];
    }
    for (std::size_t i = 0U; i < 36U; ++i) {
        p.covariance[i] = (t.count == kFieldsWithFullCovariance) ? v[7U + i] : 0.0;
    }
    if (t.count == kFieldsWithDiagonal) {
        for (std::size_t i = 0U; i < 6U; ++i) {
            p.covariance[i * 7U] = v[7U + i];
        }
    }
    // The same check every driver applies before handing a pose out; its reason names the
    // field, the line number goes into the detail.
    const Status valid = validatePose(p);
    return valid.isOk() ? valid : Status(valid.code(), valid.reason(), line);
}

Status appendPose(const PoseEstimate& p, std::int64_t line, FixedVector<PoseEstimate, file_limits::kMaxPoses>& out) noexcept {
    if (!out.empty() && p.timestamp_ns <= out[out.size() - 1U].timestamp_ns) {
        return Status(StatusCode::kOutOfOrder, "pose log: timestamp_ns not greater than the previous pose's", line);
    }
    if (!out.push_back(p)) {
        return Status(StatusCode::kUnsupported, "pose log: more than kMaxPoses (4096) poses", line);
    }
    return Status::ok();
}

}  // namespace

Status loadPoseLog(const char* path, FixedVector<PoseEstimate, file_limits::kMaxPoses>& out) noexcept {
    out.clear();
    TextFile file(kReasons);
    VTM_RETURN_IF_ERROR(file.open(path));
    VTM_RETURN_IF_ERROR(readFirstLine(file));
    // TextFile ends the file after kMaxTextLines lines, which bounds this loop.
    for (std::size_t n = 1U; n <= file_limits::kMaxTextLines; ++n) {
        const Status got = file.nextLine();
        if (got.code() == StatusCode::kNoData) {
            break;
        }
        VTM_RETURN_IF_ERROR(got);
        const LineTokens t = splitLine(file.line());
        if (!t.too_many && isBlankOrComment(t)) {
            continue;
        }
        PoseEstimate p;
        VTM_RETURN_IF_ERROR(readPose(t, file.lineNumber(), p));
        VTM_RETURN_IF_ERROR(appendPose(p, file.lineNumber(), out));
    }
    if (out.empty()) {
        return Status(StatusCode::kNoData, "pose log: no pose line", file.lineNumber() + 1);
    }
    return Status::ok();
}

}  // namespace vtm::hal::detail
