#!/usr/bin/env bash
# Placement-seed sweep of the ECP5 flow: one export and one Yosys synth_ecp5, then
# nextpnr-ecp5 once per seed (same device, constraint and options as synth/flow_ecp5.sh).
# Writes docs/fpga_results/ecp5_n{W}[_noshadow]_seeds.md: Fmax and critical path per
# seed, and the minimum, median and maximum.
#   synth/seeds_ecp5.sh [--placer heap|heap:W|static] WIDTH shadow|noshadow SEED...
#     e.g. synth/seeds_ecp5.sh 8 noshadow 1 2 3 4
# --placer as synth/flow_ecp5.sh's fifth argument (default heap); another placer than heap
# adds its name to the report's file name (ecp5_n8_seeds_heap40.md).
# Why: at N = 8 the worst path is the placer's choice among several of similar length,
# and one seed's Fmax moves by ±15 % with the seed alone (docs/fpga.md); compare changes
# on a sweep, not on one seed.
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
usage="usage: synth/seeds_ecp5.sh [--placer heap|heap:W|static] WIDTH shadow|noshadow SEED... (e.g. 8 noshadow 1 2 3 4)"
PLACER=heap; PLACER_OPT=""
if [ "${1:-}" = --placer ]; then
  [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
  PLACER=$2; PLACER_OPT="--placer $2 "; shift 2
fi
check_placer "$PLACER"
[ $# -ge 3 ] || { echo "$usage" >&2; exit 2; }
W=$1; CFG=$2; shift 2
case "$W" in ''|*[!0-9]*|0*) echo "WIDTH must be a positive integer without leading zeros, got '$W'" >&2; exit 2 ;; esac
case "$CFG" in shadow) sfx="" ;; noshadow) sfx="_noshadow" ;; *) echo "second argument: shadow or noshadow, got '$CFG'" >&2; exit 2 ;; esac
for S in "$@"; do
  case "$S" in ''|*[!0-9]*) echo "SEED must be a non-negative integer, got '$S'" >&2; exit 2 ;; esac
done
pick_yosys; pick_pnr ecp5
OUT=target/flow/seeds_ecp5_n$W$sfx
RES=docs/fpga_results/ecp5_n$W${sfx}_seeds$PLACER_SFX.md
rm -rf "$OUT"; mkdir -p "$OUT" docs/fpga_results
export_core "$OUT" "$W" "$CFG"
cp synth/ecp5/pixelproc.lpf "$OUT/"
t0=$(now)
check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
synth_ecp5_core "$OUT"
t1=$(now)
echo "synthesis: $(secs "$t0" "$t1")"
args=()
for S in "$@"; do
  ts=$(now)
  pnr_ecp5 "$OUT" "$S" "report_$S.json" "pnr_$S.log" "$PLACER"
  te=$(now)
  echo "seed $S: $(secs "$ts" "$te")"
  args+=("$S=$OUT/report_$S.json=$(secs "$ts" "$te")")
done
python3 synth/seeds_report.py "$RES" "ECP5 LFE5U-85F: pixelproc_top, N = $W, ${CFG/noshadow/no shadows}, placement seeds" \
  "synth/seeds_ecp5.sh $PLACER_OPT$W $CFG $*" "$($YOSYS -V | head -1); $($PNR --version 2>&1 | head -1)" "$(secs "$t0" "$t1")" "${args[@]}"
cat "$RES"
