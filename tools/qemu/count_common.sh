# Sourced by the instruction-count scripts (count_stereo.sh, count_descent.sh,
# count_matcher.sh): one probe run under the counting plugin, the check that a probe's
# output does not depend on its repeat count, and the gate of their --max-* options.

# insn_count OUT LOG OPTS PROBE ARGS...: runs PROBE ARGS... under "$emulator" with the
# plugin "$plugin" (its options: outfile=OUT, then OPTS, e.g. mode=insn), the probe's
# output to LOG; prints the instruction total.
insn_count() {
  local out=$1 log=$2 opts=$3
  shift 3
  "$emulator" -plugin "$plugin,outfile=$out,$opts" "$@" > "$log"
  awk '$1 == "insns" {print $2}' "$out"
}

# same_repeats SCRIPT LOG1 LOG2: exit 1, naming SCRIPT, when the two runs' outputs differ
# other than in their repeat counts (same input, same bits).
same_repeats() {
  cmp -s <(sed 's/repeat [0-9]*//' "$2") <(sed 's/repeat [0-9]*//' "$3") \
    || { echo "$1: probe output differs between repeats" >&2; exit 1; }
}

# gate_check NAME VALUE LIMIT prints the comparison and sets gate=1 when VALUE > LIMIT;
# the script exits "$gate" after its report.
gate=0
gate_check() {
  if awk -v v="$2" -v m="$3" 'BEGIN { exit !(v > m) }'; then
    echo "gate: $1 $2 > $3: FAILED"; gate=1
  else
    echo "gate: $1 $2 <= $3: ok"
  fi
}
