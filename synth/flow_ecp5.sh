#!/usr/bin/env bash
# ECP5 flow for the pixelproc core: export, Yosys synth_ecp5, nextpnr-ecp5 on the
# LFE5U-85F (CABGA381, speed grade 6), out of context, clock constrained by
# synth/ecp5/pixelproc.lpf (150 MHz). Writes docs/fpga_results/ecp5_n{W}[_noshadow].md.
#   synth/flow_ecp5.sh [WIDTH=8] [SEED=1] [shadow|noshadow] [ooc|pins] [heap|heap:W|static] [6|7|8]
# The fifth argument is nextpnr's placer: heap (its default), heap:W (heap with timing
# weight W, a whole number 1..1000, instead of nextpnr's 10) or static (its electrostatic
# placer); the report says which in its placer row and its command, and a placer other
# than heap adds its name to the report's file name (ecp5_n64_pins_heap40.md).
# Out of context (`ooc`, the default) because the core's ports (348 pins, 256 of them the
# command word) do not fit the CABGA381 (205 user I/O) and are on-chip signals in any real
# design: the ports stay ports, no I/O buffers are placed, and the clock is ideal (not
# routed). `pins` places the core inside a pin-level harness instead (synth/ecp5/harness.py:
# the clock on a PCLK pin and the global clock network, every other input from a shift
# register, the outputs into a signature register), with synth/ecp5/pixelproc_harness.lpf;
# results go to docs/fpga_results/ecp5_n{W}[_noshadow]_pins.md.
# The sixth argument is the speed grade nextpnr times against: 6 (the default and the
# slowest), 7 or 8 (the fastest); a grade other than 6 adds _speedG to the file name and
# names the part LFE5U-85F-G in the report.
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
W=${1:-8}; SEED=${2:-1}; CFG=${3:-shadow}; MODE=${4:-ooc}; PLACER=${5:-heap}; SPEED=${6:-6}
case "$W" in ''|*[!0-9]*|0*) echo "WIDTH must be a positive integer without leading zeros, got '$W'" >&2; exit 2 ;; esac
case "$SEED" in ''|*[!0-9]*) echo "SEED must be a non-negative integer, got '$SEED'" >&2; exit 2 ;; esac
check_placer "$PLACER"
check_speed "$SPEED"
case "$CFG" in shadow) sfx="" ;; noshadow) sfx="_noshadow" ;; *) echo "third argument: shadow or noshadow" >&2; exit 2 ;; esac
case "$MODE" in
  ooc) msfx=""; LPF=synth/ecp5/pixelproc.lpf
    DEVICE="LFE5U-85F-$ECP5_SPEED CABGA381, out of context (348 port pins vs 205 user I/O; on-chip in a real design)" ;;
  pins) msfx="_pins"; LPF=synth/ecp5/pixelproc_harness.lpf; ECP5_OOC=""
    DEVICE="LFE5U-85F-$ECP5_SPEED CABGA381, on pins: the core in synth/ecp5/harness.py's harness, clock on PCLK pin G2 and the global network" ;;
  *) echo "fourth argument: ooc or pins, got '$MODE'" >&2; exit 2 ;;
esac
OUT=target/flow/ecp5_n$W$sfx$msfx$SPEED_SFX
RES=docs/fpga_results/ecp5_n$W$sfx$msfx$PLACER_SFX$SPEED_SFX.md
mkdir -p "$OUT" docs/fpga_results
pick_yosys; pick_pnr ecp5
export_core "$OUT" "$W" "$CFG"
cp "$LPF" "$OUT/pixelproc.lpf"
t0=$(now)
check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
if [ "$MODE" = pins ]; then
  python3 synth/ecp5/harness.py "$OUT/v/pixelproc_top.v" pixelproc_top "$OUT/harness.v"
  synth_ecp5_core "$OUT" pixelproc_top_harness "$OUT/harness.v"
else
  synth_ecp5_core "$OUT"
fi
t1=$(now)
pnr_ecp5 "$OUT" "$SEED" report.json pnr.log "$PLACER"
t2=$(now)
CMD="synth/flow_ecp5.sh $W $SEED $CFG${msfx:+ pins}"
if [ "$PLACER" != heap ] || [ "$SPEED" != 6 ]; then
  if [ "$MODE" = ooc ]; then CMD="$CMD ooc"; fi
  CMD="$CMD $PLACER"
fi
if [ "$SPEED" != 6 ]; then CMD="$CMD $SPEED"; fi
python3 synth/pnr_report.py "$OUT/report.json" "$RES" "ECP5 LFE5U-85F${SPEED_SFX:+-$ECP5_SPEED}: pixelproc_top, N = $W, ${CFG/noshadow/no shadows}${msfx:+, on pins}" \
  "device=$DEVICE" \
  "configuration=N = $W, ${CFG}, input FIFO 32 beats, output FIFO 16 pixels" \
  "constraint=$LPF: FREQUENCY PORT clock 150 MHz" \
  "placement seed=$SEED" \
  "placer=$PLACER_WORDS" \
  "synthesis time=$(secs "$t0" "$t1") (Yosys synth_ecp5, 2-core machine shared with other jobs)" \
  "place and route time=$(secs "$t1" "$t2")" \
  "tools=$($YOSYS -V | head -1); $($PNR --version 2>&1 | head -1)" \
  "command=$CMD"
cat "$RES"
