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
