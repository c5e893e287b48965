//! Runs the mask search unit check and prints the summary:
//! `mask_search_check [iter|pipe|both] [exhaustive|scene:NAME|random:N] [rusthdl|icarus|verilator] [4x4|8x8]`.
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_rtl::mask_search::Variant;
use pixelproc_testbench::mask_search_tb::{search_unit_check, Stimulus};
use pixelproc_testbench::SimKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let variants = match arg(1, "both").as_str() {
        "iter" => vec![Variant::Iterative],
        "pipe" => vec![Variant::Pipelined],
        _ => Variant::ALL.to_vec(),
    };
    let st = arg(2, "exhaustive");
    let stim = if let Some(n) = st.strip_prefix("scene:") {
        Stimulus::Scene(n.to_string())
    } else if let Some(n) = st.strip_prefix("random:") {
        Stimulus::Random {
            count: n.parse()?,
            seed: 1,
        }
    } else {
        Stimulus::Exhaustive
    };
    let sim = match arg(3, "rusthdl").as_str() {
        "icarus" => SimKind::Icarus,
        "verilator" => SimKind::Verilator,
        _ => SimKind::RustHdl,
    };
    let size = MaskSize::parse(&arg(4, "4x4"))?;
    for v in variants {
        let dir = std::env::temp_dir().join(format!("pixelproc-msu-{}-{:?}", v.name(), sim));
        let t = std::time::Instant::now();
        let s = search_unit_check(v, size, &stim, sim, &dir)?;
        println!(
            "{} {} {:?} {:?}: jobs {} cycles {} bit_exact {} sim {:.2} s ({:.0} cycles/s) build {:.1} s, total {:.1} s{}",
            v.name(),
            size,
            sim,
            stim,
            s.jobs,
            s.cycles,
            s.bit_exact,
            s.seconds,
            s.cycles as f64 / s.seconds.max(1e-9),
            s.build_seconds,
            t.elapsed().as_secs_f64(),
            if s.detail.is_empty() { String::new() } else { format!("\n{}", s.detail) }
        );
    }
    Ok(())
}
