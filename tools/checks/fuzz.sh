#!/usr/bin/env bash
# Bounded libFuzzer runs (clang, ASan + UBSan) of the input parsers that face the outside:
#   fuzz_link_decoder   the HIL link decoder and session (hal/link)
#   fuzz_file_readers   hal/file: PGM and PNG decoders, frame manifest, pose log
#   fuzz_camera_model   vtm::parseCameraModel (fsw/core)
#   fuzz_scenario       sim::parseScenario (.scn files; seeds: sim/scenarios/*.scn)
#   fuzz_pose_files     tools/ground's vtm-camera-poses / vtm-poses readers and pose specs
#   fuzz_ply_reader     tools/ground's PLY point reader (ascii, binary little endian)
#   fuzz_pds_reader     tools/ground's PDS3 image reader (seeds: the MER labels, tests/fuzz/seeds/pds)
#   fuzz_panorama_stations  tools/ground's panorama stations file (vtm panorama)
# Configures build/fuzz from tests/fuzz/CMakeLists.txt, writes a seed corpus per target
# (valid inputs; Python's zlib.crc32 computes the link CRCs independently of our code),
# runs each target for FUZZ_SECONDS (default 30; FUZZ_JOBS of them at once, default the
# number of cores) and prints executions and findings.
# FUZZ_TARGETS="NAME..." runs only those targets. With FUZZ_RUNS=N each target runs N executions instead (no time limit): the long
# campaign of docs/static-analysis.md is FUZZ_RUNS=10000000 FUZZ_JOBS=1 tools/checks/fuzz.sh.
# Exit 1 if any target found a crash, leak, timeout or sanitizer report.
#
#   tools/checks/fuzz.sh [SECONDS]        e.g. FUZZ_JOBS=1 tools/checks/fuzz.sh 60
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-${FUZZ_SECONDS:-30}}
jobs=${FUZZ_JOBS:-$(nproc)}
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: FUZZ_JOBS must be a positive integer, got '$jobs'" >&2; exit 2; }
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: SECONDS must be a positive integer, got '$seconds'" >&2; exit 2; }
runs=${FUZZ_RUNS:-}
[[ -z "$runs" || "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: FUZZ_RUNS must be a positive integer, got '$runs'" >&2; exit 2; }
if [[ -n "$runs" ]]; then limit=(-runs="$runs" -max_total_time=0); else limit=(-max_total_time="$seconds"); fi
build=${FUZZ_BUILD_DIR:-$root/build/fuzz}
work=$build/runs

cmake -S "$root/tests/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$build" --target fuzz_link_decoder fuzz_file_readers fuzz_camera_model fuzz_scenario \
    fuzz_pose_files fuzz_ply_reader fuzz_pds_reader fuzz_panorama_stations >/dev/null

rm -rf "$work"
mkdir -p "$work"/{link,file,cmod,scn,poses,ply,pds,pano}/{corpus,artifacts}
cp "$root"/sim/scenarios/*.scn "$work/scn/corpus/"
cp "$root"/tests/fuzz/seeds/pds/* "$work/pds/corpus/"
python3 - "$work" <<'PY'
import struct, sys, zlib
work = sys.argv[1]
seq = [1]
def msg(mtype, payload, version=1):
    body = struct.pack(">4sBBHIII", b"VTML", version, mtype, 0, seq[0], len(payload),
                       zlib.crc32(payload) if payload else 0)
    seq[0] += 1
    return body + struct.pack(">I", zlib.crc32(body)) + payload
def camera(w, h, depth):
    reals = [100.0, 100.0, (w - 1) / 2, (h - 1) / 2] + [0.0] * 23
    return msg(1, struct.pack(">BBBBiiHH", 0, depth, 1, 0, w, h, w, h) + struct.pack(">27d", *reals))
def pose(t, x):
    cov = [0.0] * 36
    for i in range(6):
        cov[i * 7] = 1e-4
    return msg(2, struct.pack(">Q", t) + struct.pack(">3d4d36d", x, 0, 0, 1, 0, 0, 0, *cov))
def frame(fseq, t, w, h, depth, chunk):
    bpp = 2 if depth > 8 else 1
    px = bytes((i * 7 + fseq) & (0x0F if bpp == 2 and i % 2 == 0 else 0xFF) for i in range(w * h * bpp))
    out = msg(3, struct.pack(">IQIBBBBiiI", fseq, t, 2500, 0, depth, bpp, 0, w, h, len(px)))
    for off in range(0, len(px), chunk):
        out += msg(4, struct.pack(">II", fseq, off) + px[off:off + chunk])
    return out
def write(path, data):
    with open(path, "wb") as f:
        f.write(data)
for name, (w, h, depth) in {"8bit": (16, 8, 8), "12bit": (12, 6, 12)}.items():
    seq[0] = 1
    s = camera(w, h, depth)
    for k in range(1, 4):
        s += pose(1000 * k, 0.5 * k) + frame(k, 1000 * k, w, h, depth, 40)
    s += msg(5, struct.pack(">Q", 7)) + msg(6, b"")
    write(f"{work}/link/corpus/stream_{name}", s)
seq[0] = 1
write(f"{work}/link/corpus/heartbeats", msg(5, struct.pack(">Q", 1)) + b"garbage" + msg(5, struct.pack(">Q", 2)))
# hal/file: selector byte 0 PGM, 1 PNG, 2 manifest, 3 pose log.
write(f"{work}/file/corpus/pgm8", b"\x00P5\n# c\n4 3\n255\n" + bytes(range(12)))
write(f"{work}/file/corpus/pgm16", b"\x00P5 3 2 4095\n" + b"".join(struct.pack(">H", i * 300) for i in range(6)))
def png(w, h, colour, depth, raw):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, colour, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
write(f"{work}/file/corpus/png_grey", b"\x01" + png(4, 3, 0, 8, b"".join(b"\x00" + bytes([y * 4 + x for x in range(4)]) for y in range(3))))
write(f"{work}/file/corpus/png_rgb", b"\x01" + png(2, 2, 2, 8, b"\x00" + bytes(6) + b"\x01" + bytes(range(6))))
write(f"{work}/file/corpus/manifest", b"\x02vtm-frames 1\n# c\ncamera_id 3\nwidth_px 4\nheight_px 3\nbit_depth 8\n"
      b"model pinhole 800 800 1.5 1 -0.1 0.01 0 0 0\nframe 1 1000 2500 a.pgm\nframe 2 2000 2500 b.png\n")
write(f"{work}/file/corpus/poses", b"\x03vtm-poses 1\n# t x y z qw qx qy qz var...\n"
      b"1000 0 0 0 1 0 0 0 1e-4 1e-4 1e-4 1e-6 1e-6 1e-6\n2000 1 0.5 0 0.7071067811865476 0 0 0.7071067811865476 "
      b"1e-4 1e-4 1e-4 1e-6 1e-6 1e-6\n")
write(f"{work}/cmod/corpus/pinhole", b"vtm_camera_model 1\n# Navcam-like\nkind pinhole\nwidth_px 1024\nheight_px 1024\n"
      b"fx_px 1236.0773\nfy_px 1236.0773\ncx_px 511.5\ncy_px 511.5\nk1 -0.2\nk2 0.08\nk3 0\np1 0\np2 0\n")
write(f"{work}/cmod/corpus/cahv", b"vtm_camera_model 1\nkind cahv\nwidth_px 4\nheight_px 3\n"
      b"C 0 0 0\nA 0 0 1\nH 100 0 1.5\nV 0 100 1\n")
write(f"{work}/cmod/corpus/cahvor", b"vtm_camera_model 1\nkind cahvor\nwidth_px 64\nheight_px 48\n"
      b"C 0.1 0 0\nA 0 0 1\nH 100 0 31.5\nV 0 100 23.5\nO 0 0.01 0.99995\nR 0 -0.1 0.01\n")
# pose files: selector byte 0 camera poses, 1 pose log, 2 spec FILE:INDEX (INDEX = byte 2), 3 spec FILE.
cams = (b"vtm-camera-poses 1\n# frame camera t x y z qw qx qy qz\n0 mast 1000 0 0 -1.9 1 0 0 0\n"
        b"1 mast 2000 5 0.5 -1.9 0.9961946980917455 0 0 0.08715574274765817\n")
write(f"{work}/poses/corpus/camera_poses", b"\x00\x00" + cams)
write(f"{work}/poses/corpus/pose_log", b"\x01\x00vtm-poses 1\n1000 0 0 0 1 0 0 0 1e-4 1e-4 1e-4 1e-6 1e-6 1e-6\n")
write(f"{work}/poses/corpus/spec_index", b"\x02\x01" + cams)
write(f"{work}/poses/corpus/spec_one", b"\x03\x00vtm-camera-poses 1\n0 mast 1000 0 0 -1.9 1 0 0 0\n")
# PLY: ascii with an extra property and a face list; binary little endian, doubles and a list.
write(f"{work}/ply/corpus/ascii", b"ply\nformat ascii 1.0\ncomment seed\nelement vertex 3\nproperty float x\n"
      b"property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
      b"property list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0.5 2\n0 1 -0.25 3\n3 0 1 2\n")
write(f"{work}/ply/corpus/binary", b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      b"property double y\nproperty double z\nproperty short s\nelement face 1\n"
      b"property list uchar uint vertex_indices\nend_header\n" +
      struct.pack("<3dh", 1.5, -2.0, 0.25, 7) + struct.pack("<3dh", 0.0, 3.0, -1.0, 8) + struct.pack("<B2I", 2, 0, 1))
# Panorama stations: a two-station file with a full prior and a sigma line.
write(f"{work}/pano/corpus/two", b"vtm-panorama-stations 1\n# seed\nleft_camera l.cmod\nright_camera r.cmod\n"
      b"right_from_left -0.42 0 0 1 0 0 0\nbit_depth 12\nstations 2 tiers 1 columns 2\n"
      b"station 0 tier 0 column 0 pan_deg 0 tilt_deg -15\nimages a.png b.png\ntrue 1 2 -1.5 1 0 0 0\n"
      b"approx 1 2 -1.5 0.5 0.5 0.5 0.5\nprior 1e-4 1e-6 0 0 0 0 1e-6 1e-4 0 0 0 0 0 0 1e-4 0 0 0 "
      b"0 0 0 1e-4 0 0 0 0 0 0 1e-4 0 0 0 0 0 0 1e-4\n"
      b"station 1\nimages c.png d.png\napprox 1 2 -1.5 1 0 0 0\nsigma 0.01 0.01 0.02 0 0 0.005\n")
PY

# Each target runs on a core of its own: up to FUZZ_JOBS (default: the number of cores)
# at once, each for the full SECONDS, so running them side by side changes the wall time,
# not the fuzzing each one gets. The reports are printed in a fixed order afterwards.
run() {  # name dir: runs one target, writes its report line(s) to dir/report.txt and 0/1 to dir/status
  local name=$1 dir=$work/$2
  local start=$SECONDS
  set +e
  "$build/$name" "$dir/corpus" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix="$dir/artifacts/" -print_final_stats=1 >"$dir/log.txt" 2>&1
  local rc=$?
  set -e
  local took=$((SECONDS - start)) execs findings
  # (no stats line after a crash: grep fails, which must not end the run under pipefail)
  execs=$(grep -m1 "stat::number_of_executed_units" "$dir/log.txt" | awk '{print $2}' || true)
  findings=$(find "$dir/artifacts" -type f | wc -l)
  local failed=0
  [[ $rc -eq 0 && $findings -eq 0 ]] || failed=1
  {
    printf '%-18s %5ss  executions %-10s corpus %-5s findings %s (exit %s)\n' "$name" "$took" "${execs:-?}" \
        "$(find "$dir/corpus" -type f | wc -l)" "$findings" "$rc"
    if [[ $failed -ne 0 ]]; then
      grep -m5 -E "ERROR|SUMMARY|runtime error" "$dir/log.txt" || true
      find "$dir/artifacts" -type f | head -3
    fi
  } > "$dir/report.txt"
  echo "$failed" > "$dir/status"
}
targets=(fuzz_link_decoder:link fuzz_file_readers:file fuzz_camera_model:cmod fuzz_scenario:scn
         fuzz_pose_files:poses fuzz_ply_reader:ply fuzz_pds_reader:pds fuzz_panorama_stations:pano)
if [[ -n ${FUZZ_TARGETS:-} ]]; then  # e.g. FUZZ_TARGETS="fuzz_file_readers fuzz_pose_files"
  chosen=()
  for t in "${targets[@]}"; do
    [[ " $FUZZ_TARGETS " == *" ${t%%:*} "* ]] && chosen+=("$t")
  done
  [[ ${#chosen[@]} -gt 0 ]] || { echo "fuzz.sh: FUZZ_TARGETS names none of ${targets[*]%%:*}" >&2; exit 2; }
  targets=("${chosen[@]}")
fi
for t in "${targets[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do wait -n || true; done
  run "${t%%:*}" "${t##*:}" &
done
wait
status=0
for t in "${targets[@]}"; do
  dir=$work/${t##*:}
  cat "$dir/report.txt" 2>/dev/null || echo "${t%%:*}: no report"
  [[ "$(cat "$dir/status" 2>/dev/null)" == 0 ]] || status=1
done
exit $status
