#!/usr/bin/env bash
# The ECP5 cost of one pixel processor split by part (token, decision, state, shadow
# flags, readout, and its share of the array's readout gather): Yosys synth_ecp5 of the
# core at WIDTH processors with shadows (default 8), then synth/processor_cost.py on the
# netlist. Writes docs/fpga_results/ecp5_processor_cost.md. Synthesis only (no packing,
# placement or routing); about a minute at N = 8.
#   synth/processor_cost.sh [WIDTH=8]      (WIDTH >= 3: the report is of an interior processor)
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
W=${1:-8}
case "$W" in ''|*[!0-9]*|0*|1|2) echo "WIDTH must be an integer of at least 3 without leading zeros (the report is of an interior processor), got '$W'" >&2; exit 2 ;; esac
[ $# -le 1 ] || { echo "usage: synth/processor_cost.sh [WIDTH=8]" >&2; exit 2; }
pick_yosys
OUT=target/flow/cost_n$W
RES=docs/fpga_results/ecp5_processor_cost.md
mkdir -p "$OUT" docs/fpga_results
export_core "$OUT" "$W" shadow
check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
synth_ecp5_core "$OUT"
python3 synth/processor_cost.py "$OUT/top.json" "$W" "$RES" "synth/processor_cost.sh $W" "$($YOSYS -V | head -1)"
cat "$RES"
