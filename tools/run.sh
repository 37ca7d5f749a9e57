#!/usr/bin/env bash
# The README's main-job command: builds the host Release configuration if needed and
# runs `vtm` with the given arguments. Today `vtm` with no argument prints its version,
# build configuration and static memory budget; the mapping issues make it fly the
# built-in simulated mission.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
. tools/scripts/ensure_packages.sh
ensure_packages $VTM_HOST_PACKAGES || exit 1
mkdir -p build
cmake --preset host-release > build/configure-host-release.log 2>&1 || { cat build/configure-host-release.log >&2; exit 1; }
cmake --build --preset host-release --target vtm > build/build-vtm.log 2>&1 || { cat build/build-vtm.log >&2; exit 1; }
exec build/host-release/tools/vtm/vtm "$@"
