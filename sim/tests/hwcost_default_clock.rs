//! The default clock of the hardware figures is the routed Fmax of the core without
//! shadows: the flow script's report `docs/fpga_results/ecp5_n8_noshadow.md` is read and
//! parsed here, so a re-route that changes the figure fails this test until
//! `HwConfig::DEFAULT.clock_mhz` follows it.

use std::path::PathBuf;

use pixelproc_sim::hwcost::HwConfig;

/// The report of the routed `N = 8` core without shadows.
fn report_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/fpga_results/ecp5_n8_noshadow.md")
}

/// The cells of a Markdown table row (`| a | b |` → `["a", "b"]`), or `None` for a line
/// that is not a table row.
fn cells(line: &str) -> Option<Vec<String>> {
    let l = line.trim();
    if !(l.starts_with('|') && l.ends_with('|') && l.len() >= 2) {
        return None;
    }
    Some(
        l[1..l.len() - 1]
            .split('|')
            .map(|c| c.trim().to_string())
            .collect(),
    )
}

/// The `achieved` cell of the `clock` row of the report's `## Fmax` table, in MHz.
fn parse_fmax(text: &str) -> Result<f64, String> {
    let mut lines = text
        .lines()
        .skip_while(|l| l.trim() != "## Fmax")
        .skip(1)
        .take_while(|l| !l.starts_with("## "))
        .filter_map(cells);
    let header = lines
        .next()
        .ok_or("no table under \"## Fmax\"".to_string())?;
    let col = header
        .iter()
        .position(|c| c == "achieved")
        .ok_or(format!("no `achieved` column in {header:?}"))?;
    for row in lines {
        if row.first().map(|c| c.trim_matches('`')) == Some("clock") {
            let cell = row.get(col).ok_or(format!("short row {row:?}"))?;
            let num = cell
                .strip_suffix("MHz")
                .ok_or(format!("`{cell}` is not in MHz"))?
                .trim();
            return num.parse().map_err(|e| format!("`{cell}`: {e}"));
        }
    }
    Err("no `clock` row in the Fmax table".into())
}

#[test]
fn parser_reads_the_flow_scripts_table() {
    // The layout the flow script writes, with another figure: the parser takes the
    // `achieved` column of the `clock` row, not the constraint.
    let text = "# x\n\n## Fmax\n\n| clock | achieved | constraint | met |\n|---|---:|---:|---|\n| `clock` | 91.25 MHz | 150.01 MHz | no |\n\n## Utilisation\n\n| clock | achieved |\n|---|---|\n| `clock` | 1.00 MHz |\n";
    assert_eq!(parse_fmax(text), Ok(91.25));
    assert!(parse_fmax("## Fmax\n\nnothing routed\n").is_err());
    assert!(parse_fmax("| `clock` | 91.25 MHz |\n").is_err());
}

#[test]
fn default_clock_is_the_routed_noshadow_fmax() {
    let p = report_path();
    let text =
        std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("reading {}: {e}", p.display()));
    let fmax = parse_fmax(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let got = HwConfig::DEFAULT.clock_mhz;
    assert!(
        (got - fmax).abs() <= 0.005,
        "HwConfig::DEFAULT.clock_mhz is {got} MHz but the routed no-shadow core reaches \
         {fmax} MHz (docs/fpga_results/ecp5_n8_noshadow.md): update `clock_mhz` of \
         `HwConfig::DEFAULT` in sim/src/hwcost/mod.rs (and the figures of docs/accuracy.md, \
         regenerated with `cargo run --release -- tradeoff --runs 5`)"
    );
}
