#!/usr/bin/env bash
# Self-test of the instruction-counting plugin (tools/qemu/insn_count.c) on ppc750:
# builds the plugin and a static PowerPC program with a loop of K instructions
# (selftest/counted_loop.c), counts K in the disassembly, runs the program for N = 1000
# and N = 2000 iterations under qemu-ppc with the plugin (per-instruction and per-TB
# modes) and checks that the counts differ by exactly 1000 * K.
# Usage: tools/qemu/selftest.sh [WORKDIR]   (default: build/peer-ppc750/qemu)
# Needs: gcc, gcc-powerpc-linux-gnu (g++-powerpc-linux-gnu pulls it), qemu-user.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
work=${1:-$here/../../build/peer-ppc750/qemu}
mkdir -p "$work"
"$here/build_plugin.sh" "$work/libinsn_count.so"
powerpc-linux-gnu-gcc -O1 -mcpu=750 -static -o "$work/counted_loop" "$here/selftest/counted_loop.c"

# K: instructions from counted_loop_begin up to (not including) counted_loop_end.
k=$(powerpc-linux-gnu-objdump -d "$work/counted_loop" | awk '
  /<counted_loop_begin>:/ {inside=1; next}
  /^[0-9a-f]+ <[^>]+>:/ {inside=0}
  inside && /^ *[0-9a-f]+:\t/ {n++}
  END {print n+0}')
echo "loop body from objdump: K = $k instructions"
[ "$k" -gt 0 ] || { echo "selftest: loop not found in the disassembly" >&2; exit 1; }

count() {  # count MODE N -> prints the instruction total
  qemu-ppc -plugin "$work/libinsn_count.so,outfile=$work/count.txt,mode=$1" "$work/counted_loop" "$2" || true
  awk '$1 == "insns" {print $2}' "$work/count.txt"
}
rc=0
for mode in insn tb; do
  c1=$(count "$mode" 1000); c2=$(count "$mode" 2000)
  diff=$((c2 - c1)); want=$((1000 * k))
  echo "mode=$mode: N=1000 -> $c1, N=2000 -> $c2, difference $diff, expected 1000*K = $want"
  [ "$diff" -eq "$want" ] || { echo "selftest: mode=$mode count is not exact" >&2; rc=1; }
done
[ $rc -eq 0 ] && echo "selftest: ok"
exit $rc
