# Sourced by the instruction-count scripts (count_stereo.sh, count_descent.sh): the gate of
# their --max-* options. gate_check NAME VALUE LIMIT prints the comparison and sets
# gate=1 when VALUE > LIMIT; the script exits "$gate" after its report.
gate=0
gate_check() {
  if awk -v v="$2" -v m="$3" 'BEGIN { exit !(v > m) }'; then
    echo "gate: $1 $2 > $3: FAILED"; gate=1
  else
    echo "gate: $1 $2 <= $3: ok"
  fi
}
