#!/usr/bin/env bash
# Target-ISA instruction count of the features template matcher per searched feature,
# under qemu-user with the exact counting plugin (tools/qemu/insn_count.c).
#
#   tools/qemu/count_matcher.sh [--build DIR] [--emulator QEMU] [--max-per-feature N] [--content K]
#                               [--detect]
#
# Defaults: --build build/ppc750 (`cmake --build build/ppc750 --target
# vtm_matcher_insn_probe`), --emulator qemu-ppc.
# Method (as count_descent.sh): the probe (tests/bench/matcher_insn_probe.cpp) calls
# match() REPEAT times on one textured pair; one match() = count(REPEAT=2) -
# count(REPEAT=1); per feature = that / the features attempted.
# --content K: the probe's image content (texture, the default; noise, flat, periodic,
# saturated, allbins: issue 22 item 5, docs/features.md). A content without features
# (flat, stripes, ramps) reports the whole match() only.
# --detect: count one Förstner detection of image A instead (per pixel of the 512 x 448 image).
# --max-per-feature N: a gate. Exit 1 (after the report) when the count per attempted
# feature exceeds N. The counts are exact, so the gate is deterministic (ctest
# bench.matcher_insn_gate on ppc750).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$root/build/ppc750
emulator=qemu-ppc
max_per_feature=""
content=texture
operation=match
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --emulator) emulator=$2; shift 2 ;;
    --max-per-feature) max_per_feature=$2; shift 2 ;;
    --content) content=$2; shift 2 ;;
    --detect) operation=detect; shift ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "count_matcher.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
probe=$build/tests/bench/vtm_matcher_insn_probe
[ -x "$probe" ] || { echo "count_matcher.sh: $probe not built (cmake --build $build --target vtm_matcher_insn_probe)" >&2; exit 1; }
work=$build/qemu
mkdir -p "$work"
plugin=$work/libinsn_count.so
"$here/build_plugin.sh" "$plugin"

# shellcheck source=tools/qemu/count_common.sh
. "$here/count_common.sh"
count() {  # count REPEAT -> instruction total of one probe run
  insn_count "$work/matcher-count-$1.txt" "$work/matcher-probe-$1.log" mode=insn "$probe" "$1" "$content" "$operation"
}
c1=$(count 1)
c2=$(count 2)
same_repeats count_matcher.sh "$work/matcher-probe-1.log" "$work/matcher-probe-2.log"
field() {  # field NAME -> the value after NAME on the probe's line
  awk -v k="$1" '{for (i = 1; i < NF; ++i) if ($i == k) print $(i + 1)}' "$work/matcher-probe-1.log"
}
attempted=$(field attempted)
echo "target: $(basename "$emulator" | sed 's/^qemu-//')  build: $build  content: $content  operation: $operation"
echo "probe:  $(sed 's/ repeat [0-9]*//' "$work/matcher-probe-1.log")"
if [ "$operation" = detect ]; then
  awk -v a="$c1" -v b="$c2" -v n="$(field pixels)" \
    'BEGIN { c = b - a; printf "one detect(): %.0f instructions, %.1f per pixel\n", c, c / n }'
  exit 0
fi
figures=$(awk -v a="$c1" -v b="$c2" -v n="$attempted" 'BEGIN {
  c = b - a
  printf "one match(): %.0f instructions\n", c
  if (n > 0) printf "per feature: %.0f\n", c / n
  else printf "per feature: (no feature searched)\n"
}')
echo "$figures"
[ -n "$max_per_feature" ] && gate_check "per feature" "$(echo "$figures" | awk '/^per feature/ {print $NF}')" "$max_per_feature"
exit "$gate"
