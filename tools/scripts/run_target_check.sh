#!/usr/bin/env bash
# The main job on a cross target gives the host's bits (ctest run.target_bits on every
# cross build; docs/run.md, "On a target"). Flies SCENARIO twice with the HOST vtm: in
# process, and with --target TARGET (the cross-compiled vtm under qemu-user against the
# native vtm-sim over the HIL link), then requires both runs to map every request and
# every product computed from the flight executives' output (the .pfm depth / disparity /
# range / elevation maps and the .ply point clouds) to be byte-identical.
#
#   run_target_check.sh HOST_VTM TARGET FLIGHT_VTM SCENARIO WORK_DIR
set -euo pipefail
[[ $# -eq 5 ]] || { echo "usage: $0 HOST_VTM TARGET FLIGHT_VTM SCENARIO WORK_DIR" >&2; exit 2; }
host_vtm=$1; target=$2; flight=$3; scenario=$4; work=$5
[[ -x $host_vtm ]] || { echo "$0: host vtm not found: $host_vtm (build the host preset first)" >&2; exit 1; }
rm -rf "$work"; mkdir -p "$work"
"$host_vtm" run "$scenario" --out "$work/host" 2> "$work/host.log" \
  || { echo "host run failed:"; cat "$work/host.log"; exit 1; }
"$host_vtm" run "$scenario" --target "$target" --flight "$flight" --out "$work/$target" 2> "$work/$target.log" \
  || { echo "$target run failed:"; cat "$work/$target.log"; exit 1; }
grep -q "Flown by the vtm built for $target " "$work/$target/report.md" \
  || { echo "$target report does not say it was flown by the $target build"; exit 1; }
n=0; bad=0
for f in "$work"/host/*.pfm "$work"/host/*.ply; do
  [[ -e $f ]] || continue
  name=$(basename "$f")
  if cmp -s "$f" "$work/$target/$name"; then
    n=$((n + 1))
  else
    echo "DIFFERS: $name (host vs $target)"; bad=$((bad + 1))
  fi
done
[[ $n -gt 0 || $bad -gt 0 ]] || { echo "no products to compare in $work/host"; exit 1; }
grep -E "world built|mapped in|ended with" "$work/$target.log" || true
echo "$n products byte-identical between the host and $target, $bad differ"
[[ $bad -eq 0 ]]
