#!/usr/bin/env bash
# Timing budget of the two mapping executives in the default flight configuration
# (1024 x 1024 wide-baseline pair with 128 disparities; 1024 x 1024 descent pair with 64
# planes): per-stage host time (median of --runs requests), per-stage instruction counts
# on each target ISA under qemu-user, and the derived time on a RAD750-class CPU at
# 200 MHz. docs/budgets.md "Timing".
#
#   tools/budget/timing_budget.sh [--runs N] [--targets "aarch64 armhf ppc750 leon3 riscv64"]
#                                 [--ipc X] [--out FILE]
#
# Inputs: frames 0 and 1 of sim/scenarios/rover_wide_baseline.scn and descent.scn,
# rendered by `vtm-sim render` (build/timing/), played by hal::FileCamera and
# hal::FileOdometry in tests/bench/mapper_probe.cpp, which flies WideBaselineMapper{} /
# DescentMapper{} with the scenario's camera mount.
# Host: the probe's StageRecords (hal::MonotonicClock), median over N requests (default 5).
# Targets: build/<target>/tests/bench/vtm_mapper_probe (configured with `cmake --preset T`;
# the script builds the probe), one request under qemu with the counting plugin's
# marker=vtm_probe_mark: every stage reads the clock at its start and its end, so the
# instruction totals at the marks bracket each stage exactly. Targets without a build are
# skipped (listed). The products' hash must be the same on every target.
# RAD750 time = ppc750 instructions / (200e6 * IPC), IPC 1 unless --ipc (an assumption:
# the 750 issues up to two instructions a cycle; memory stalls pull it below one).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
runs=5
targets="aarch64 armhf ppc750 leon3 riscv64"
ipc=1
out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --targets) targets=$2; shift 2 ;;
    --ipc) ipc=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    *) echo "timing_budget.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cd "$root"
host=build/host-release
work=build/timing
mkdir -p "$work"
cmake --build "$host" --target vtm-sim vtm_mapper_probe > "$work/build.log" 2>&1 \
  || { cat "$work/build.log" >&2; echo "timing_budget.sh: host build failed" >&2; exit 1; }
for s in rover descent; do
  scn=sim/scenarios/$([ "$s" = rover ] && echo rover_wide_baseline || echo descent).scn
  if [ ! -f "$work/$s/scenario.scn" ] || ! cmp -s "$scn" "$work/$s/scenario.scn"; then
    rm -rf "${work:?}/$s"
    "$host/tools/sim/vtm-sim" render "$scn" "$work/$s" --frames 0,1 > "$work/render-$s.log" 2>&1 \
      || { cat "$work/render-$s.log" >&2; exit 1; }
  fi
done

# The camera mount (R_vehicle_from_camera, centre in the vehicle frame) from the true
# vehicle pose and the true camera pose of frame 0.
mount() {  # mount DIR CAMERA
  python3 - "$1" "$2" <<'EOF'
import math, sys
d, cam = sys.argv[1], sys.argv[2]
def rot(w, x, y, z):
    n = math.sqrt(w*w + x*x + y*y + z*z); w, x, y, z = w/n, x/n, y/n, z/n
    return [[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)], [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
            [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]]
v = [l.split() for l in open(d + "/truth.poses") if l[:1].isdigit()][0]
c = [l.split() for l in open(d + "/camera_poses.txt") if l[:1].isdigit() and l.split()[1] == cam][0]
Rv, pv = rot(*map(float, v[4:8])), list(map(float, v[1:4]))
Rc, pc = rot(*map(float, c[6:10])), list(map(float, c[3:6]))
R = [[sum(Rv[k][i] * Rc[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
p = [sum(Rv[k][i] * (pc[k] - pv[k]) for k in range(3)) for i in range(3)]
print(" ".join("%.17g" % R[i][j] for i in range(3) for j in range(3)), " ".join("%.17g" % x for x in p))
EOF
}
declare -A cam=([rover]=mast [descent]=nadir)
declare -A args
for s in rover descent; do
  args[$s]="$s $work/$s/${cam[$s]}.frames $work/$s/odometry.poses $(mount "$work/$s" "${cam[$s]}")"
done

# Host: median stage times over the runs.
for s in rover descent; do
  # shellcheck disable=SC2086
  "$host/tests/bench/vtm_mapper_probe" ${args[$s]} "$runs" > "$work/host-$s.log" \
    || { cat "$work/host-$s.log" >&2; echo "timing_budget.sh: host $s request failed" >&2; exit 1; }
done

plugin=$work/libinsn_count.so
"$root/tools/qemu/build_plugin.sh" "$plugin"
emulator() { case "$1" in aarch64) echo qemu-aarch64 ;; armhf) echo qemu-arm ;; ppc750) echo qemu-ppc ;;
                            leon3) echo qemu-sparc32plus ;; riscv64) echo qemu-riscv64 ;; esac; }
counted=""
skipped=""
for t in $targets; do
  probe=build/$t/tests/bench/vtm_mapper_probe
  if [ ! -f "build/$t/CMakeCache.txt" ]; then skipped="$skipped $t"; continue; fi
  cmake --build "build/$t" --target vtm_mapper_probe > "$work/build-$t.log" 2>&1 \
    || { cat "$work/build-$t.log" >&2; echo "timing_budget.sh: $t build failed" >&2; exit 1; }
  for s in rover descent; do
    # shellcheck disable=SC2086
    "$(emulator "$t")" -plugin "$plugin,outfile=$work/count-$t-$s.txt,mode=insn,marker=vtm_probe_mark" \
      "$probe" ${args[$s]} 1 > "$work/qemu-$t-$s.log" \
      || { cat "$work/qemu-$t-$s.log" >&2; echo "timing_budget.sh: $t $s request failed" >&2; exit 1; }
  done
  counted="$counted $t"
