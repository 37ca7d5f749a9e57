// Reading and writing one table key's value (scenario_values.hpp).
#include "scenario_values.hpp"

#include <cstdlib>
#include <cstring>

#include "vtm/core/math.hpp"

namespace vtm::sim::detail {
namespace {

constexpr std::size_t kMaxNumberChars = 63U;

// The token as a NUL-terminated copy, or false if it does not fit.
bool copyToken(std::string_view token, char (&buffer)[kMaxNumberChars + 1U]) noexcept {
    if (token.empty() || token.size() > kMaxNumberChars) {
        return false;
    }
    std::memcpy(buffer, token.data(), token.size());
    buffer[token.size()] = '\0';
    return true;
}

bool parseInteger(std::string_view token, bool allow_negative, std::uint64_t& magnitude, bool& negative) noexcept {
    negative = false;
    std::size_t i = 0U;
    if (allow_negative && !token.empty() && token[0] == '-') {
        negative = true;
        i = 1U;
    }
    if (i >= token.size() || token.size() - i > 20U) {
        return false;
    }
    magnitude = 0U;
    for (; i < token.size(); ++i) {  // bound: at most 20 digits (checked above)
        const char c = token[i];
        if (c < '0' || c > '9') {
            return false;
        }
        const auto digit = static_cast<std::uint64_t>(c - '0');
        if (magnitude > (UINT64_MAX - digit) / 10U) {
            return false;
        }
        magnitude = magnitude * 10U + digit;
    }
    return true;
}

bool validNameChar(char c) noexcept {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

template <typename Enum>
struct WordValue {
    std::string_view word;
    Enum value;
};

template <typename Enum, std::size_t N>
bool parseWord(std::string_view token, const WordValue<Enum> (&words)[N], Enum& out) noexcept {
    for (const WordValue<Enum>& w : words) {  // bound: N table entries
        if (w.word == token) {
            out = w.value;
            return true;
        }
    }
    return false;
}

constexpr WordValue<ScenarioKind> kKindWords[] = {
    {"rover_pair", ScenarioKind::kRoverPair}, {"descent", ScenarioKind::kDescent},
    {"traverse", ScenarioKind::kTraverse},    {"panorama", ScenarioKind::kPanorama}};
constexpr WordValue<CameraModelKind> kModelWords[] = {
    {"pinhole", CameraModelKind::kPinholeBrown}, {"cahv", CameraModelKind::kCahv}, {"cahvor", CameraModelKind::kCahvor}};
constexpr WordValue<TerrainKind> kTerrainWords[] = {
    {"mars", TerrainKind::kMars}, {"plane", TerrainKind::kPlane}, {"dome", TerrainKind::kDome}};
constexpr WordValue<OrbitalModality> kModalityWords[] = {
    {"visible", OrbitalModality::kVisible}, {"thermal", OrbitalModality::kThermal}};
constexpr WordValue<bool> kBoolWords[] = {{"true", true}, {"false", false}};

bool setName(std::string_view token, char* name) noexcept {
    if (token.empty() || token.size() > kMaxScenarioNameChars) {
        return false;
    }
    for (const char c : token) {  // bound: <= kMaxScenarioNameChars characters
        if (!validNameChar(c)) {
            return false;
        }
    }
    std::memcpy(name, token.data(), token.size());
    name[token.size()] = '\0';
    return true;
}

bool inRange(const KeySpec& spec, double value) noexcept { return value >= spec.lo && value <= spec.hi; }

// The `n` numbers of a numeric key into `values` (n = valueCount(spec.type), or 2 for a
// two-tier kTierTilts).
Status parseNumbers(const KeySpec& spec, const std::string_view* tokens, std::size_t n, double* values,
                    std::int32_t line) noexcept {
    for (std::size_t i = 0U; i < n; ++i) {  // bound: <= 3 values
        if (spec.type == ValueType::kDouble || spec.type == ValueType::kVec2 || spec.type == ValueType::kVec3 ||
            spec.type == ValueType::kArray3 || spec.type == ValueType::kTierTilts) {
            if (!parseNumber(tokens[i], values[i])) {
                return Status(StatusCode::kCorruptData, spec.bad_value, line);
            }
        } else {
            std::uint64_t magnitude = 0U;
            bool negative = false;
            if (!parseInteger(tokens[i], true, magnitude, negative) || magnitude > (1ULL << 40U)) {
                return Status(StatusCode::kCorruptData, spec.bad_value, line);
            }
            values[i] = negative ? -static_cast<double>(magnitude) : static_cast<double>(magnitude);
        }
        if (!inRange(spec, values[i])) {
            return Status(StatusCode::kInvalidConfig, spec.out_of_range, line);
        }
    }
    return Status::ok();
}

void storeNumbers(const KeySpec& spec, const double* values, std::size_t n, void* field) noexcept {
    switch (spec.type) {
        case ValueType::kTierTilts: {
            TierTilts& t = *static_cast<TierTilts*>(field);
            t.count = static_cast<std::int32_t>(n);
            for (std::size_t i = 0U; i < n; ++i) {  // bound: <= kMaxPanoramaTiers values
                t.deg[i] = values[i];
            }
            break;
        }
        case ValueType::kDouble: *static_cast<double*>(field) = values[0]; break;
        case ValueType::kInt32: *static_cast<std::int32_t*>(field) = static_cast<std::int32_t>(values[0]); break;
        case ValueType::kUint16: *static_cast<std::uint16_t*>(field) = static_cast<std::uint16_t>(values[0]); break;
        case ValueType::kVec2: *static_cast<Vec2*>(field) = Vec2(values[0], values[1]); break;
        case ValueType::kVec3: *static_cast<Vec3*>(field) = Vec3(values[0], values[1], values[2]); break;
        case ValueType::kArray3: {
            double* a = static_cast<double*>(field);
            a[0] = values[0];
            a[1] = values[1];
            a[2] = values[2];
            break;
        }
        default: break;
    }
}

}  // namespace

std::size_t valueCount(ValueType type) noexcept {
    switch (type) {
        case ValueType::kVec2: return 2U;
        case ValueType::kVec3:
        case ValueType::kArray3:
        case ValueType::kTierTilts: return 3U;
        default: return 1U;
    }
}

bool parseNumber(std::string_view token, double& out) noexcept {
    char buffer[kMaxNumberChars + 1U];
    if (!copyToken(token, buffer)) {
        return false;
    }
    char* end = nullptr;
    const double value = std::strtod(buffer, &end);
    if (end != buffer + token.size() || !math::isFinite(value)) {
        return false;
    }
    out = value;
    return true;
}

Status setValue(const KeySpec& spec, const std::string_view* tokens, std::size_t count, Scenario& s,
                std::int32_t line) noexcept {
    const bool two_tiers = spec.type == ValueType::kTierTilts && count == 2U;
    if (count != valueCount(spec.type) && !two_tiers) {
        return Status(StatusCode::kCorruptData, spec.bad_value, line);
    }
    void* field = spec.field(s);
    bool ok = true;
    switch (spec.type) {
        case ValueType::kUint64: {
            bool negative = false;
            ok = parseInteger(tokens[0], false, *static_cast<std::uint64_t*>(field), negative);
            break;
        }
        case ValueType::kBool: ok = parseWord(tokens[0], kBoolWords, *static_cast<bool*>(field)); break;
        case ValueType::kName: ok = setName(tokens[0], static_cast<char*>(field)); break;
        case ValueType::kKind: ok = parseWord(tokens[0], kKindWords, *static_cast<ScenarioKind*>(field)); break;
        case ValueType::kModel: ok = parseWord(tokens[0], kModelWords, *static_cast<CameraModelKind*>(field)); break;
        case ValueType::kTerrainKind: ok = parseWord(tokens[0], kTerrainWords, *static_cast<TerrainKind*>(field)); break;
        case ValueType::kModality: ok = parseWord(tokens[0], kModalityWords, *static_cast<OrbitalModality*>(field)); break;
        default: {
            double values[3] = {0.0, 0.0, 0.0};
            VTM_RETURN_IF_ERROR(parseNumbers(spec, tokens, count, values, line));
            storeNumbers(spec, values, count, field);
            break;
        }
    }
    return ok ? Status::ok() : Status(StatusCode::kCorruptData, spec.bad_value, line);
}

Status checkRange(const KeySpec& spec, const Scenario& s) noexcept {
    // The table's accessors take a mutable Scenario; reading through them changes nothing.
    void* field = spec.field(const_cast<Scenario&>(s));  // NOLINT(cppcoreguidelines-pro-type-const-cast)
    double values[3] = {0.0, 0.0, 0.0};
    switch (spec.type) {
        case ValueType::kDouble: values[0] = *static_cast<const double*>(field); break;
        case ValueType::kInt32: values[0] = static_cast<double>(*static_cast<const std::int32_t*>(field)); break;
        case ValueType::kUint16: values[0] = static_cast<double>(*static_cast<const std::uint16_t*>(field)); break;
        case ValueType::kVec2: {
            const Vec2& v = *static_cast<const Vec2*>(field);
            values[0] = v.x();
            values[1] = v.y();
            break;
        }
        case ValueType::kVec3: {
            const Vec3& v = *static_cast<const Vec3*>(field);
            values[0] = v.x();
            values[1] = v.y();
            values[2] = v.z();
            break;
        }
        case ValueType::kArray3: std::memcpy(values, field, sizeof(values)); break;
        case ValueType::kTierTilts: {
            const TierTilts& t = *static_cast<const TierTilts*>(field);
            if (t.count < kMinPanoramaTiers || t.count > kMaxPanoramaTiers) {
                return Status(StatusCode::kInvalidConfig, spec.out_of_range, 0);
            }
            std::memcpy(values, t.deg, sizeof(values));
            break;
        }
        default: return Status::ok();
    }
    const std::size_t n = (spec.type == ValueType::kTierTilts)
                              ? static_cast<std::size_t>(static_cast<const TierTilts*>(field)->count)
                              : valueCount(spec.type);
    for (std::size_t i = 0U; i < n; ++i) {  // bound: <= 3 values
        // NaN fails both comparisons: out of range.
        if (!inRange(spec, values[i])) {
            return Status(StatusCode::kInvalidConfig, spec.out_of_range, 0);
        }
    }
    return Status::ok();
}

}  // namespace vtm::sim::detail
