// parseCameraModel: the text form of a camera model (vtm/core/camera_model.hpp,
// docs/camera-models.md). Works on the caller's string_view in place: no heap, no copy
// beyond one number at a time, every loop bounded by the text length.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/text_number.hpp"

namespace vtm {
namespace {

// A number field longer than this is not a number we wrote ("%.17g" needs at most 24).
constexpr std::size_t kMaxNumberChars = 63U;
// A line needs at most key + 3 values; one more field is enough to tell "too many".
constexpr std::size_t kMaxFields = 5U;

constexpr std::uint8_t kPinholeBit = 1U << 0U;
constexpr std::uint8_t kCahvBit = 1U << 1U;
constexpr std::uint8_t kCahvorBit = 1U << 2U;

// The model's numeric fields: which kinds use them and the reasons that name them.
struct FieldSpec {
    std::string_view key;
    std::size_t count;   // numbers on the line after the key
    std::uint8_t kinds;  // kinds that use the field (bit mask)
    const char* bad;     // not `count` finite numbers
    const char* missing;
    const char* foreign;  // given for a kind that does not use it
};

constexpr FieldSpec kFields[] = {
    {"fx_px", 1U, kPinholeBit, "camera model text: fx_px must be one finite number", "camera model text: fx_px missing",
     "camera model text: fx_px is not a field of this kind"},
    {"fy_px", 1U, kPinholeBit, "camera model text: fy_px must be one finite number", "camera model text: fy_px missing",
     "camera model text: fy_px is not a field of this kind"},
    {"cx_px", 1U, kPinholeBit, "camera model text: cx_px must be one finite number", "camera model text: cx_px missing",
     "camera model text: cx_px is not a field of this kind"},
    {"cy_px", 1U, kPinholeBit, "camera model text: cy_px must be one finite number", "camera model text: cy_px missing",
     "camera model text: cy_px is not a field of this kind"},
    {"k1", 1U, kPinholeBit, "camera model text: k1 must be one finite number", "camera model text: k1 missing",
     "camera model text: k1 is not a field of this kind"},
    {"k2", 1U, kPinholeBit, "camera model text: k2 must be one finite number", "camera model text: k2 missing",
     "camera model text: k2 is not a field of this kind"},
    {"k3", 1U, kPinholeBit, "camera model text: k3 must be one finite number", "camera model text: k3 missing",
     "camera model text: k3 is not a field of this kind"},
    {"p1", 1U, kPinholeBit, "camera model text: p1 must be one finite number", "camera model text: p1 missing",
     "camera model text: p1 is not a field of this kind"},
    {"p2", 1U, kPinholeBit, "camera model text: p2 must be one finite number", "camera model text: p2 missing",
     "camera model text: p2 is not a field of this kind"},
    {"C", 3U, kCahvBit | kCahvorBit, "camera model text: C must be three finite numbers", "camera model text: C missing",
     "camera model text: C is not a field of this kind"},
    {"A", 3U, kCahvBit | kCahvorBit, "camera model text: A must be three finite numbers", "camera model text: A missing",
     "camera model text: A is not a field of this kind"},
    {"H", 3U, kCahvBit | kCahvorBit, "camera model text: H must be three finite numbers", "camera model text: H missing",
     "camera model text: H is not a field of this kind"},
    {"V", 3U, kCahvBit | kCahvorBit, "camera model text: V must be three finite numbers", "camera model text: V missing",
     "camera model text: V is not a field of this kind"},
    {"O", 3U, kCahvorBit, "camera model text: O must be three finite numbers", "camera model text: O missing",
     "camera model text: O is not a field of this kind"},
    {"R", 3U, kCahvorBit, "camera model text: R must be three finite numbers", "camera model text: R missing",
     "camera model text: R is not a field of this kind"},
};
constexpr std::size_t kFieldCount = sizeof kFields / sizeof kFields[0];

double* fieldStorage(CameraModel& m, std::size_t index) noexcept {
    // The entries point into `m` for writing: they cannot point to const.
    // cppcheck-suppress constVariable
    double* const storage[kFieldCount] = {&m.fx_px, &m.fy_px, &m.cx_px, &m.cy_px, &m.k1, &m.k2, &m.k3, &m.p1,
                                          &m.p2,    m.c,      m.a,      m.h,      m.v,   m.o,   m.r};
    return storage[index];
}

// One line split at blanks, tabs and '\r' (views into the caller's text).
struct Fields {
    std::string_view field[kMaxFields];
    std::size_t count = 0U;  // kMaxFields means "kMaxFields or more"
};

bool isSeparator(char c) noexcept { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

Fields splitFields(std::string_view line) noexcept {
    Fields f;
    std::size_t i = 0U;
    for (; i < line.size() && f.count < kMaxFields; ++i) {  // bound: line.size()
        if (isSeparator(line[i])) {
            continue;
        }
        const std::size_t start = i;
        for (; i < line.size() && !isSeparator(line[i]); ++i) {  // bound: line.size()
        }
        f.field[f.count] = line.substr(start, i - start);
        ++f.count;
    }
    return f;
}

bool parseFinite(std::string_view field, double& out) noexcept {
    char buffer[kMaxNumberChars + 1U] = {};
    if (field.size() > kMaxNumberChars) {
        return false;
    }
    for (std::size_t i = 0U; i < field.size(); ++i) {
        if (field[i] == '\0') {
            return false;  // a NUL inside the text would end the number early
        }
        buffer[i] = field[i];
    }
    double value = 0.0;
    if (!text::parseReal(buffer, value) || !math::isFinite(value)) {
        return false;
    }
    out = value;
    return true;
}

bool parseSide(std::string_view field, std::uint16_t& out) noexcept {
    char buffer[8] = {};
    if (field.size() >= sizeof buffer) {
        return false;
    }
    for (std::size_t i = 0U; i < field.size(); ++i) {
        buffer[i] = field[i];
    }
    std::uint64_t value = 0U;
    if (!text::parseUnsigned(buffer, 0xFFFFU, value) || value == 0U) {
        return false;
    }
    out = static_cast<std::uint16_t>(value);
    return true;
}

struct ParseState {
    CameraModel model;
    std::int64_t kind_line = 0;  // 0 = not seen
    std::int64_t width_line = 0;
    std::int64_t height_line = 0;
    std::int64_t field_line[kFieldCount] = {};
};

Status corrupt(const char* reason, std::int64_t line) noexcept {
    return Status(StatusCode::kCorruptData, reason, line);
}

Status readKind(const Fields& f, std::int64_t line, ParseState& s) noexcept {
    if (s.kind_line != 0) {
        return corrupt("camera model text: kind given twice", line);
    }
    s.kind_line = line;
    if (f.count == 2U && f.field[1] == "pinhole") {
        s.model.kind = CameraModelKind::kPinholeBrown;
    } else if (f.count == 2U && f.field[1] == "cahv") {
        s.model.kind = CameraModelKind::kCahv;
    } else if (f.count == 2U && f.field[1] == "cahvor") {
        s.model.kind = CameraModelKind::kCahvor;
    } else {
        return corrupt("camera model text: kind must be one of pinhole, cahv, cahvor", line);
    }
    return Status::ok();
}

Status readSide(const Fields& f, std::int64_t line, std::int64_t& seen, const char* twice, const char* bad,
                std::uint16_t& out) noexcept {
    if (seen != 0) {
        return corrupt(twice, line);
    }
    seen = line;
    if (f.count != 2U || !parseSide(f.field[1], out)) {
        return corrupt(bad, line);
    }
    return Status::ok();
}

Status readField(const Fields& f, std::int64_t line, std::size_t index, ParseState& s) noexcept {
    const FieldSpec& spec = kFields[index];
    if (s.field_line[index] != 0) {
        return corrupt("camera model text: field given twice", line);
    }
    s.field_line[index] = line;
    if (f.count != spec.count + 1U) {
        return corrupt(spec.bad, line);
    }
    double* const to = fieldStorage(s.model, index);
    for (std::size_t i = 0U; i < spec.count; ++i) {
        if (!parseFinite(f.field[i + 1U], to[i])) {
            return corrupt(spec.bad, line);
        }
    }
    return Status::ok();
}

Status readLine(const Fields& f, std::int64_t line, ParseState& s) noexcept {
    const std::string_view key = f.field[0];
    if (key == "kind") {
        return readKind(f, line, s);
    }
    if (key == "width_px") {
        return readSide(f, line, s.width_line, "camera model text: width_px given twice",
                        "camera model text: width_px must be one integer 1..65535", s.model.width_px);
    }
    if (key == "height_px") {
        return readSide(f, line, s.height_line, "camera model text: height_px given twice",
                        "camera model text: height_px must be one integer 1..65535", s.model.height_px);
    }
    for (std::size_t i = 0U; i < kFieldCount; ++i) {
        if (key == kFields[i].key) {
            return readField(f, line, i, s);
        }
    }
    return corrupt("camera model text: unknown key", line);
}

std::uint8_t kindBit(CameraModelKind kind) noexcept {
    switch (kind) {
        case CameraModelKind::kPinholeBrown:
            return kPinholeBit;
        case CameraModelKind::kCahv:
            return kCahvBit;
        case CameraModelKind::kCahvor:
            return kCahvorBit;
        case CameraModelKind::kNone:
            break;
    }
    return 0U;
}

// After the last line: kind and size present, every field of the kind and no other.
Status checkComplete(const ParseState& s) noexcept {
    if (s.kind_line == 0) {
        return corrupt("camera model text: kind missing", 0);
    }
    if (s.width_line == 0) {
        return corrupt("camera model text: width_px missing", 0);
    }
    if (s.height_line == 0) {
        return corrupt("camera model text: height_px missing", 0);
    }
    const std::uint8_t bit = kindBit(s.model.kind);
    for (std::size_t i = 0U; i < kFieldCount; ++i) {
        const bool used = (kFields[i].kinds & bit) != 0U;
        if (used && s.field_line[i] == 0) {
            return corrupt(kFields[i].missing, 0);
        }
        if (!used && s.field_line[i] != 0) {
            return corrupt(kFields[i].foreign, s.field_line[i]);
        }
    }
    return Status::ok();
}

bool isHeader(const Fields& f) noexcept {
    return f.count == 2U && f.field[0] == "vtm_camera_model" && f.field[1] == "1";
}

}  // namespace

Status parseCameraModel(std::string_view text, CameraModel& out) noexcept {
    ParseState s;
    std::int64_t line = 0;
    std::size_t pos = 0U;
    // Each pass consumes one line (at least one character): at most text.size() + 1 passes.
    for (std::size_t pass = 0U; pass <= text.size() && pos < text.size(); ++pass) {
        std::size_t end = text.find('\n', pos);
        end = (end == std::string_view::npos) ? text.size() : end;
        const Fields f = splitFields(text.substr(pos, end - pos));
        pos = end + 1U;
        ++line;
        if (line == 1) {
            if (!isHeader(f)) {
                return corrupt("camera model text: first line must be 'vtm_camera_model 1'", line);
            }
            continue;
        }
        if (f.count == 0U || f.field[0][0] == '#') {
            continue;
        }
        VTM_RETURN_IF_ERROR(readLine(f, line, s));
    }
    if (line == 0) {
        return corrupt("camera model text: first line must be 'vtm_camera_model 1'", 1);
    }
    VTM_RETURN_IF_ERROR(checkComplete(s));
    const Status valid = validateCameraModel(s.model);
    if (!valid.isOk()) {
        return corrupt(valid.reason(), 0);
    }
    out = s.model;
    return Status::ok();
}

}  // namespace vtm
