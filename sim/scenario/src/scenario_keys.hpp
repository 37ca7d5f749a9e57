// The table of scenario keys (private to sim/scenario): one row per "key value..." a
// scenario file may hold, with its section, value type, range, the kinds it belongs to
// and the Status reasons naming it. Parsing, validation of code-built scenarios and the
// documentation all follow this one table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sim/scenario.hpp"

namespace vtm::sim::detail {

enum class ValueType : std::uint8_t {
    kDouble,      // one finite number in [lo, hi]
    kInt32,       // one integer in [lo, hi] (int32 member)
    kUint16,      // one integer in [lo, hi] (uint16 member)
    kUint64,      // one integer 0 .. 2^64-1 (seeds)
    kBool,        // true | false
    kName,        // [A-Za-z0-9_-], 1 .. kMaxScenarioNameChars
    kKind,        // rover_pair | descent | traverse | panorama
    kModel,       // pinhole | cahv | cahvor
    kTerrainKind, // mars | plane | dome
    kModality,    // visible | thermal (OrbitalModality)
    kVec2,        // two finite numbers, each in [lo, hi]
    kVec3,        // three finite numbers, each in [lo, hi]
    kArray3,      // three finite numbers (double[3] member), each in [lo, hi]
    kTierTilts,   // two or three finite numbers, each in [lo, hi] (TierTilts member)
};

enum class Section : std::uint8_t {
    kTop, kTerrain, kCamera, kSensor, kLighting, kMotion, kOdometry, kOrbital, kPointing
};

// Bit masks of the scenario kinds a key belongs to.
constexpr std::uint8_t kAnyKind = 0xFU;
constexpr std::uint8_t kPairOnly = 0x1U;
constexpr std::uint8_t kDescentOnly = 0x2U;
constexpr std::uint8_t kTraverseOnly = 0x4U;
constexpr std::uint8_t kRoverKinds = 0x5U;
constexpr std::uint8_t kPanoramaOnly = 0x8U;
constexpr std::uint8_t kMovingKinds = 0x7U;      // kinds whose vehicle moves (odometry, a fixed mount)
constexpr std::uint8_t kPairOrPanorama = 0x9U;

[[nodiscard]] constexpr std::uint8_t kindBit(ScenarioKind kind) noexcept {
    return static_cast<std::uint8_t>(1U << (static_cast<std::uint8_t>(kind) - 1U));
}

// [camera] keys that belong to only some camera models.
constexpr std::uint8_t kAnyModel = 0x7U;
constexpr std::uint8_t kPinholeOnly = 0x1U;
constexpr std::uint8_t kCahvModels = 0x6U;
constexpr std::uint8_t kCahvorOnly = 0x4U;

struct KeySpec {
    Section section;
    std::string_view key;
    ValueType type;
    double lo;
    double hi;
    std::uint8_t kinds;    // scenario kinds the key is allowed in
    std::uint8_t models;   // camera models ([camera] only)
    bool required;
    void* (*field)(Scenario&);
    // Status reasons naming section.key.
    const char* bad_value;     // not a number / wrong word / wrong count (kCorruptData)
    const char* out_of_range;  // (kInvalidConfig)
    const char* repeated;      // (kCorruptData)
    const char* missing;       // (kInvalidConfig)
    const char* wrong_kind;    // (kInvalidConfig): key of another scenario kind or camera model
};

// The table and its length.
[[nodiscard]] const KeySpec* scenarioKeys(std::size_t& count) noexcept;

}  // namespace vtm::sim::detail
