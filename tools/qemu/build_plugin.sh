#!/usr/bin/env bash
# Builds the instruction-counting qemu plugin (host shared object).
# Usage: tools/qemu/build_plugin.sh OUTPUT.so
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${1:?usage: build_plugin.sh OUTPUT.so}
mkdir -p "$(dirname "$out")"
if [ ! -f "$out" ] || [ "$here/insn_count.c" -nt "$out" ] || [ "$here/qemu_plugin_api.h" -nt "$out" ]; then
  gcc -O2 -std=c11 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden \
      -o "$out" "$here/insn_count.c"
fi
