//! The ECP5 registered multiplier (`synth/ecp5/pixelproc_mul_reg.v`: one MULT18X18D with
//! its input and output registers) behaves like the generic `pixelproc_mul_reg` the
//! exported core carries (`pixelproc_rtl::mul_reg::GENERIC_VERILOG`), clock by clock, in
//! Icarus Verilog: `synth/ecp5/sim/tb_mul_reg.v` under random operands, the MULT18X18D
//! being our own model of the subset used (`synth/ecp5/sim/mult18x18d_model.v`, written
//! from Lattice's documentation; no vendor model is available to the open tools). Then
//! each of a list of wiring mistakes in the ECP5 module (operand and product bits,
//! registers, clock enable, reset) must make the comparison fail.
//!
//! Needs iverilog. A missing tool prints `SKIPPED: ...`, and fails under `CI=true`.

use pixelproc_rtl::mul_reg::{GENERIC_VERILOG, MODULE};
use pixelproc_testbench::external::{skip_or_fail, tool_available, Ecp5Module};

/// The module, its testbench and the primitive's model.
const UNDER_TEST: Ecp5Module = Ecp5Module {
    module: MODULE,
    generic: GENERIC_VERILOG,
    testbench: "tb_mul_reg.v",
    model: "mult18x18d_model.v",
};

#[test]
fn ecp5_mul_reg_matches_the_generic_one() {
    if !tool_available("iverilog") {
        skip_or_fail("iverilog").unwrap();
        return;
    }
    // Wiring mistakes the comparison must catch: (what, text in the module, replacement).
    let mutants: [(&str, &str, &str); 8] = [
        (
            "operand a bits 0 and 1 swapped",
            ".A0(a[0]), .A1(a[1])",
            ".A0(a[1]), .A1(a[0])",
        ),
        ("operand b bit 15 tied low", ".B15(b[15])", ".B15(1'b0)"),
        (
            "product bit 31 from bit 30",
            ".P31(prod[31])",
            ".P31(prod[30])",
        ),
        (
            "no output register",
            ".REG_OUTPUT_CLK(\"CLK0\")",
            ".REG_OUTPUT_CLK(\"NONE\")",
        ),
        (
            "operand a not registered",
            ".REG_INPUTA_CLK(\"CLK0\")",
            ".REG_INPUTA_CLK(\"NONE\")",
        ),
        (
            "a pipeline register as well",
            ".REG_PIPELINE_CLK(\"NONE\")",
            ".REG_PIPELINE_CLK(\"CLK0\")",
        ),
        ("registers never enabled", ".CE0(1'b1)", ".CE0(1'b0)"),
        ("registers held in reset", ".RST0(1'b0)", ".RST0(1'b1)"),
    ];
    let dir = tempfile::tempdir().unwrap();
    UNDER_TEST.check(dir.path(), 20_000, &mutants);
}
