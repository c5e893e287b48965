//! The Verilog checked in under `synth/rtl/` (read by FuseSoC's `pixelproc.core`, the
//! formal checks and the flow scripts) must be exactly what the Rust RTL exports today
//! (N = 8, shadows). Regenerate with `synth/regen.sh`.

use pixelproc_rtl::verilog::{verilog_files, TopConfig};
use std::path::Path;

#[test]
fn checked_in_verilog_matches_the_export() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../synth/rtl");
    let files = verilog_files(TopConfig {
        width: 8,
        shadows: true,
    })
    .unwrap();
    let mut checked = 0;
    for name in ["pixelproc_top.v", "span_parity.v"] {
        let (_, text) = files
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("the export has no {name}"));
        let on_disk = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        assert!(
            on_disk == *text,
            "synth/rtl/{name} differs from the Verilog the Rust RTL exports now \
             ({} vs {} bytes); regenerate it with `synth/regen.sh` and commit the result",
            on_disk.len(),
            text.len()
        );
        checked += 1;
    }
    assert_eq!(checked, 2);
}

/// The frame time's default clock (`pixelproc testbench --frame`) is the Fmax of the
/// committed routed report of the core (`docs/fpga_results/ecp5_n8.md`, N = 8 with
/// shadows, written by `synth/flow_ecp5.sh 8 1 shadow`): re-routing changes the report,
/// and this fails until `DEFAULT_CLOCK_MHZ` follows.
#[test]
fn default_frame_clock_is_the_routed_figure() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/fpga_results/ecp5_n8.md");
    let text = std::fs::read_to_string(&path).expect("docs/fpga_results/ecp5_n8.md");
    // The Fmax table's row: | `clock` | 99.14 MHz | 150.01 MHz | no |
    let row = text
        .lines()
        .find(|l| l.starts_with("| `clock` |"))
        .expect("the report has no `clock` row in its Fmax table");
    let mhz: f64 = row
        .split('|')
        .nth(2)
        .and_then(|c| c.trim().strip_suffix(" MHz"))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("cannot read the achieved Fmax from {row:?}"));
    let ours = pixelproc_testbench::frame::DEFAULT_CLOCK_MHZ;
    assert!(
        (ours - mhz).abs() < 0.005,
        "pixelproc_testbench::frame::DEFAULT_CLOCK_MHZ is {ours} MHz but the routed report \
         says {mhz} MHz: update the constant (and docs/core.md's frame-time column)"
    );
}
