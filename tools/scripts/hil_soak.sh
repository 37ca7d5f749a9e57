#!/usr/bin/env bash
# HIL soak (issue 26, docs/hal-link.md "Soak"): `vtm-sim serve --soak SEED` streams the
# rover pair of SCENARIO over and over with random faults (drops, truncations, corrupt
# bytes, replays, garbage, stalls, hangs past the receiver's timeout, disconnects), and
# the flight-side vtm_hil_soak answers REQUESTS mapping requests with the rover executive,
# reconnecting after each disconnect. Then the simulator's fault log and the soak's report
# are checked against each other:
#   - every request answered: products + named refusals = REQUESTS (and per stage/code);
#   - no heap in the request loop; stack and memory high-water marks flat in the second half;
#   - messages delivered intact = messages the simulator sent intact; replays counted =
#     replays sent; reconnects = connections - 1; frames delivered = frames_ok;
#   - no frame the simulator damaged (drop, crc, truncate, disconnect on its begin or a
#     chunk) was delivered, every frame it sent untouched was delivered (a frame held up by
#     a hang may go either way: the receiver may have been mapping meanwhile), nothing
#     delivered that was not sent.
#
#   hil_soak.sh VTM_SIM VTM_HIL_SOAK SCENARIO REQUESTS SEED [OUT_DIR]
# e.g. hil_soak.sh build/host-release/tools/sim/vtm-sim build/host-release/tests/link/vtm_hil_soak \
#        sim/scenarios/test_rover_small.scn 1000 7 /tmp/soak
set -euo pipefail
[[ $# -ge 5 ]] || { echo "usage: $0 VTM_SIM VTM_HIL_SOAK SCENARIO REQUESTS SEED [OUT_DIR]" >&2; exit 2; }
sim=$1; soak=$2; scenario=$3; requests=$4; seed=$5; out=${6:-}
[[ "$requests" =~ ^[1-9][0-9]*$ ]] || { echo "$0: REQUESTS must be a positive integer, got '$requests'" >&2; exit 2; }
[[ "$seed" =~ ^[0-9]+$ ]] || { echo "$0: SEED must be a non-negative integer, got '$seed'" >&2; exit 2; }
for f in "$sim" "$soak"; do
  [[ -x $f ]] || { echo "$0: not found: $f (build the host tools and tests first)" >&2; exit 1; }
done
if [[ -z $out ]]; then out=$(mktemp -d /tmp/vtm_soak_XXXXXX); fi
mkdir -p "$out"
sock=$(mktemp -u /tmp/vtm_soak_XXXXXX.sock)
timeout_ms=1000
frames=$((requests * 5 / 2 + 16))  # two per request, and spares for the frames faults cost
SECONDS=0
"$sim" serve "$scenario" --unix "$sock" --camera 0 --frames "$frames" --soak "$seed" --fault-rate 20 \
    --stall-ms 100 --hang-ms $((timeout_ms * 3 / 2)) --fault-log "$out/faults.txt" --accept-timeout 60 \
    2> "$out/serve.log" &
server=$!
trap 'kill "$server" 2>/dev/null || true; rm -f "$sock"' EXIT
set +e
"$soak" --unix "$sock" --scenario "$scenario" --requests "$requests" --timeout-ms "$timeout_ms" \
    --report "$out/report.txt" > "$out/soak.log" 2>&1
soak_rc=$?
wait "$server"
server_rc=$?
set -e
echo "hil_soak: $requests requests, seed $seed, $SECONDS s; soak exit $soak_rc, simulator exit $server_rc; files in $out"
grep "FAILED" "$out/soak.log" || true
[[ $server_rc -eq 0 ]] || { tail -3 "$out/serve.log"; }
set +e
python3 - "$out/faults.txt" "$out/report.txt" "$requests" <<'PY'
import sys
faults_path, report_path, requests = sys.argv[1], sys.argv[2], int(sys.argv[3])
sent, damaged, hung, pose_hit = set(), set(), set(), 0
total = {}
for line in open(faults_path):
    w = line.split()
    if w[0] == "frame":
        seq = int(w[1]); sent.add(seq)
        kinds = w[2:]
        if any(k.split(":")[0] == "frame" and k.split(":")[1] in ("drop", "crc", "truncate", "disconnect") for k in kinds):
            damaged.add(seq)
        if "frame:hang" in kinds:
            hung.add(seq)
        pose_hit += sum(k.startswith("pose:") for k in kinds)
    elif w[0] == "total":
        total = {w[i]: int(w[i + 1]) for i in range(1, len(w) - 1, 2)}
delivered, link, fault, res, req, refusals = [], {}, {}, {}, {}, []
for line in open(report_path):
    w = line.split()
    if not w: continue
    if w[0] == "delivered": delivered.append(int(w[1]))
    elif w[0] == "link": link = {w[i]: int(w[i + 1]) for i in range(1, len(w) - 1, 2)}
    elif w[0] == "fault": fault[w[1]] = int(w[2])
    elif w[0] == "resources": res = {w[i]: int(w[i + 1]) for i in range(1, len(w) - 1, 2)}
    elif w[0] == "requests": req = {w[i]: int(w[i + 1]) for i in range(0, len(w) - 1, 2)}
    elif w[0] == "refusal": refusals.append((w[1], w[2], int(w[3]), " ".join(w[4:])))
failures = []
def check(ok, what):
    print(("  ok     " if ok else "  FAILED ") + what)
    if not ok: failures.append(what)
d = set(delivered)
intact = sent - damaged - hung
print(f"simulator: {total.get('frames')} frames, {total.get('messages')} messages ({total.get('intact')} intact), "
      + ", ".join(f"{k} {total.get(k, 0)}" for k in ("drop", "crc", "truncate", "replay", "garbage", "stall", "hang", "disconnect"))
      + f"; {len(damaged)} frames damaged, {len(hung)} held up by a hang, {pose_hit} pose messages hit")
print(f"flight side: {req.get('requests')} requests: {req.get('products')} products, {req.get('refused')} refused; "
      f"{len(delivered)} frames delivered ({req.get('drained')} while draining), {link.get('reconnects')} reconnects")
for stage, code, n, reason in refusals:
    print(f"  refused at {stage:<11} {code:<14} {n:5d}  e.g. \"{reason}\"")
print(f"resources: heap calls {res.get('heap_calls')}, stack high-water {res.get('stack_half')} -> {res.get('stack_end')} B, "
      f"VmHWM {res.get('hwm_half_kib')} -> {res.get('hwm_end_kib')} KiB (half run -> end)")
check(req.get("requests") == requests and req.get("ended_early") == 0, f"all {requests} requests answered")
check(req.get("requests") == req.get("products", -1) + req.get("refused", -1) and req.get("unnamed") == 0,
      "requests = products + named refusals")
check(sum(n for _, _, n, _ in refusals) == req.get("refused"), "refusals by stage and code add up to the refused requests")
check(res.get("heap_calls") == 0, "no heap in the request loop")
check(res.get("stack_half") == res.get("stack_end"), "stack high-water flat in the second half")
check(res.get("hwm_half_kib") == res.get("hwm_end_kib"), "memory high-water (VmHWM) flat in the second half")
check(link.get("messages_ok") == total.get("intact"), f"messages intact: delivered {link.get('messages_ok')} = sent {total.get('intact')}")
check(fault.get("replay") == total.get("replay"), f"replays counted {fault.get('replay')} = sent {total.get('replay')}")
check(link.get("reconnects") == total.get("connections", 0) - 1 == total.get("disconnect"),
      f"reconnects {link.get('reconnects')} = connections - 1 = disconnects {total.get('disconnect')}")
check(link.get("frames_ok") == len(delivered) and len(d) == len(delivered), "frames delivered once each, as frames_ok counts")
check(not (d & damaged), f"no damaged frame delivered ({len(d & damaged)})")
check(intact <= d, f"every intact frame delivered (missing {sorted(intact - d)[:5]})")
check(d <= sent, "nothing delivered that was not sent")
kinds = ("drop", "crc", "truncate", "replay", "garbage", "stall", "hang", "disconnect")
missing = [k for k in kinds if total.get(k, 0) == 0]
check(not missing, "the run met every fault kind" + (f" (not {', '.join(missing)}: more requests or another seed)" if missing else ""))
sys.exit(1 if failures else 0)
PY
check_rc=$?
set -e
[[ $soak_rc -eq 0 && $server_rc -eq 0 && $check_rc -eq 0 ]]
