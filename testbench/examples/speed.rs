//! Simulation speed, same stimulus: RustHDL direct loop vs Verilator vs Icarus.
//! `cargo run --release -p pixelproc-testbench --example speed [N]`
use pixelproc_sim::pixel_array::Command;
use pixelproc_testbench::compare::compare_commands;
use pixelproc_testbench::external::{run_external, ExternalSim};
use pixelproc_testbench::sim_tools::speed_line;
use pixelproc_testbench::stimulus::{random_command, Rng};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(16);
    let mut rng = Rng::new(5);
    let cmds: Vec<(u32, Command)> = (0..20_000)
        .map(|_| (rng.range(0, 64) as u32, random_command(&mut rng, 128)))
        .collect();
    let c = compare_commands(&cmds, n, true, None)?;
    println!(
        "rusthdl N={n}: {} cycles, {:.2} s incl. per-clock golden compare, {:.0} cycles/s, bit-exact {}",
        c.cycles, c.seconds, c.cycles as f64 / c.seconds, c.bit_exact()
    );
    for (sim, tag) in [
        (ExternalSim::Verilator, "verilator"),
        (ExternalSim::Icarus, "icarus"),
    ] {
        let dir = std::env::temp_dir().join(format!("pixelproc-speed-{tag}"));
        if let Some(r) = run_external(sim, &dir, &cmds, n, true)? {
            println!("{}", speed_line(&format!("{tag} N={n}"), &r));
        }
    }
    Ok(())
}
