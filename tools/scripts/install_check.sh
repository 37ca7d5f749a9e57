#!/usr/bin/env bash
# ctest install.find_package (tests/install): installs this build's flight libraries into
# a fresh prefix, builds tests/install/consumer against it with find_package(vtm) and the
# build's own toolchain, and runs the consumer (under the build's emulator when cross).
#   install_check.sh BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR [TOOLCHAIN_FILE] [EMULATOR]
set -euo pipefail
[ $# -ge 4 ] || { echo "install_check.sh: usage: BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR [TOOLCHAIN_FILE] [EMULATOR]" >&2; exit 2; }
build=$1 src=$2 work=$3 generator=$4 toolchain=${5:-} emulator=${6:-}
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" --component vtm > "$work/install.log"
echo "installed: $(find "$work/prefix/lib" -name 'libvtm_*.a' | wc -l) libraries, $(find "$work/prefix/include" -name '*.hpp' | wc -l) headers"
args=(-S "$src/tests/install/consumer" -B "$work/build" -G "$generator" -DCMAKE_BUILD_TYPE=Release
      "-Dvtm_DIR=$work/prefix/lib/cmake/vtm")
[ -n "$toolchain" ] && args+=("-DCMAKE_TOOLCHAIN_FILE=$toolchain")
cmake "${args[@]}" > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j "${JOBS:-2}" > "$work/build.log" 2>&1 || { tail -n 40 "$work/build.log"; exit 1; }
if [ -n "$emulator" ]; then
  "$emulator" "$work/build/vtm_consumer"
else
  "$work/build/vtm_consumer"
fi
