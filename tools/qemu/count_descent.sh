#!/usr/bin/env bash
# Target-ISA instruction count of the descent plane sweep per pixel*plane, under
# qemu-user with the exact counting plugin (tools/qemu/insn_count.c).
#
#   tools/qemu/count_descent.sh [--build DIR] [--emulator QEMU] [--size N] [--planes P1,P2]
#                               [--content K] [--max-marginal M] [--max-fixed F]
#
# Defaults: --build build/h-desc-ppc750 (`cmake --preset ppc750 -B build/h-desc-ppc750 &&
# cmake --build build/h-desc-ppc750 --target vtm_descent_insn_probe`), --emulator qemu-ppc,
# --size 1024 (N x N), --planes 32,64.
#
# Method (as count_stereo.sh): the probe (tests/bench/descent_insn_probe.cpp) builds a
# synthetic nadir pair and calls compute() REPEAT times. For each plane count P:
#   C(P) = count(REPEAT=2) - count(REPEAT=1)   instructions of one compute()
# Then, with N2 = N*N pixels:
#   all-in per plane at P        = C(P) / P           (the issue's "instructions per plane")
#   marginal per pixel*plane     = (C(P2) - C(P1)) / (N2 * (P2 - P1))
#   per pixel, independent of P  = C(P1) / N2 - marginal * P1   (prefilter, decision)
# --content K: the probe's image content (texture, the default; noise, flat, periodic,
# saturated, allbins: issue 22 item 5's adversarial inputs).
# --max-marginal M, --max-fixed F: a gate. Exit 1 (after the report) when the marginal
# per pixel*plane exceeds M or the per-pixel part exceeds F. The counts are exact, so the
# gate is deterministic (ctest bench.descent_insn_gate on ppc750).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$root/build/h-desc-ppc750
emulator=qemu-ppc
size=1024
planes=32,64
max_marginal=""
max_fixed=""
content=texture
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --emulator) emulator=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --planes) planes=$2; shift 2 ;;
    --content) content=$2; shift 2 ;;
    --max-marginal) max_marginal=$2; shift 2 ;;
    --max-fixed) max_fixed=$2; shift 2 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "count_descent.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
p1=${planes%,*}; p2=${planes#*,}
probe=$build/tests/bench/vtm_descent_insn_probe
[ -x "$probe" ] || { echo "count_descent.sh: $probe not built (cmake --build $build --target vtm_descent_insn_probe)" >&2; exit 1; }
work=$build/qemu
mkdir -p "$work"
plugin=$work/libinsn_count.so
"$here/build_plugin.sh" "$plugin"

# shellcheck source=tools/qemu/count_common.sh
. "$here/count_common.sh"
count() {  # count PLANES REPEAT -> instruction total of one probe run
  insn_count "$work/descent-count-$1-$2.txt" "$work/descent-probe-$1-$2.log" mode=insn \
    "$probe" "$size" "$1" "$2" "$content"
}
declare -A c
for p in "$p1" "$p2"; do
  for r in 1 2; do
    c[$p,$r]=$(count "$p" "$r")
  done
  same_repeats count_descent.sh "$work/descent-probe-$p-1.log" "$work/descent-probe-$p-2.log"
done
echo "target: $(basename "$emulator" | sed 's/^qemu-//')  build: $build  size: ${size}x${size}  content: $content"
echo "probe:  $(sed 's/ repeat [0-9]*//' "$work/descent-probe-$p2-1.log")"
figures=$(awk -v n="$size" -v p1="$p1" -v p2="$p2" \
    -v a1="${c[$p1,1]}" -v a2="${c[$p1,2]}" -v b1="${c[$p2,1]}" -v b2="${c[$p2,2]}" 'BEGIN {
  n2 = n * n; c1 = a2 - a1; c2 = b2 - b1
  printf "one compute(), %d planes: %.0f instructions\n", p1, c1
  printf "one compute(), %d planes: %.0f instructions\n", p2, c2
  printf "all-in per plane: %d planes %.3g, %d planes %.3g\n", p1, c1 / p1, p2, c2 / p2
  m = (c2 - c1) / (n2 * (p2 - p1))
  printf "marginal per pixel*plane (%d..%d planes): %.2f\n", p1, p2, m
  printf "per pixel, independent of the planes: %.1f\n", c1 / n2 - m * p1
}')
echo "$figures"
[ -n "$max_marginal" ] && gate_check "marginal per pixel*plane" "$(echo "$figures" | awk '/^marginal/ {print $NF}')" "$max_marginal"
[ -n "$max_fixed" ] && gate_check "per pixel, independent of the planes" "$(echo "$figures" | awk '/^per pixel/ {print $NF}')" "$max_fixed"
exit "$gate"
