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
use pixelproc_testbench::external::{mutant, skip_or_fail, tool_available};
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Compiles the testbench with `ecp5` as the ECP5 module's text and runs it for `seed`;
/// returns the simulator's output.
fn run(dir: &Path, ecp5: &str, seed: u32) -> String {
    let generic = dir.join("generic.v");
    // The two implementations share a module name: the generic one is renamed.
    std::fs::write(&generic, GENERIC_VERILOG.replace(MODULE, "generic_mul_reg")).unwrap();
    let ecp5_file = dir.join("ecp5.v");
    std::fs::write(&ecp5_file, ecp5).unwrap();
    let sim = repo().join("synth/ecp5/sim");
    let out = dir.join("tb.vvp");
    let c = Command::new("iverilog")
        .args(["-g2012", "-Wall", "-o"])
        .arg(&out)
        .arg(sim.join("tb_mul_reg.v"))
        .arg(&generic)
        .arg(&ecp5_file)
        .arg(sim.join("mult18x18d_model.v"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&c.stdout).to_string() + &String::from_utf8_lossy(&c.stderr);
    assert!(c.status.success(), "iverilog failed:\n{text}");
    assert!(!text.contains("warning"), "iverilog warnings:\n{text}");
    let r = Command::new("vvp")
        .arg("-n")
        .arg(&out)
        .arg(format!("+seed={seed}"))
        .arg("+cycles=20000")
        .output()
        .unwrap();
    String::from_utf8_lossy(&r.stdout).to_string() + &String::from_utf8_lossy(&r.stderr)
}

/// `(compared, changes)` of a `PASS` line, or `None`.
fn passed(text: &str) -> Option<(u64, u64)> {
    let line = text.lines().find(|l| l.starts_with("PASS "))?;
    let mut v = line
        .split_whitespace()
        .skip(1)
        .filter_map(|kv| kv.split_once('=').and_then(|(_, n)| n.parse::<u64>().ok()));
    Some((v.next()?, v.next()?))
}

#[test]
fn ecp5_mul_reg_matches_the_generic_one() {
    if !tool_available("iverilog") {
        skip_or_fail("iverilog").unwrap();
        return;
    }
    let ecp5 = std::fs::read_to_string(repo().join("synth/ecp5/pixelproc_mul_reg.v")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for seed in [1, 2, 3] {
        let text = run(dir.path(), &ecp5, seed);
        let (compared, changes) =
            passed(&text).unwrap_or_else(|| panic!("seed {seed}: no PASS:\n{text}"));
        // Every clock compared, and the product moving on most of them.
        assert!(
            compared == 20_000 && changes > 15_000,
            "seed {seed}: {text}"
        );
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
    for (what, from, to) in mutants {
        let text = run(dir.path(), &mutant(&ecp5, what, from, to), 1);
        assert!(
            passed(&text).is_none() && text.contains("MISMATCH"),
            "{what}: the comparison did not fail:\n{text}"
        );
    }
}
