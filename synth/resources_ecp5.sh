#!/usr/bin/env bash
# ECP5 resources of the core per array width, from synthesis alone (Yosys synth_ecp5, no
# place and route): one row per WIDTH, written with the run times to
# docs/fpga_results/ecp5_resources[_noshadow].md.
#   synth/resources_ecp5.sh shadow|noshadow WIDTH...     e.g. synth/resources_ecp5.sh shadow 8 16 32 64
# Widths already synthesised from the same Verilog (target/flow/res_*) are not run again.
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
RES=docs/fpga_results/ecp5_resources$sfx.md
DIRS=()
for W in "$@"; do
  OUT=target/flow/res_${CFG}_n$W
  mkdir -p "$OUT"
  export_core "$OUT" "$W" "$CFG"
  h=$(cat "$OUT/v/pixelproc_top.v" $ECP5_CELLS | sha256sum | cut -c1-16)
  if [ -f "$OUT/stat.txt" ] && [ "$(cat "$OUT/hash" 2>/dev/null)" = "$h" ]; then
    echo "N = $W ($CFG): up to date"
  else
    rm -f "$OUT/stat.txt" "$OUT/hash"
    t0=$(now)
    check_export "$OUT" pixelproc_top "$OUT/v/pixelproc_top.v"
    $YOSYS -p "read_verilog $OUT/v/pixelproc_top.v; read_verilog -overwrite $ECP5_CELLS; synth_ecp5 -top pixelproc_top; tee -o $OUT/stat.txt stat" > "$OUT/synth.log" 2>&1
    t1=$(now)
    secs "$t0" "$t1" > "$OUT/time"
    echo "$h" > "$OUT/hash"
    echo "N = $W ($CFG): $(cat "$OUT/time")"
  fi
  DIRS+=("$OUT")
done
python3 synth/resources_report.py "$RES" "$CFG" "$($YOSYS -V | head -1)" "synth/resources_ecp5.sh $CFG $*" "${DIRS[@]}"
cat "$RES"
