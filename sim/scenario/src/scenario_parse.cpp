// parseScenario / validateScenario (sim/scenario.hpp): the line reader, sections and the
// checks that span several keys. One key's value: scenario_values.cpp.
#include <cstring>

#include "scenario_keys.hpp"
#include "scenario_panorama.hpp"
#include "scenario_values.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {
namespace {

using detail::KeySpec;
using detail::Section;

constexpr std::size_t kMaxKeys = 160U;
constexpr std::size_t kMaxTokens = 5U;  // key + up to 3 values (+1 to detect too many)

struct SectionName {
    std::string_view name;
    Section section;
};
constexpr SectionName kSections[] = {{"terrain", Section::kTerrain},   {"camera", Section::kCamera},
                                     {"sensor", Section::kSensor},     {"lighting", Section::kLighting},
                                     {"motion", Section::kMotion},     {"odometry", Section::kOdometry},
                                     {"orbital", Section::kOrbital},   {"pointing", Section::kPointing}};

struct Tokens {
    std::string_view token[kMaxTokens];
    std::size_t count = 0U;
};

bool isBlank(char c) noexcept { return c == ' ' || c == '\t' || c == '\r'; }

// Fields of a line up to a '#' (comment). count == kMaxTokens means "too many".
Tokens tokenize(std::string_view line) noexcept {
    Tokens t;
    std::size_t i = 0U;
    while (i < line.size() && line[i] != '#') {  // bound: line length
        if (isBlank(line[i])) {
            ++i;
            continue;
        }
        const std::size_t start = i;
        while (i < line.size() && !isBlank(line[i]) && line[i] != '#') {  // bound: line length
            ++i;
        }
        if (t.count == kMaxTokens) {
            break;
        }
        t.token[t.count] = line.substr(start, i - start);
        ++t.count;
    }
    return t;
}

Status parseSectionHeader(const Tokens& t, Section& section, std::int32_t line) noexcept {
    const std::string_view head = t.token[0];
    if (t.count != 1U || head.size() < 3U || head.back() != ']') {
        return Status(StatusCode::kCorruptData, "scenario: a section line must be [name] alone", line);
    }
    const std::string_view name = head.substr(1U, head.size() - 2U);
    for (const SectionName& s : kSections) {  // bound: 8 sections
        if (s.name == name) {
            section = s.section;
            return Status::ok();
        }
    }
    return Status(StatusCode::kCorruptData,
                  "scenario: unknown [section] (terrain, camera, sensor, lighting, motion, odometry, orbital, pointing)",
                  line);
}

const char* unknownKeyReason(Section section) noexcept {
    switch (section) {
        case Section::kTop: return "scenario: unknown key before the first [section] (name, kind, seed)";
        case Section::kTerrain: return "scenario: unknown key in [terrain]";
        case Section::kCamera: return "scenario: unknown key in [camera]";
        case Section::kSensor: return "scenario: unknown key in [sensor]";
        case Section::kLighting: return "scenario: unknown key in [lighting]";
        case Section::kMotion: return "scenario: unknown key in [motion]";
        case Section::kOrbital: return "scenario: unknown key in [orbital]";
        case Section::kPointing: return "scenario: unknown key in [pointing]";
        default: return "scenario: unknown key in [odometry]";
    }
}

struct ParseState {
    Section section = Section::kTop;
    std::int32_t line_of[kMaxKeys] = {};  // line where each table key was given, 0 = not given
    std::int32_t orbital_line = 0;        // line of the [orbital] header, 0 = none
};

// A section header; [orbital] also switches the orbital image on (once).
Status enterSection(const Tokens& t, ParseState& state, std::int32_t line) noexcept {
    VTM_RETURN_IF_ERROR(parseSectionHeader(t, state.section, line));
    if (state.section == Section::kOrbital) {
        if (state.orbital_line != 0) {
            return Status(StatusCode::kCorruptData, "scenario: [orbital] given twice", line);
        }
        state.orbital_line = line;
    }
    return Status::ok();
}

Status parseLine(std::string_view text, std::int32_t line, ParseState& state, Scenario& s) noexcept {
    const Tokens t = tokenize(text);
    if (t.count == 0U) {
        return Status::ok();
    }
    if (t.token[0][0] == '[') {
        return enterSection(t, state, line);
    }
    std::size_t key_count = 0U;
    const KeySpec* keys = detail::scenarioKeys(key_count);
    for (std::size_t k = 0U; k < key_count; ++k) {  // bound: table size
        if (keys[k].section != state.section || keys[k].key != t.token[0]) {
            continue;
        }
        if (state.line_of[k] != 0) {
            return Status(StatusCode::kCorruptData, keys[k].repeated, line);
        }
        state.line_of[k] = line;
        return detail::setValue(keys[k], &t.token[1], t.count - 1U, s, line);
    }
    return Status(StatusCode::kCorruptData, unknownKeyReason(state.section), line);
}

// Index of a key in the table (programmer error if it is not there).
std::size_t keyIndex(Section section, std::string_view key) noexcept {
    std::size_t key_count = 0U;
    const KeySpec* keys = detail::scenarioKeys(key_count);
    for (std::size_t k = 0U; k < key_count; ++k) {  // bound: table size
        if (keys[k].section == section && keys[k].key == key) {
            return k;
        }
    }
    VTM_ASSERT(false);
    return 0U;
}

std::uint8_t modelBit(CameraModelKind kind) noexcept {
    switch (kind) {
        case CameraModelKind::kPinholeBrown: return detail::kPinholeOnly;
        case CameraModelKind::kCahv: return 0x2U;
        default: return detail::kCahvorOnly;
    }
}

// Required keys, keys of another kind or camera model.
Status checkPresence(const ParseState& state, const Scenario& s) noexcept {
    std::size_t key_count = 0U;
    const KeySpec* keys = detail::scenarioKeys(key_count);
    for (std::size_t k = 0U; k < key_count; ++k) {  // bound: table size
        if (keys[k].required && state.line_of[k] == 0) {
            return Status(StatusCode::kInvalidConfig, keys[k].missing, 0);
        }
    }
    if (state.orbital_line != 0 && s.kind != ScenarioKind::kDescent) {
        return Status(StatusCode::kInvalidConfig, "scenario: [orbital] belongs to descent scenarios only",
                      state.orbital_line);
    }
    const std::uint8_t kind = detail::kindBit(s.kind);
    const std::uint8_t model = modelBit(s.camera.kind);
    for (std::size_t k = 0U; k < key_count; ++k) {  // bound: table size
        const bool given = state.line_of[k] != 0;
        if (given && ((keys[k].kinds & kind) == 0U || (keys[k].models & model) == 0U)) {
            return Status(StatusCode::kInvalidConfig, keys[k].wrong_kind, state.line_of[k]);
        }
    }
    return Status::ok();
}

bool given(const ParseState& state, std::string_view key) noexcept {
    return state.line_of[keyIndex(Section::kCamera, key)] != 0;
}

Status missingCameraKey(const ParseState& state, std::string_view key) noexcept {
    std::size_t key_count = 0U;
    const KeySpec* keys = detail::scenarioKeys(key_count);
    const std::size_t k = keyIndex(Section::kCamera, key);
    return (state.line_of[k] == 0) ? Status(StatusCode::kInvalidConfig, keys[k].missing, 0) : Status::ok();
}

// The camera model from [camera]: a pinhole from hfov_deg (plus distortion) or from
// fx/fy/cx/cy, or CAHV(OR) vectors.
Status finishCamera(const ParseState& state, Scenario& s) noexcept {
    if (s.camera.kind != CameraModelKind::kPinholeBrown) {
        const std::string_view vectors[] = {"c", "a", "h", "v", "o", "r"};
        const std::size_t n = (s.camera.kind == CameraModelKind::kCahvor) ? 6U : 4U;
        for (std::size_t i = 0U; i < n; ++i) {  // bound: <= 6 vectors
            VTM_RETURN_IF_ERROR(missingCameraKey(state, vectors[i]));
        }
        return Status::ok();
    }
    if (!given(state, "hfov_deg")) {
        const std::string_view intrinsics[] = {"fx_px", "fy_px", "cx_px", "cy_px"};
        for (const std::string_view key : intrinsics) {  // bound: 4 keys
            VTM_RETURN_IF_ERROR(missingCameraKey(state, key));
        }
        return Status::ok();
    }
    if (given(state, "fx_px") || given(state, "fy_px") || given(state, "cx_px") || given(state, "cy_px")) {
        return Status(StatusCode::kInvalidConfig,
                      "scenario: camera.hfov_deg and camera.fx_px/fy_px/cx_px/cy_px exclude each other",
                      state.line_of[keyIndex(Section::kCamera, "hfov_deg")]);
    }
    CameraModel pinhole = makePinhole(s.camera.width_px, s.camera.height_px, s.camera_hfov_deg);
    pinhole.k1 = s.camera.k1;
    pinhole.k2 = s.camera.k2;
    pinhole.k3 = s.camera.k3;
    pinhole.p1 = s.camera.p1;
    pinhole.p2 = s.camera.p2;
    s.camera = pinhole;
    return Status::ok();
}

// Seeds not given in the file are derived from the scenario seed, one per purpose.
void deriveSeeds(const ParseState& state, Scenario& s) noexcept {
    std::uint64_t mix = s.seed;
    const std::uint64_t terrain_seed = splitMix64(mix);
    const std::uint64_t noise_seed = splitMix64(mix);
    const std::uint64_t orbital_seed = splitMix64(mix);
    if (state.line_of[keyIndex(Section::kTerrain, "seed")] == 0) {
        s.terrain.seed = terrain_seed;
    }
    if (state.line_of[keyIndex(Section::kSensor, "noise_seed")] == 0) {
        s.sensor.noise_seed = noise_seed;
    }
    if (state.line_of[keyIndex(Section::kOrbital, "noise_seed")] == 0) {
        s.orbital.noise_seed = orbital_seed;
    }
}

// The [orbital] section's combinations of fields, then the renderer's own checks.
Status validateOrbitalScenario(const Scenario& s) noexcept {
    if (!s.orbital.enabled) {
        return Status::ok();
    }
    if (s.kind != ScenarioKind::kDescent) {
        return Status(StatusCode::kInvalidConfig, "scenario: [orbital] belongs to descent scenarios only");
    }
    if (s.orbital.bit_depth != 8 && s.orbital.bit_depth != 16) {
        return Status(StatusCode::kInvalidConfig, "scenario: orbital.bit_depth must be 8 or 16");
    }
    if (!(s.orbital.thermal_subsolar_k > s.orbital.thermal_floor_k)) {
        return Status(StatusCode::kInvalidConfig, "scenario: orbital.thermal_subsolar_k must exceed orbital.thermal_floor_k");
    }
    return validateOrbitalParams(scenarioOrbitalParams(s));
}

Status parseLines(std::string_view text, ParseState& state, Scenario& s) noexcept {
    std::int32_t line = 0;
    std::size_t pos = 0U;
    while (pos < text.size()) {  // bound: text size (<= kMaxScenarioTextBytes), one line per pass
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) {
            end = text.size();
        }
        ++line;
        VTM_RETURN_IF_ERROR(parseLine(text.substr(pos, end - pos), line, state, s));
        pos = end + 1U;
    }
    return Status::ok();
}

}  // namespace

