#!/usr/bin/env bash
# The README's test command. Installs what it needs (as root; otherwise prints the
# apt-get line), builds and runs the host tests and the flight-policy checks.
#   tools/test.sh            host Release build + unit tests + policy checks
#   tools/test.sh --all      also: ASan+UBSan build, static analysis (clang-tidy,
#                            cppcheck), and all five cross targets under qemu-user,
#                            then the static-memory / stack budget of every target,
#                            and bounded libFuzzer runs (FUZZ_SECONDS, default 30)
#   tools/test.sh --targets "aarch64 ppc750"   host + the named cross targets only
# Environment: JOBS (parallel build jobs, default: number of cores).
set -uo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
ALL_TARGETS="aarch64 armhf ppc750 leon3 riscv64"
all=0
targets=""
while [ $# -gt 0 ]; do
  case "$1" in
    --all) all=1; targets="$ALL_TARGETS"; shift ;;
    --targets) targets="$2"; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
JOBS=${JOBS:-$(nproc)}

# ---- packages ---------------------------------------------------------------------
. "$here/tools/scripts/ensure_packages.sh"
pkgs="$VTM_HOST_PACKAGES"
[ -n "$targets" ] && pkgs="$pkgs qemu-user"
[ "$all" = 1 ] && pkgs="$pkgs clang-tidy cppcheck valgrind clang libclang-rt-14-dev"
for t in $targets; do
  case "$t" in
    aarch64) pkgs="$pkgs g++-aarch64-linux-gnu" ;;
    armhf) pkgs="$pkgs g++-arm-linux-gnueabihf" ;;
    ppc750) pkgs="$pkgs g++-powerpc-linux-gnu" ;;
    leon3) pkgs="$pkgs g++-sparc64-linux-gnu g++-12-multilib-sparc64-linux-gnu" ;;
    riscv64) pkgs="$pkgs g++-riscv64-linux-gnu" ;;
    *) echo "test.sh: unknown target '$t' (known: $ALL_TARGETS)" >&2; exit 2 ;;
  esac
done
ensure_packages $pkgs || exit 1

# ---- steps ------------------------------------------------------------------------
passed=0; failed=0; skipped=0; failures=""
report=build/test-report.md
mkdir -p build
# The simulator's render cache (docs/sim-render.md "Render cache"): the host tests render
# each scene of the tests that take scenes as input once; the sanitizer, valgrind and
# cross runs read the same frames back instead of ray casting them again (under qemu the
# renderer is about a third of the module tests' time). Emptied here, so that no frame of
# an earlier tree is read; a plain ctest run without the variable renders everything.
export VTM_RENDER_CACHE="$here/build/render-cache"
rm -rf "$VTM_RENDER_CACHE" && mkdir -p "$VTM_RENDER_CACHE"
printf '# tools/test.sh report\n\n| step | result | seconds | CPU seconds |\n|---|---|---|---|\n' > "$report"

children_cpu() {  # sets CPU: user + system seconds of the finished child processes so far
  times > build/.times  # in this shell: inside $( ) `times` would see a subshell's children
  CPU=$(tail -n 1 build/.times | awk '{ s = 0; for (i = 1; i <= 2; ++i) { split($i, a, /[ms]/); s += a[1] * 60 + a[2] }
                                        printf "%d", s }')
}

step() {  # step NAME COMMAND...: runs, times, records. A step that is not a ctest run
          # (build, analysis, memcheck, budget) counts as one check in the summary.
          # CPU seconds beside the wall seconds: on 2 cores a step whose CPU is well
          # under twice its wall time left a core idle (docs/build.md "CI time").
  local name="$1"; shift
  local t0=$SECONDS c0
  children_cpu; c0=$CPU
  echo "== $name"
  if "$@"; then
    children_cpu
    echo "| $name | ok | $((SECONDS - t0)) | $((CPU - c0)) |" >> "$report"
    [ "$1" = ctest_counted ] || passed=$((passed + 1))
  else
    children_cpu
    echo "| $name | FAILED | $((SECONDS - t0)) | $((CPU - c0)) |" >> "$report"
    failures="$failures $name"
    [ "$1" = ctest_counted ] || failed=$((failed + 1))
  fi
}

ctest_counted() {  # ctest_counted PRESET: runs ctest, adds its counts to the totals
  local log="build/ctest-$1.log"
  ctest --preset "$1" -j "$JOBS" 2>&1 | tee "$log" | grep -E "tests passed|tests failed|\*\*\*Failed|Not Run|Timeout|\(Failed\)"
  local rc=${PIPESTATUS[0]}
  local line total nfail
  line=$(grep -E "tests passed, [0-9]+ tests? failed out of [0-9]+" "$log" | tail -n 1)
  total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<< "$line")
  nfail=$(sed -E 's/.*passed, ([0-9]+) tests? failed.*/\1/' <<< "$line")
  # ctest counts a skipped test (GTEST_SKIP: a measurement run on request) as passed
  local nskip
  nskip=$(grep -cE '^[[:space:]]+[0-9]+ - .* \(Skipped\)$' "$log" || true)
  if [ -n "$line" ]; then
    passed=$((passed + total - nfail - nskip)); failed=$((failed + nfail)); skipped=$((skipped + nskip))
  else
    failed=$((failed + 1))
  fi
  return "$rc"
}

build_preset() { cmake --preset "$@" > "build/configure-$1.log" 2>&1 || { cat "build/configure-$1.log"; return 1; }
                 cmake --build --preset "$1" -j "$JOBS"; }

