# Sourced by tools/test.sh and tools/run.sh: ensure_packages PKG... installs the Debian
# packages that are missing (as root), or prints the apt-get line and returns 1.
ensure_packages() {
  local missing="" p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
  done
  [ -z "$missing" ] && return 0
  if [ "$(id -u)" = 0 ]; then
    echo "== installing:$missing"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq --no-install-recommends $missing && return 0
    echo "apt-get install failed" >&2
    return 1
  fi
  echo "missing packages. Run as root:" >&2
  echo "  apt-get update && apt-get install -y --no-install-recommends$missing" >&2
  return 1
}

# The packages every host build needs (tools/ and tests/ included).
VTM_HOST_PACKAGES="cmake ninja-build g++ googletest libeigen3-dev libstb-dev libcli11-dev libopencv-dev libopencv-contrib-dev libbenchmark-dev libgdal-dev gdal-bin python3"
