#!/usr/bin/env bash
# ECP5 flow for the pixelproc core: export, Yosys synth_ecp5, nextpnr-ecp5 on the
# LFE5U-85F (CABGA381, speed grade 6), out of context, clock constrained by
# synth/ecp5/pixelproc.lpf (150 MHz). Writes docs/fpga_results/ecp5_n{W}[_noshadow].md.
#   synth/flow_ecp5.sh [WIDTH=8] [SEED=1] [shadow|noshadow]
# Out of context because the core's ports (348 pins, 256 of them the command word) do
# not fit the CABGA381 (205 user I/O) and are on-chip signals in any real design: the
# ports stay ports, no I/O buffers are placed.
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
W=${1:-8}; SEED=${2:-1}; CFG=${3:-shadow}
case "$CFG" in shadow) sfx="" ;; noshadow) sfx="_noshadow" ;; *) echo "third argument: shadow or noshadow" >&2; exit 2 ;; esac
OUT=target/flow/ecp5_n$W$sfx
RES=docs/fpga_results/ecp5_n$W$sfx.md
mkdir -p "$OUT" docs/fpga_results
pick_yosys; pick_pnr ecp5
export_core "$OUT" "$W" "$CFG"
cp synth/ecp5/pixelproc.lpf "$OUT/"
t0=$(now)
check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
synth_ecp5_core "$OUT"
t1=$(now)
pnr_ecp5 "$OUT" "$SEED" report.json pnr.log
t2=$(now)
python3 synth/pnr_report.py "$OUT/report.json" "$RES" "ECP5 LFE5U-85F: pixelproc_top, N = $W, ${CFG/noshadow/no shadows}" \
  "device=LFE5U-85F-6 CABGA381, out of context (348 port pins vs 205 user I/O; on-chip in a real design)" \
  "configuration=N = $W, ${CFG}, input FIFO 32 beats, output FIFO 16 pixels" \
  "constraint=synth/ecp5/pixelproc.lpf: FREQUENCY PORT clock 150 MHz" \
  "placement seed=$SEED" \
  "synthesis time=$(secs "$t0" "$t1") (Yosys synth_ecp5, 2-core machine shared with other jobs)" \
  "place and route time=$(secs "$t1" "$t2")" \
  "tools=$($YOSYS -V | head -1); $($PNR --version 2>&1 | head -1)" \
  "command=synth/flow_ecp5.sh $W $SEED $CFG"
cat "$RES"