# The vtm command line, cross-compiled, is what `vtm run --target` flies, and ctest's
# run.target_bits compares its products with the host's bit for bit. To keep the CI run
# short that whole-mission check (and the 90 s of compiler time the tools cost per
# target) runs on the RAD750 (ppc750), big-endian and 32-bit like LEON3; the other
# targets, LEON3 among them, run every module test and the determinism suite, which
# compare each module's bits with the host's (docs/build.md "CI time"). A developer's
# `cmake --preset leon3` still builds the tools, and `vtm run --target leon3` flies there.
cross_args() {
  case "$1" in
    ppc750) echo "-DVTM_VECTORISER_DUMPS=ON" ;;  # read by tools/checks/vector_guard.py
    *) echo "-DVTM_BUILD_TOOLS=OFF" ;;
  esac
}

memcheck_executables() {  # the host unit-test executables memcheck runs, the longest first
  local exe
  # The longest under valgrind start first, so that none of them ends the step alone on
  # one core (docs/static-analysis.md, memcheck row).
  for exe in "$1"/tests/tiepoints/vtm_tiepoints_tests "$1"/tests/refine/vtm_refine_tests; do
    [ -x "$exe" ] && echo "$exe"
  done
  for exe in "$1"/tests/vtm_*_tests "$1"/tests/*/vtm_*_tests; do
    case "$(basename "$exe")" in
      vtm_tiepoints_tests|vtm_refine_tests) ;;
      *peer*|*accuracy*|*eval*|*cli*|vtm_app_tests|vtm_app_orbital_tests|vtm_msl_navcam_tests|vtm_strecha_tests|vtm_pds_panorama_tests|vtm_pds_pointing_tests|vtm_app_panorama_tests) ;;
      *) echo "$exe" ;;
    esac
  done
}

memcheck() {  # the host unit-test executables under valgrind: uninitialised reads, leaks
  # Left out (all of them ran natively in the host steps): death tests (they fork and
  # abort); MathAccuracy.*: valgrind computes x87 long double at double precision, so their
  # high-precision reference is not one there; NoHeapGuard.*: valgrind replaces operator
  # new/delete with its own, so the guard's counters cannot see them there.
  # Also left out: the peer, accuracy, evaluation and command-line suites, vtm_app_tests and
  # vtm_app_panorama_tests (they run whole requests: 30 s natively, far longer under valgrind); the MER frames'
  # tie points and pointing adjustment (vtm_pds_panorama_tests, vtm_pds_pointing_tests: whole
  # 1024^2 frames and OpenCV's adjusters, 54 s of valgrind CPU and more; their reader is
  # vtm_pds_tests, in, and their matcher and adjuster are the features and bundle modules,
  # whose unit tests are in); the module unit tests in tests/*/ are in.
  # Up to JOBS executables at once (valgrind runs each on one core).
  local rc=0 exe log
  for exe in $(memcheck_executables "$1"); do
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
    log="build/memcheck-$(basename "$exe").log"
    rm -f "$log.failed"
    ( valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
        "$exe" --gtest_filter='-*DeathTest*:MathAccuracy.*:NoHeapGuard.*' --gtest_brief=1 > "$log" 2>&1 \
        || touch "$log.failed" ) &
  done
  wait
  for exe in $(memcheck_executables "$1"); do
    log="build/memcheck-$(basename "$exe").log"
    if [ -e "$log.failed" ]; then
      echo "memcheck: $exe"; tail -n 30 "$log"; rc=1
    fi
  done
  return $rc
}

step "host-release build" build_preset host-release
step "host-release tests" ctest_counted host-release

if [ "$all" = 1 ]; then
  step "host-asan build" build_preset host-asan
  step "host-asan tests" ctest_counted host-asan
  step "static analysis" tools/checks/static_analysis.sh build/host-release
  step "valgrind memcheck (host unit tests)" memcheck build/host-release
  # Bounded libFuzzer runs of the parsers that face the outside (docs/static-analysis.md).
  step "fuzz (link decoder, file readers, camera model, scenario, pose files, PLY reader; ${FUZZ_SECONDS:-30} s each)" tools/checks/fuzz.sh
fi
budget_dirs="build/host-release"
for t in $targets; do
  step "$t build" build_preset "$t" $(cross_args "$t")
  step "$t tests" ctest_counted "$t"
  budget_dirs="$budget_dirs build/$t"
done
if [ -n "$targets" ]; then
  step "budget (static memory, worst stack)" python3 tools/budget/vtm_budget.py $budget_dirs
fi
case " $targets " in
  *" ppc750 "*)  # the report; the gate is ctest bench.stereo_insn_gate (docs/stereo.md "Cost")
    step "ppc750 instructions per pixel*disparity (dense stereo)" tools/qemu/count_stereo.sh --build build/ppc750
    # GCC 12.2 miscompiles a vectorised narrow multiply-high on the scalar targets (docs/build.md "Compiler bugs").
    step "vector multiply-high guard (flight code as compiled for ppc750)" python3 tools/checks/vector_guard.py build/ppc750 ;;
esac

echo
cat "$report"
if [ -n "$failures" ]; then
  echo "FAILED steps:$failures"
fi
# Unit tests of every configuration plus one check per other step.
echo "summary: $passed passed, $failed failed, $skipped skipped (run on request)"
[ -z "$failures" ]
