// Exit codes of the ground command lines, vtm and vtm-sim (docs/tools.md). In tools/ground
// so that both include it by its path, "vtm/ground/exit_codes.hpp"; the names stay in
// vtm::tools, the namespace of the command-line code that returns them.
#pragma once

namespace vtm::tools {

constexpr int kExitOk = 0;
// The inputs cannot be processed: a file is missing or unreadable, sizes differ, the
// configuration is refused, the workspace exceeds the budget, an output cannot be written.
constexpr int kExitInputError = 1;
// The command line itself is malformed: unknown option, missing argument, a value that
// does not parse (e.g. --disparity abc) or an empty disparity range.
constexpr int kExitUsageError = 2;

}  // namespace vtm::tools
