// "A:B" command-line options: one parser for every vtm command (option_pair.hpp).
#include "option_pair.hpp"

#include <cmath>
#include <cstdlib>

namespace vtm::cli {
namespace {

// One finite number taking the whole text; when `whole`, a whole number within +-1e6 (it
// fits an int32 pixel count).
bool parseNumber(const std::string& s, bool whole, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    if (whole) {
        const long n = std::strtol(s.c_str(), &end, 10);
        v = static_cast<double>(n);
        if (n < -1000000 || n > 1000000) return false;
    } else {
        v = std::strtod(s.c_str(), &end);
    }
    return *end == '\0' && std::isfinite(v);
}

// "MIN:MAX in metres with 0 < MIN < MAX": the form, the unit, then the condition.
std::string expected(PairRule rule, const char* unit) {
    std::string e = rule == PairRule::kAny ? "X:Y" : "MIN:MAX";
    if (unit != nullptr && unit[0] != '\0') e += std::string(" ") + unit;
    switch (rule) {
        case PairRule::kAny: return e + " (two numbers)";
        case PairRule::kOrdered: return e + " (two numbers, MIN <= MAX)";
        case PairRule::kPositiveIncreasing: return e + " with 0 < MIN < MAX";
        case PairRule::kWholeOrdered: return e;
    }
    return e;
}

}  // namespace

std::string parseOptionPair(const std::string& option, const std::string& text, PairRule rule, const char* unit,
                            const char* example, double& a, double& b) {
    const std::string head = option + " '" + text + "': ";
    const std::size_t colon = text.find(':');
    const bool whole = rule == PairRule::kWholeOrdered;
    const bool parsed = colon != std::string::npos && parseNumber(text.substr(0, colon), whole, a) &&
                        parseNumber(text.substr(colon + 1), whole, b);
    if (parsed && whole && a > b) return head + "empty range (MIN > MAX)";
    const bool holds = rule == PairRule::kAny || (rule == PairRule::kPositiveIncreasing ? a > 0.0 && b > a : a <= b);
    if (parsed && holds) return "";
    std::string e = head + "expected " + expected(rule, unit);
    if (example != nullptr && example[0] != '\0') e += std::string(", e.g. ") + example;
    return e;
}

}  // namespace vtm::cli
