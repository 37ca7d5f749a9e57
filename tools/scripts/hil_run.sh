#!/usr/bin/env bash
# HIL run: starts the simulator (`vtm-sim serve`, native) and the flight-side receiver
# (tests/link/hil_receiver.cpp, native or a cross build under qemu-user), both on one
# Unix socket (or TCP loopback with --tcp PORT), and fails unless the receiver got every
# frame bit-identical to its in-process render. docs/hal-link.md, "HIL run".
#
#   hil_run.sh VTM_SIM SCENARIO [--tcp PORT] [--frames N] [--fault KIND:N]... -- RECEIVER_COMMAND...
# --fault goes to the simulator (vtm-sim serve --fault) and makes the receiver expect
# faults (--expect-faults): refused frames are skipped, the frames delivered must be exact.
# e.g. hil_run.sh build/host-release/tools/sim/vtm-sim sim/scenarios/test_rover_small.scn \
#        -- qemu-aarch64 build/aarch64/tests/link/vtm_hil_receiver
set -euo pipefail
[[ $# -ge 4 ]] || { echo "usage: $0 VTM_SIM SCENARIO [--tcp PORT] [--frames N] -- RECEIVER..." >&2; exit 2; }
sim=$1; scenario=$2; shift 2
port=""; frames=""; faults=(); expect=()
while [[ $# -gt 0 && $1 != "--" ]]; do
  case $1 in
    --tcp) port=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --fault) faults+=(--fault "$2"); expect=(--expect-faults); shift 2 ;;
    *) echo "$0: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ ${1:-} == "--" ]] || { echo "$0: missing -- RECEIVER" >&2; exit 2; }
shift
[[ -x $sim ]] || { echo "$0: simulator not found: $sim (build the host tools first)" >&2; exit 1; }

if [[ -n $port ]]; then
  endpoint=(--tcp "127.0.0.1:$port")
else
  sock=$(mktemp -u /tmp/vtm_hil_XXXXXX.sock)
  endpoint=(--unix "$sock")
fi
frame_args=(); [[ -n $frames ]] && frame_args=(--frames "$frames")

"$sim" serve "$scenario" "${endpoint[@]}" "${frame_args[@]}" "${faults[@]}" --accept-timeout 60 &
server=$!
trap 'kill "$server" 2>/dev/null || true; [[ -n ${sock:-} ]] && rm -f "$sock"' EXIT
set +e
"$@" "${endpoint[@]}" --scenario "$scenario" "${frame_args[@]}" "${expect[@]}" --timeout-ms 60000
receiver_rc=$?
wait "$server"
server_rc=$?
set -e
echo "hil_run: receiver exit $receiver_rc, simulator exit $server_rc"
[[ $receiver_rc -eq 0 && $server_rc -eq 0 ]]
