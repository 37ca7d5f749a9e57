// The static memory plan of the flight build: every statically allocated object a
// flight image holds, by name, with its size. Sizes are sizeof() of the real types, so
// the table cannot drift from the code; tests/tools/memory_budget_test.cpp checks it.
#pragma once

#include <cstddef>

namespace vtm::tools {

enum class BudgetGroup { kFlight, kPlaybackDriver };

struct BudgetEntry {
    BudgetGroup group;  // flight configuration, or the desk/HIL playback driver
    const char* name;   // the object
    const char* owner;  // library that defines its type
    std::size_t bytes;  // sizeof or the library's capacity constant, bytes
};

// Entries in a fixed order; count in *n.
const BudgetEntry* memoryBudget(std::size_t* n);
// Sum of the entries of one group, bytes.
std::size_t memoryBudgetTotal(BudgetGroup group);

}  // namespace vtm::tools
