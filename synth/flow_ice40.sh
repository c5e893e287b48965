#!/usr/bin/env bash
# iCE40 flow for a small pixelproc core: export, Yosys synth_ice40, nextpnr-ice40 on the
# HX8K (CT256) through the pin-reduced wrapper synth/ice40/pins_wrapper.v, clock
# constrained by synth/ice40/pixelproc.pcf. Writes docs/fpga_results/ice40_n{W}[_noshadow].md.
#   synth/flow_ice40.sh [WIDTH=8] [SEED=1] [noshadow|shadow]   (default: N = 8, no shadows)
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
W=${1:-8}; SEED=${2:-1}; CFG=${3:-noshadow}
case "$CFG" in shadow) sfx="" ;; noshadow) sfx="_noshadow" ;; *) echo "third argument: shadow or noshadow" >&2; exit 2 ;; esac
OUT=target/flow/ice40_n$W$sfx
RES=docs/fpga_results/ice40_n$W$sfx.md
mkdir -p "$OUT" docs/fpga_results
pick_yosys; pick_pnr ice40
export_core "$OUT" "$W" "$CFG"
cp synth/ice40/pixelproc.pcf "$OUT/"
t0=$(now)
check_export "$OUT" pixelproc_ice40_pins "$OUT/v/pixelproc_top.v" synth/ice40/pins_wrapper.v
$YOSYS -p "read_verilog $OUT/v/pixelproc_top.v synth/ice40/pins_wrapper.v; synth_ice40 -top pixelproc_ice40_pins -json $OUT/top.json; stat" > "$OUT/synth.log" 2>&1 \
  || { echo "Yosys synthesis failed: $OUT/synth.log" >&2; grep -E "ERROR" "$OUT/synth.log" | head -5 >&2; exit 1; }
t1=$(now)
rc=0
(cd "$OUT" && $PNR --hx8k --package ct256 --json top.json --pcf pixelproc.pcf --pcf-allow-unconstrained \
  --seed "$SEED" --timing-allow-fail --report report.json > pnr.log 2>&1) || rc=$?
t2=$(now)
if [ $rc != 0 ]; then
  { echo "# iCE40 HX8K: pixelproc_top, N = $W, $CFG"; echo; echo "Place and route FAILED (synth/flow_ice40.sh $W $SEED $CFG, $(secs "$t1" "$t2")):"; echo;
    echo '```'; grep -E "ERROR|Device utilisation|ICESTORM_LC|ICESTORM_RAM|SB_IO" "$OUT/pnr.log" | head -20; echo '```'; } > "$RES"
  cat "$RES"; exit 1
fi
grep -q "constrain.*clock.*48" "$OUT/pnr.log" || { echo "the PCF clock constraint was not applied (see $OUT/pnr.log)" >&2; exit 1; }
python3 synth/pnr_report.py "$OUT/report.json" "$RES" "iCE40 HX8K: pixelproc_top, N = $W, ${CFG/noshadow/no shadows}" \
  "device=iCE40 HX8K CT256, through synth/ice40/pins_wrapper.v (8-bit command shift port: the 256-bit word does not fit 206 I/O)" \
  "configuration=N = $W, ${CFG}, input FIFO 32 beats, output FIFO 16 pixels" \
  "constraint=synth/ice40/pixelproc.pcf: set_frequency clock 48 MHz" \
  "placement seed=$SEED" \
  "synthesis time=$(secs "$t0" "$t1") (Yosys synth_ice40, 2-core machine shared with other jobs)" \
  "place and route time=$(secs "$t1" "$t2")" \
  "tools=$($YOSYS -V | head -1); $($PNR --version 2>&1 | head -1)" \
  "command=synth/flow_ice40.sh $W $SEED $CFG"
cat "$RES"
