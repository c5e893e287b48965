//! Every scanline of the default scene (3-D, with shadows) through the RTL array, compared
//! with the golden model; the same run in RustHDL and Verilator (speed comparison).
//! `cargo run --release -p pixelproc-testbench --example scene_run [N] [WIDTH HEIGHT] [rusthdl|verilator|both]`
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_testbench::compare::compare_stream;
use pixelproc_testbench::external::{run_external, ExternalSim};
use pixelproc_testbench::scene_stream;
use pixelproc_testbench::sim_tools::speed_line;
use pixelproc_testbench::stimulus::LineStream;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let n: usize = a.get(1).map(|s| s.parse()).transpose()?.unwrap_or(64);
    let mut ls = pixelproc_sim::scene::load_builtin("default")?;
    if let (Some(w), Some(h)) = (a.get(2), a.get(3)) {
        ls.scene.width = w.parse()?;
        ls.scene.height = h.parse()?;
    }
    let which = a.get(4).map(String::as_str).unwrap_or("both");
    let fx = Effects::resolve(&ls, &Overrides::default())?;
    let (rows, bg) = scene_stream(&ls, &fx)?;
    let s = LineStream {
        width: ls.scene.width,
        bg,
        lines: rows,
    };
    let cmds = s.flatten(n);
    println!(
        "default scene {}x{}, N={n}: {} commands per clock ({} span words)",
        ls.scene.width,
        ls.scene.height,
        cmds.len(),
        s.span_words()
    );
    if which != "verilator" {
        let c = compare_stream(&s, n, true, None)?;
        println!(
            "rusthdl: {} cycles, {:.1} s incl. per-clock compare of every register, {:.0} cycles/s, bit-exact {}",
            c.cycles,
            c.seconds,
            c.cycles as f64 / c.seconds,
            c.bit_exact()
        );
        if let Some(m) = c.mismatch {
            println!("{m}");
        }
    }
    if which != "rusthdl" {
        let dir = std::env::temp_dir().join("pixelproc-scene-verilator");
        if let Some(r) = run_external(ExternalSim::Verilator, &dir, &cmds, n, true)? {
            println!("{}", speed_line("verilator", &r));
        }
    }
    Ok(())
}
