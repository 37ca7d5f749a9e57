#!/usr/bin/env bash
# The README's main-job command: builds the host Release configuration if needed and
# runs `vtm` with the given arguments. With none it flies the built-in simulated mission:
# `vtm run --out build/run` (docs/run.md), which writes build/run/report.md and
# report.html with the products.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
. tools/scripts/ensure_packages.sh
ensure_packages $VTM_HOST_PACKAGES || exit 1
mkdir -p build
cmake --preset host-release > build/configure-host-release.log 2>&1 || { cat build/configure-host-release.log >&2; exit 1; }
cmake --build --preset host-release --target vtm > build/build-vtm.log 2>&1 || { cat build/build-vtm.log >&2; exit 1; }
if [ $# -eq 0 ]; then
  set -- run --out build/run
fi
exec build/host-release/tools/vtm/vtm "$@"
