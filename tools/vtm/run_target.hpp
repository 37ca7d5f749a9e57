// `vtm run --target T`: the same mission flown by the vtm cross-compiled for target T
// (build/T/tools/vtm/vtm, its flight executives built with the target's compiler and
// flags) under qemu-user, against this host's native vtm-sim over the HIL link. The
// cross-compiled vtm is started as `QEMU FLIGHT run [SCENARIO] --link --sim NATIVE_SIM
// --out DIR --expect-target T [--size N]`: it refuses to run if it was built for another
// target, and otherwise builds the world for the truth, flies the executives and
// writes the products and the report itself. docs/run.md.
#pragma once

#include <string>

#include "run_command.hpp"

namespace vtm::tools {

// The targets `--target` knows, space-separated (aarch64 armhf ppc750 leon3 riscv64).
std::string runTargetNames();
// Exit code (exit_codes.hpp): the cross-compiled vtm's, or kExitInputError with one line
// on stderr when it cannot be started (unknown target, no such build, no qemu, a vtm
// built for another target) or was killed by a signal.
int runOnTarget(const RunOptions& options);

}  // namespace vtm::tools
