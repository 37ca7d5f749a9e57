// The attached label of a PDS3 file (NASA Planetary Data System, "PDS3 Standards
// Reference" chapter 12, Object Description Language): the statements KEY = VALUE before
// the END line, with the GROUP / OBJECT each one sits in (docs/pds.md).
//
// Subset read: ASCII text (bytes 0x20..0x7E, tab, CR, LF); one statement per line,
// except that a quoted string or a parenthesised list may go on over several lines;
// "/* ... */" comments on one line; GROUP = N ... END_GROUP [= N] and OBJECT = N ...
// END_OBJECT [= N], nested at most kMaxPdsNesting deep and closed in order; the END line
// closes the label. The first statement must be PDS_VERSION_ID = PDS3.
// Values are kept as text with line breaks and the blanks next to them removed from
// lists; pdsReal / pdsReals / pdsUnsigned / pdsText read them.
//
// Refused, with one line naming the input, the label line and the reason: a byte that is
// not text, no END within kMaxPdsLabelBytes, a line without '=', an empty key or value,
// an unterminated string, list or comment, unbalanced GROUP/OBJECT, more than
// kMaxPdsStatements statements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

constexpr std::size_t kMaxPdsLabelBytes = std::size_t{1} << 20;  // 1 MiB; MER labels are ~27 KB
constexpr std::size_t kMaxPdsStatements = 20000;
constexpr std::size_t kMaxPdsNesting = 8;

struct PdsStatement {
    std::string scope;  // enclosing GROUP/OBJECT names joined by '/', "" at the top level
    std::string key;    // e.g. "LINES", "^IMAGE"
    std::string value;  // e.g. "1024", "(0.44,-0.06,-1.25)", "\"NAVCAM LEFT\"", "2.69 <deg>"
    std::size_t line = 0;  // 1-based label line of the key
};

struct PdsLabel {
    std::vector<PdsStatement> statements;  // in label order, GROUP/OBJECT/END_* lines excluded
    std::size_t end_offset = 0;            // first byte after the END line

    // The first statement `key` directly in `scope` ("" = top level), or nullptr.
    [[nodiscard]] const PdsStatement* find(const std::string& scope, const std::string& key) const;
    // The scopes (in label order, each once) holding a statement key = value (value compared
    // after pdsText), e.g. the group whose COORDINATE_SYSTEM_NAME is ROVER_FRAME.
    [[nodiscard]] std::vector<std::string> scopesWhere(const std::string& key, const std::string& value) const;
};

// Parses the label at the start of `bytes`; `name` (usually the path) starts the errors.
Result<PdsLabel> parsePdsLabel(const std::vector<unsigned char>& bytes, const std::string& name);

// Value readers (statement values as parsePdsLabel keeps them). Each returns false for a
// value that is not of the form, leaving `out` unchanged.
// A finite real, optionally followed by a unit "<...>": "45.1766 <deg>".
[[nodiscard]] bool pdsReal(const std::string& value, double& out);
// A list of exactly n finite reals, each with an optional unit: "(1.5 <rad>,-0.2 <rad>)".
[[nodiscard]] bool pdsReals(const std::string& value, std::size_t n, std::vector<double>& out);
// An unsigned decimal integer not above max_value, optionally followed by a unit.
[[nodiscard]] bool pdsUnsigned(const std::string& value, std::uint64_t max_value, std::uint64_t& out);
// A symbol or a quoted string, the quotes removed: "NAVCAM_LEFT", "\"NAVCAM LEFT\"".
[[nodiscard]] std::string pdsText(const std::string& value);

}  // namespace vtm::ground
