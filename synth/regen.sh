#!/usr/bin/env bash
# Regenerates the checked-in export in synth/rtl/ (N = 8, shadows: pixelproc_top.v, the
# streaming core, and span_parity.v, the block the formal checks read) from the Rust RTL.
# Run after any change under rtl/src; testbench/tests/flow_rtl_export.rs fails until the
# files match the export.
#   synth/regen.sh
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cargo run -q --release -p pixelproc-rtl --example export_verilog "$tmp" 8 >/dev/null
for f in pixelproc_top.v span_parity.v; do cp "$tmp/$f" "synth/rtl/$f"; done
echo "synth/rtl/: pixelproc_top.v span_parity.v regenerated (N = 8, shadows)"
