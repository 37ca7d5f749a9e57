#!/usr/bin/env bash
# The README's main-job command: builds the host Release configuration if needed and
# runs `vtm` with the given arguments. Today `vtm` with no argument prints its version,
# build configuration and static memory budget; the mapping issues make it fly the
# built-in simulated mission.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
pkgs="cmake ninja-build g++ libeigen3-dev libstb-dev libcli11-dev libopencv-dev libbenchmark-dev googletest python3"
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing
  else
    echo "run.sh: missing packages. Run as root:" >&2
    echo "  apt-get update && apt-get install -y --no-install-recommends$missing" >&2
    exit 1
  fi
fi
mkdir -p build
cmake --preset host-release > build/configure-host-release.log 2>&1 || { cat build/configure-host-release.log >&2; exit 1; }
cmake --build --preset host-release --target vtm > build/build-vtm.log 2>&1 || { cat build/build-vtm.log >&2; exit 1; }
exec build/host-release/tools/vtm/vtm "$@"
