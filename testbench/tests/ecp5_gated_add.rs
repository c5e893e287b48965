//! The ECP5 gated adder (`synth/ecp5/pixelproc_gated_add.v`: one chain of CCU2C cells
//! whose LUTs take the gate) equals the generic `pixelproc_gated_add` the exported core
//! carries (`pixelproc_rtl::gated_add::GENERIC_VERILOG`, `s = a + (b & {W{en}})`), proved
//! for every input with Yosys's SAT solver (`miter -equiv`, `sat -prove-asserts`) on
//! Yosys's own simulation model of the CCU2C (`+/ecp5/cells_sim.v`). The widths are the
//! processor's two (44: depth, 34: intensity) and an odd one (the last cell's unused
//! half). Then each of a list of mistakes in the ECP5 module (the LUT's function, the gate
//! on another input, the carry's start or its chain) must make the proof fail.
//!
//! Needs yosys. A missing tool prints `SKIPPED: ...`, and fails under `CI=true`.

use pixelproc_rtl::gated_add::{GENERIC_VERILOG, MODULE};
use pixelproc_testbench::external::{mutant, skip_or_fail, tool_available};
use std::path::Path;
use std::process::Command;

/// Whether Yosys proves the generic module and `ecp5` (the ECP5 module's text) equal at
/// width `w`, in `dir`; the Yosys log when it does not.
fn proved_equal(dir: &Path, ecp5: &str, w: usize) -> Result<(), String> {
    let wrap = |name: &str| {
        format!(
            "module {name}(input [{m}:0] a, input [{m}:0] b, input en, output [{m}:0] s);\n\
             \x20   {MODULE} #(.W({w})) u(.a(a), .b(b), .en(en), .s(s));\nendmodule\n",
            m = w - 1
        )
    };
    std::fs::write(dir.join("generic.v"), GENERIC_VERILOG).unwrap();
    std::fs::write(dir.join("ecp5.v"), ecp5).unwrap();
    std::fs::write(dir.join("gold.v"), wrap("gold")).unwrap();
    std::fs::write(dir.join("gate.v"), wrap("gate")).unwrap();
    // Each side is elaborated and flattened in a design of its own (both define the
    // module), then the two are compared in one.
    let script = "read_verilog generic.v gold.v; hierarchy -top gold; proc; flatten; \
                  design -stash gold_side; \
                  read_verilog ecp5.v gate.v; read_verilog +/ecp5/cells_sim.v; \
                  hierarchy -top gate; proc; flatten; opt_clean; \
                  design -copy-from gold_side -as gold gold; \
                  miter -equiv -flatten -make_assert gold gate miter; hierarchy -top miter; \
                  sat -verify -prove-asserts miter";
    let out = Command::new("yosys")
        .current_dir(dir)
        .args(["-q", "-p", script])
        .output()
        .expect("run yosys");
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

#[test]
fn ecp5_gated_add_is_proved_equal_to_the_generic_one() {
    if !tool_available("yosys") {
        skip_or_fail("yosys").unwrap();
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../synth/ecp5/pixelproc_gated_add.v");
    let ecp5 = std::fs::read_to_string(&path).expect("the ECP5 module");
    let dir = tempfile::tempdir().unwrap();
    for w in [44, 34, 7] {
        if let Err(log) = proved_equal(dir.path(), &ecp5, w) {
            panic!("W = {w}: not proved equal:\n{log}");
        }
    }
    // Mistakes the proof must catch: (what, text in the module, replacement).
    let mutants: [(&str, &str, &str); 6] = [
        (
            "propagate without the gate (A ^ B)",
            ".INIT0(16'h66AA)",
            ".INIT0(16'h6666)",
        ),
        (
            "the LUT passing b, not a, where the gate is closed",
            ".INIT1(16'h66AA)",
            ".INIT1(16'h66CC)",
        ),
        ("gate on C, which is tied low", ".D0(en)", ".D0(1'b0)"),
        (
            "carry in of 1",
            "assign carry[0] = 1'b0;",
            "assign carry[0] = 1'b1;",
        ),
        ("carry chain broken", ".CIN(carry[k])", ".CIN(1'b0)"),
        ("operand bits crossed", ".B1(bb[2*k+1])", ".B1(bb[2*k])"),
    ];
    for (what, from, to) in mutants {
        let bad = mutant(&ecp5, what, from, to);
        assert!(
            proved_equal(dir.path(), &bad, 44).is_err(),
            "the proof missed a mistake: {what}"
        );
    }
}
