//! The ECP5 shading-table bank (`synth/ecp5/pixelproc_bank_ram.v`: one DP16KD with its
//! output register) behaves like the generic `pixelproc_bank_ram` the exported core
//! carries (`pixelproc_rtl::bank_ram::GENERIC_VERILOG`), clock by clock, in Icarus
//! Verilog: `synth/ecp5/sim/tb_bank_ram.v` under random writes and reads, the DP16KD
//! being our own model of the subset used (`synth/ecp5/sim/dp16kd_model.v`, written from
//! Lattice's documentation; no vendor model is available to the open tools). Then each of
//! a list of wiring mistakes in the ECP5 module (address, data and output bits, byte
//! enables, chip select, output register mode and enable) must make the comparison fail.
//!
//! Needs iverilog. A missing tool prints `SKIPPED: ...`, and fails under `CI=true`.

use pixelproc_rtl::bank_ram::{GENERIC_VERILOG, MODULE};
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
    std::fs::write(
        &generic,
        GENERIC_VERILOG.replace(MODULE, "generic_bank_ram"),
    )
    .unwrap();
    let ecp5_file = dir.join("ecp5.v");
    std::fs::write(&ecp5_file, ecp5).unwrap();
    let sim = repo().join("synth/ecp5/sim");
    let out = dir.join("tb.vvp");
    let c = Command::new("iverilog")
        .args(["-g2012", "-Wall", "-o"])
        .arg(&out)
        .arg(sim.join("tb_bank_ram.v"))
        .arg(&generic)
        .arg(&ecp5_file)
        .arg(sim.join("dp16kd_model.v"))
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
fn ecp5_bank_ram_matches_the_generic_one() {
    if !tool_available("iverilog") {
        skip_or_fail("iverilog").unwrap();
        return;
    }
    let ecp5 = std::fs::read_to_string(repo().join("synth/ecp5/pixelproc_bank_ram.v")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for seed in [1, 2, 3] {
        let text = run(dir.path(), &ecp5, seed);
        let (compared, changes) =
            passed(&text).unwrap_or_else(|| panic!("seed {seed}: no PASS:\n{text}"));
        // Every clock compared, and the data moving on most of them.
        assert!(compared > 21_000 && changes > 15_000, "seed {seed}: {text}");
    }
    // Wiring mistakes the comparison must catch: (what, text in the module, replacement).
    let mutants: [(&str, &str, &str); 9] = [
        (
            "read address bits 0 and 1 swapped",
            ".ADB4(adb[4]), .ADB5(adb[5])",
            ".ADB4(adb[5]), .ADB5(adb[4])",
        ),
        (
            "write address bits 8 and 9 swapped",
            ".ADA12(ada[12]), .ADA13(ada[13])",
            ".ADA12(ada[13]), .ADA13(ada[12])",
        ),
        (
            "read address one bit low",
            "{read_address, 4'b0000}",
            "{read_address[8:0], 5'b00000}",
        ),
        (
            "write data bits 0 and 1 swapped",
            ".DIA0(write_data[0]), .DIA1(write_data[1])",
            ".DIA0(write_data[1]), .DIA1(write_data[0])",
        ),
        (
            "high byte not enabled",
            "{write_address, 2'b00, 2'b11}",
            "{write_address, 2'b00, 2'b01}",
        ),
        (
            "read data bit 17 from bit 16",
            ".DOB17(dob[17])",
            ".DOB17(dob[16])",
        ),
        (
            "no output register",
            ".REGMODE_B(\"OUTREG\")",
            ".REGMODE_B(\"NOREG\")",
        ),
        (
            "output register never enabled",
            ".OCEB(1'b1)",
            ".OCEB(1'b0)",
        ),
        (
            "read port never selected",
            ".CSDECODE_B(\"0b000\")",
            ".CSDECODE_B(\"0b001\")",
        ),
    ];
    for (what, from, to) in mutants {
        let text = run(dir.path(), &mutant(&ecp5, what, from, to), 1);
        assert!(
            passed(&text).is_none() && text.contains("MISMATCH"),
            "{what}: the comparison did not fail:\n{text}"
        );
    }
}
