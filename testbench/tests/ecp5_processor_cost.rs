//! The per-processor cost split of `synth/processor_cost.py` on the core's ECP5 netlist
//! (Yosys `synth_ecp5` of the export at N = 3 with shadows, the flow's ECP5 definitions
//! read over the generic ones; the report's processor is the interior one): every
//! flip-flop of a processor falls in a named part (a renamed register would otherwise
//! drop out of the table unseen), the token holds the flip-flops its fields' widths add
//! up to, and its steps are the carry chains their widths make.
//!
//! Needs yosys and python3. A missing tool prints `SKIPPED: ...`, and fails under
//! `CI=true`.

use pixelproc_rtl::layout::HEAD_W;
use pixelproc_rtl::pixel_processor::{DI3_W, I3_W, REL_W, ZACC_W};
use pixelproc_rtl::verilog::{write_verilog_dir, TopConfig};
use pixelproc_rtl::{bank_ram, mul_reg};
use pixelproc_testbench::external::tools_or_skip;
use std::path::Path;
use std::process::Command;

/// Width of the token's `dZ` field (the span word's).
const DZ_W: usize = pixelproc_formats::SPAN_DZ.width;

/// The numbers of the row of `part` in the report's table.
fn row(report: &str, part: &str) -> Vec<f64> {
    let line = report
        .lines()
        .find(|l| l.starts_with(&format!("| {part} |")))
        .unwrap_or_else(|| panic!("no row `{part}` in:\n{report}"));
    line.split('|')
        .skip(2)
        .filter_map(|c| c.trim().trim_end_matches(" %").parse().ok())
        .collect()
}

#[test]
fn every_processor_register_has_a_part_and_the_token_its_widths() {
    if !tools_or_skip(&["yosys", "python3"]) {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = tempfile::tempdir().unwrap();
    let top = TopConfig {
        width: 3,
        shadows: true,
    };
    write_verilog_dir(dir.path(), top).unwrap();
    // The ECP5 definitions of the wrapped modules, `synth/ecp5/<module>.v` (what the flow
    // reads over the generic ones).
    let ecp5: Vec<String> = [bank_ram::MODULE, mul_reg::MODULE]
        .iter()
        .map(|m| root.join(format!("synth/ecp5/{m}.v")).display().to_string())
        .collect();
    let script = format!(
        "read_verilog pixelproc_top.v; read_verilog -overwrite {}; \
         synth_ecp5 -top pixelproc_top -json top.json",
        ecp5.join(" ")
    );
    let y = Command::new("yosys")
        .current_dir(dir.path())
        .args(["-q", "-p", &script])
        .output()
        .expect("run yosys");
    assert!(y.status.success(), "{}", String::from_utf8_lossy(&y.stderr));
    let out = dir.path().join("cost.md");
    let p = Command::new("python3")
        .arg(root.join("synth/processor_cost.py"))
        .arg(dir.path().join("top.json"))
        .arg("3")
        .arg(&out)
        .args(["test", "yosys"])
        .output()
        .expect("run python3");
    let report = std::fs::read_to_string(&out).unwrap_or_default();
    assert!(
        p.status.success(),
        "{}\n{report}",
        String::from_utf8_lossy(&p.stderr)
    );
    // LUT4, CCU2C, wide multiplexers, FF, slots, share: per processor.
    let token = row(&report, "token");
    let fields = HEAD_W + ZACC_W + DZ_W + I3_W + DI3_W + 1;
    // Yosys shares header bits with earlier processors' registers that hold the same value
    // (the attribute with stage B one processor back, the normal class with stage C two
    // back: 10 bits, counted there) and drops bits nothing reads.
    assert!(
        token[3] <= fields as f64 && token[3] >= (fields - 16) as f64,
        "token flip-flops {} per processor, its fields {fields} bits:\n{report}",
        token[3]
    );
    // The steps' carry chains, two bits per CCU2C: Z, three intensities, two range
    // differences.
    assert_eq!(
        token[1],
        ((ZACC_W + I3_W + 2 * REL_W) / 2) as f64,
        "token CCU2C:\n{report}"
    );
    for part in ["decision", "state", "shadow flags", "readout"] {
        assert!(
            row(&report, part)[3] > 0.0,
            "no flip-flop in {part}:\n{report}"
        );
    }
}