done

# Worst-case stack of the two map() entry points per target (tools/budget/vtm_budget.py).
dirs="$host"
for t in $counted; do dirs="$dirs build/$t"; done
# shellcheck disable=SC2086
python3 tools/budget/vtm_budget.py --top 0 --json "$work/stack.json" $dirs > "$work/stack.log" 2>&1 \
  || { cat "$work/stack.log" >&2; echo "timing_budget.sh: vtm_budget.py failed" >&2; exit 1; }

python3 - "$work" "$runs" "$ipc" "$counted" "$skipped" > "$work/timing-budget.md" <<'EOF'
import json, statistics, sys
work, runs, ipc = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
counted, skipped = sys.argv[4].split(), sys.argv[5].split()
def stages(log):  # [(name, ms)] of every run, in order
    out, cur = [], None
    for line in open(log):
        f = line.split()
        if f[:1] == ["run"]:
            cur = []; out.append(cur)
            if f[3] != "ok": sys.exit(f"{log}: run {f[1]} failed: {line.strip()}")
        elif f[:1] == ["stage"]:
            cur.append((f[1], float(f[3])))
    return out
def hash_of(log):
    return [l.split()[1] for l in open(log) if l.startswith("hash ")][0]
def memory_of(log):  # (object bytes, workspace bytes)
    f = [l.split() for l in open(log) if l.startswith("memory ")][0]
    return int(f[2]), int(f[4])
stack = {}
for t in json.load(open(f"{work}/stack.json"))["targets"]:
    for lib in t["libraries"]:
        for e in lib["entry_points"]:
            for m in ("WideBaselineMapper::map()", "DescentMapper::map()"):
                if e["name"] == "vtm::app::" + m:
                    stack[(t["target"], m)] = e["worst_case"]
print(f"# Timing budget (tools/budget/timing_budget.sh, {runs} host runs, IPC {ipc:g} for the RAD750)\n")
for s, title in (("rover", "WideBaselineMapper, 1024 x 1024, 128 disparities"),
                 ("descent", "DescentMapper, 1024 x 1024, 64 planes")):
    host = stages(f"{work}/host-{s}.log")
    names = [n for n, _ in host[0]]
    med = {n: statistics.median(r[i][1] for r in host) for i, n in enumerate(names)}
    counts, hashes = {}, {"host": hash_of(f"{work}/host-{s}.log")}
    for t in counted:
        marks = [int(l.split()[2]) for l in open(f"{work}/count-{t}-{s}.txt") if l.startswith("mark ")]
        if len(marks) != 2 * len(names):
            sys.exit(f"{t} {s}: {len(marks)} marks for {len(names)} stages")
        counts[t] = {n: marks[2 * i + 1] - marks[2 * i] for i, n in enumerate(names)}
        hashes[t] = hash_of(f"{work}/qemu-{t}-{s}.log")
    print(f"## {title}\n")
    head = "| stage | host ms (median) |" + "".join(f" {t} instructions |" for t in counted)
    if "ppc750" in counted: head += " RAD750 200 MHz s |"
    print(head); print("|---" * (head.count("|") - 1) + "|")
    flight = [n for n in names if not n.startswith("capture") and not n.startswith("pose")]
    for n in names + ["total (flight stages)"]:
        keys = flight if n.startswith("total") else [n]
        row = f"| {n} | {sum(med[k] for k in keys):.1f} |"
        for t in counted:
            row += f" {sum(counts[t][k] for k in keys):,} |"
        if "ppc750" in counted:
            row += f" {sum(counts['ppc750'][k] for k in keys) / (200e6 * ipc):.2f} |"
        print(row)
    entry = "WideBaselineMapper::map()" if s == "rover" else "DescentMapper::map()"
    mem = {"host": memory_of(f"{work}/host-{s}.log")}
    for t in counted:
        mem[t] = memory_of(f"{work}/qemu-{t}-{s}.log")
    print("\n| target | mapper object bytes | workspace bytes (arena, planned at init) | worst stack of map(), bytes |")
    print("|---|---|---|---|")
    for t in ["host"] + counted:
        ws = stack.get(("host" if t == "host" else t, entry))
        print(f"| {'x86-64 (host)' if t == 'host' else t} | {mem[t][0]:,} | {mem[t][1]:,} | "
              f"{'—' if ws is None else format(ws, ',')} |")
    same = len(set(hashes.values())) == 1
    print(f"\nProducts' hash: {hashes['host']} on the host" +
          ("; the same on " + ", ".join(counted) if same and counted else "") + ".")
    if not same:
        print("**Hashes differ:** " + ", ".join(f"{k} {v}" for k, v in hashes.items()))
    print("capture* and pose* are the hal/file drivers (PNG decoding, pose interpolation), not flight "
          "mapping; the total leaves them out.\n")
if skipped:
    print("Not counted (no configured build/<target>): " + ", ".join(skipped) + ".\n")
EOF
cat "$work/timing-budget.md"
[ -z "$out" ] || cp "$work/timing-budget.md" "$out"
# Different products between targets are a determinism failure.
! grep -q "Hashes differ" "$work/timing-budget.md"
