// One key's value: parsing the tokens of a "key value..." line into the Scenario field the
// key table names, and range-checking a field of a Scenario built in code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scenario_keys.hpp"

namespace vtm::sim::detail {

// Values a key takes (1, 2 or 3).
[[nodiscard]] std::size_t valueCount(ValueType type) noexcept;

// A finite decimal number ("C" locale strtod), the whole token.
[[nodiscard]] bool parseNumber(std::string_view token, double& out) noexcept;

// Parses `count` value tokens of the key into its field. kCorruptData (bad_value) for a
// wrong count or a token that does not parse, kInvalidConfig (out_of_range) for a number
// outside [lo, hi]; detail = line.
[[nodiscard]] Status setValue(const KeySpec& spec, const std::string_view* tokens, std::size_t count, Scenario& s,
                              std::int32_t line) noexcept;

// kInvalidConfig (out_of_range, detail 0) when a numeric field lies outside [lo, hi].
[[nodiscard]] Status checkRange(const KeySpec& spec, const Scenario& s) noexcept;

}  // namespace vtm::sim::detail