Vec3 sunDirection(double azimuth_deg, double elevation_deg) noexcept {
    const double az = azimuth_deg * (math::kPi / 180.0);
    const double el = elevation_deg * (math::kPi / 180.0);
    const double horizontal = math::cos(el);
    return Vec3(horizontal * math::cos(az), horizontal * math::sin(az), -math::sin(el));
}

Status parseScenario(std::string_view text, Scenario& out) noexcept {
    if (text.size() > kMaxScenarioTextBytes) {
        return Status(StatusCode::kUnsupported, "scenario: text longer than kMaxScenarioTextBytes (65536)",
                      static_cast<std::int64_t>(text.size()));
    }
    if (std::memchr(text.data(), '\0', text.size()) != nullptr) {
        return Status(StatusCode::kCorruptData, "scenario: NUL byte in the text");
    }
    Scenario s;
    s.terrain = defaultMarsTerrainParams();
    ParseState state;
    std::size_t key_count = 0U;
    (void)detail::scenarioKeys(key_count);
    VTM_ASSERT(key_count <= kMaxKeys);
    VTM_RETURN_IF_ERROR(parseLines(text, state, s));
    VTM_RETURN_IF_ERROR(checkPresence(state, s));
    s.orbital.enabled = state.orbital_line != 0;
    VTM_RETURN_IF_ERROR(finishCamera(state, s));
    deriveSeeds(state, s);
    s.lighting.to_sun_site = sunDirection(s.sun_azimuth_deg, s.sun_elevation_deg);
    VTM_RETURN_IF_ERROR(validateScenario(s));
    out = s;
    return Status::ok();
}

