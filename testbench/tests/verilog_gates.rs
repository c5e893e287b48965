//! The gates every exported Verilog file must pass, as a regression test:
//! `verilator --lint-only -Wall synth/lint.vlt` with no warning at all (the only waivers
//! are the commented ones in `synth/lint.vlt`), and Yosys's generic synthesis with
//! `check -assert` (no latches, no combinational loops, nothing undriven).
//! Under `CI=true` a missing tool fails the test; by hand it is reported as skipped.

use pixelproc_rtl::verilog::{write_mask_search_verilog, write_verilog_dir, TopConfig};
use pixelproc_testbench::external::{skip_or_fail, tool_available, tools_or_skip};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The committed Verilator waiver file.
fn waivers() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../synth/lint.vlt")
}

fn exported(dir: &Path) -> Vec<PathBuf> {
    let mut files = write_verilog_dir(
        &dir.join("shadow"),
        TopConfig {
            width: 8,
            shadows: true,
        },
    )
    .unwrap();
    files.extend(
        write_verilog_dir(
            &dir.join("plain"),
            TopConfig {
                width: 8,
                shadows: false,
            },
        )
        .unwrap(),
    );
    files.extend(write_mask_search_verilog(&dir.join("ms")).unwrap());
    files.sort();
    files.dedup();
    files
}

fn module_of(f: &Path) -> String {
    f.file_stem().unwrap().to_string_lossy().into_owned()
}

#[test]
fn verilator_lint_is_clean_outside_the_waiver_file() {
    if !tool_available("verilator") {
        skip_or_fail("verilator").unwrap();
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut files = exported(dir.path());
    // The arrays at N = 64 too (the one size the synthesis gate leaves out).
    for shadows in [true, false] {
        let sub = dir.path().join(format!("n64{shadows}"));
        let top = TopConfig { width: 64, shadows };
        files.extend(
            write_verilog_dir(&sub, top)
                .unwrap()
                .into_iter()
                .filter(|f| module_of(f).starts_with("pixel_processor_array")),
        );
    }
    assert!(files.len() >= 11, "{files:?}");
    for f in &files {
        let out = Command::new("verilator")
            .args(["--lint-only", "-Wall"])
            .arg(waivers())
            .arg(f)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stderr);
        let mut warnings = Vec::new();
        for line in text.lines() {
            if line.starts_with("%Warning-") {
                warnings.push(line);
            }
            // Verilator ends a run with warnings by "%Error: Exiting due to N warning(s)".
            let summary =
                line.starts_with("%Error: Exiting due to") && line.ends_with("warning(s)");
            assert!(
                !line.starts_with("%Error") || summary,
                "{}: {line}",
                f.display()
            );
        }
        assert!(
            warnings.is_empty(),
            "{}: {} warnings outside synth/lint.vlt's waivers:\n{}",
            f.display(),
            warnings.len(),
            warnings.join("\n")
        );
    }
}

#[test]
fn yosys_synthesis_has_no_latches_or_loops() {
    if !tool_available("yosys") {
        skip_or_fail("yosys").unwrap();
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for f in exported(dir.path()) {
        let m = module_of(&f);
        // `pixelproc_top` (the core) holds the same array: synthesised once, there.
        if m.starts_with("pixel_processor_array") {
            continue;
        }
        // The core's RAMs (FIFOs, the 32K-entry shading table) stay memories: generic
        // synthesis would map them to flip-flops (the FPGA flows map them to block RAM).
        let stages = if m.starts_with("pixelproc_top") {
            " -run begin:fine"
        } else {
            ""
        };
        let script = format!(
            "read_verilog {}; hierarchy -check -top {m}; proc; flatten; synth -top {m}{stages}; check -assert",
            f.display()
        );
        yosys_passes(&script, &m);
    }
}

/// Runs `yosys -q -p script`; fails the test with Yosys's output, under `what`, unless
/// it succeeds.
fn yosys_passes(script: &str, what: &str) {
    let out = Command::new("yosys")
        .args(["-q", "-p", script])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{what}: yosys check -assert failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The pin-level harness of the ECP5 flow (`synth/ecp5/harness.py`, `synth/flow_ecp5.sh …
/// pins`) wraps the exported core, with and without shadows: three ports (`clock`, `si`,
/// `so`), every input of the core driven by its shift register (flattened, an input left
/// open would be an undriven wire, which `check -assert` refuses), no latch or loop.
#[test]
fn the_pin_harness_drives_every_input_of_the_core() {
    if !tools_or_skip(&["yosys", "python3"]) {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = tempfile::tempdir().unwrap();
    for shadows in [true, false] {
        let sub = dir.path().join(if shadows { "shadow" } else { "plain" });
        write_verilog_dir(&sub, TopConfig { width: 8, shadows }).unwrap();
        let (top, harness) = (sub.join("pixelproc_top.v"), sub.join("harness.v"));
        let out = Command::new("python3")
            .arg(root.join("synth/ecp5/harness.py"))
            .args([&top, Path::new("pixelproc_top"), &harness])
            .output()
            .unwrap();
        assert!(out.status.success(), "harness.py: {out:?}");
        let text = std::fs::read_to_string(&harness).unwrap();
        assert!(
            text.starts_with(
                "module pixelproc_top_harness(input wire clock, input wire si, output wire so);"
            ),
            "{text}"
        );
        let script = format!(
            "read_verilog {} {}; hierarchy -check -top pixelproc_top_harness; proc; flatten; \
             opt_clean; check -assert",
            top.display(),
            harness.display()
        );
        yosys_passes(&script, &format!("the harness, shadows {shadows}"));
    }
}
