#!/usr/bin/env bash
# Target-ISA instruction count of the ML dense stereo per pixel*disparity, under
# qemu-user with the exact counting plugin (tools/qemu/insn_count.c).
#
#   tools/qemu/count_stereo.sh [--build DIR] [--emulator QEMU] [--size WxH] [--disparities D1,D2]
#                              [--mode insn|tb] [--profile] [--max-search N] [--max-fixed N] [--content K]
#
# Defaults: --build build/peer-ppc750 (a ppc750 build: `cmake --preset ppc750 -B
# build/peer-ppc750 && cmake --build build/peer-ppc750 --target vtm_stereo_insn_probe`),
# --emulator qemu-ppc, --size 450x375 (teddy's size), --disparities 32,64, --mode insn.
# Other targets: e.g. --build build/aarch64 --emulator qemu-aarch64.
# --profile: also the instructions of one compute() at D2 per containing symbol (code
# inlined into a function counts for it), top 12, demangled.
# --content K: the probe's image content (texture, the default; noise, flat, periodic,
# saturated, allbins: issue 22 item 5, docs/stereo.md "Cost").
# --max-search N, --max-fixed N: a gate. Exit 1 (after the report) when the search per
# pixel*disparity exceeds N, or the per-pixel cost independent of D does; counts are
# exact, so the gate is deterministic (ctest bench.stereo_insn_gate on ppc750).
#
# Method: the probe (tests/bench/stereo_insn_probe.cpp) builds a synthetic pair, inits
# MlStereo (default Config, d 0..D-1) and calls compute() REPEAT times. For each D:
#   C(D) = count(REPEAT=2) - count(REPEAT=1)   instructions of one compute()
# (start-up, pair synthesis, init and exit cancel exactly). Then, with N = W*H:
#   all-in per pixel*disparity at D   = C(D) / (N * D)
#   search per pixel*disparity        = (C(D2) - C(D1)) / (N * (D2 - D1))
#   per pixel, independent of D       = C(D1) / N - search * D1
# Needs: gcc (host, for the plugin), qemu-user, and the cross build.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$root/build/peer-ppc750
emulator=qemu-ppc
size=450x375
disps=32,64
mode=insn
profile=0
max_search=
max_fixed=
content=texture
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --emulator) emulator=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --disparities) disps=$2; shift 2 ;;
    --mode) mode=$2; shift 2 ;;
    --profile) profile=1; shift ;;
    --max-search) max_search=$2; shift 2 ;;
    --max-fixed) max_fixed=$2; shift 2 ;;
    --content) content=$2; shift 2 ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "count_stereo.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
w=${size%x*}; h=${size#*x}; d1=${disps%,*}; d2=${disps#*,}
probe=$build/tests/bench/vtm_stereo_insn_probe
[ -x "$probe" ] || { echo "count_stereo.sh: $probe not built (cmake --build $build --target vtm_stereo_insn_probe)" >&2; exit 1; }
work=$build/qemu
plugin=$work/libinsn_count.so
"$here/build_plugin.sh" "$plugin"

# shellcheck source=tools/qemu/count_common.sh
. "$here/count_common.sh"
count() {  # count D REPEAT -> instruction total of one probe run
  local opts="mode=$mode"
  [ "$profile" = 1 ] && [ "$1" = "$d2" ] && opts="$opts,profile=on"
  insn_count "$work/count-$1-$2.txt" "$work/probe-$1-$2.log" "$opts" "$probe" "$w" "$h" "$1" "$2" "$content"
}
declare -A c
for d in "$d1" "$d2"; do
  for r in 1 2; do
    c[$d,$r]=$(count "$d" "$r")
  done
  # The disparities must not depend on the repeat count (same input, same bits).
  same_repeats count_stereo.sh "$work/probe-$d-1.log" "$work/probe-$d-2.log"
done
echo "target: $(basename "$emulator" | sed 's/^qemu-//')  build: $build  size: ${w}x${h}  mode: $mode  content: $content"
echo "probe:  $(sed 's/ repeat [0-9]*//' "$work/probe-$d2-1.log")"
figures=$(awk -v w="$w" -v h="$h" -v d1="$d1" -v d2="$d2" \
    -v a1="${c[$d1,1]}" -v a2="${c[$d1,2]}" -v b1="${c[$d2,1]}" -v b2="${c[$d2,2]}" 'BEGIN {
  n = w * h; c1 = a2 - a1; c2 = b2 - b1
  printf "one compute(), D=%d: %.0f instructions (runs: %.0f, %.0f)\n", d1, c1, a1, a2
  printf "one compute(), D=%d: %.0f instructions (runs: %.0f, %.0f)\n", d2, c2, b1, b2
  printf "all-in per pixel*disparity: D=%d %.2f, D=%d %.2f\n", d1, c1 / (n * d1), d2, c2 / (n * d2)
  s = (c2 - c1) / (n * (d2 - d1))
  printf "search per pixel*disparity (marginal, D=%d..%d): %.2f\n", d1, d2, s
  printf "per pixel, independent of D: %.1f\n", c1 / n - s * d1
}')
echo "$figures"
[ -n "$max_search" ] && gate_check "search per pixel*disparity" "$(echo "$figures" | awk '/^search/ {print $NF}')" "$max_search"
[ -n "$max_fixed" ] && gate_check "per pixel, independent of D" "$(echo "$figures" | awk '/^per pixel/ {print $NF}')" "$max_fixed"
if [ "$profile" = 1 ]; then
  echo "one compute(), D=$d2, by symbol (instructions, per pixel*disparity, share):"
  awk -v n="$((w * h * d2))" '
    FNR == NR && $1 == "symbol" {one[$3] = $2; next}
    $1 == "symbol" {two[$3] = $2}
    END {
      for (s in two) { c = two[s] - one[s]; if (c > 0) { tot += c; cnt[s] = c } }
      for (s in cnt) printf "%.0f %.2f %.1f%% %s\n", cnt[s], cnt[s] / n, 100 * cnt[s] / tot, s
    }' "$work/count-$d2-1.txt" "$work/count-$d2-2.txt" | sort -k1,1nr | head -n 12 | c++filt | cut -c1-160 | sed 's/^/  /'
fi
exit "$gate"