Status validateScenario(const Scenario& s) noexcept {
    if (s.name[0] == '\0' || std::memchr(s.name, '\0', sizeof(s.name)) == nullptr) {
        return Status(StatusCode::kInvalidConfig, "scenario: name missing or longer than 63 characters");
    }
    std::size_t key_count = 0U;
    const KeySpec* keys = detail::scenarioKeys(key_count);
    for (std::size_t k = 0U; k < key_count; ++k) {  // bound: table size
        const bool camera_key = keys[k].section == Section::kCamera && keys[k].models != detail::kAnyModel;
        const bool motion_of_other_kind = (keys[k].kinds & detail::kindBit(s.kind)) == 0U;
        if (!camera_key && !motion_of_other_kind) {
            VTM_RETURN_IF_ERROR(detail::checkRange(keys[k], s));
        }
    }
    if (s.sensor.bit_depth != 8 && s.sensor.bit_depth != 12) {
        return Status(StatusCode::kInvalidConfig, "scenario: camera.bit_depth must be 8 or 12", s.sensor.bit_depth);
    }
    if (s.kind == ScenarioKind::kDescent && !(s.motion.start_altitude_m > s.motion.end_altitude_m)) {
        return Status(StatusCode::kInvalidConfig, "scenario: motion.start_altitude_m must exceed motion.end_altitude_m");
    }
    if (scenarioFrameCount(s) > kMaxScenarioFrames) {
        return Status(StatusCode::kInvalidConfig, "scenario: more frames than kMaxScenarioFrames (64)",
                      scenarioFrameCount(s));
    }
    VTM_RETURN_IF_ERROR(s.terrain.validate());
    VTM_RETURN_IF_ERROR(validateCameraModel(s.camera));
    VTM_RETURN_IF_ERROR(validateSensorParams(s.sensor));
    VTM_RETURN_IF_ERROR(validateLighting(s.lighting));
    VTM_RETURN_IF_ERROR(detail::validatePanoramaCoverage(s));
    return validateOrbitalScenario(s);
}

}  // namespace vtm::sim
