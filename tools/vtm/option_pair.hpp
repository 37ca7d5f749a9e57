// "A:B" command-line options (--depth, --range, --disparity, --rotation, --scale, --shift):
// one parser and one wording of its errors for every vtm command.
#pragma once

#include <string>

namespace vtm::cli {

// What a pair must satisfy besides being two finite numbers.
enum class PairRule {
    kAny,                // X:Y, any two numbers
    kOrdered,            // MIN <= MAX
    kPositiveIncreasing, // 0 < MIN < MAX
    kWholeOrdered,       // whole numbers, MIN <= MAX
};

// "" and a, b set, or the one-line error "OPTION 'TEXT': expected ... [, e.g. EXAMPLE]"
// (a reversed range of whole numbers: "OPTION 'TEXT': empty range (MIN > MAX)").
// `unit` (e.g. "in metres") and `example` may be empty.
std::string parseOptionPair(const std::string& option, const std::string& text, PairRule rule, const char* unit,
                            const char* example, double& a, double& b);

}  // namespace vtm::cli
