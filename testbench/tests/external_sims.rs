//! The exported Verilog in Icarus Verilog and Verilator against golden vector files.
//! A missing tool prints `SKIPPED: ...` (and fails under `CI=true`).

use pixelproc_sim::pixel_array::Command;
use pixelproc_testbench::external::{run_external, ExternalSim};
use pixelproc_testbench::stimulus::{corner_cases, random_command, Rng};

fn stimulus() -> Vec<(u32, Command)> {
    let mut v: Vec<(u32, Command)> = corner_cases(8).into_iter().map(|c| (0, c)).collect();
    let mut rng = Rng::new(3);
    v.extend((0..300).map(|_| (rng.range(0, 40) as u32, random_command(&mut rng, 48))));
    v.push((0, Command::ClearLine { bg: 0 }));
    v
}

fn check(sim: ExternalSim, tag: &str) {
    // Removed when the test ends, also when it fails.
    let tmp = tempfile::Builder::new()
        .prefix(&format!("pixelproc-ext-{tag}-"))
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    match run_external(sim, dir, &stimulus(), 8, true).unwrap() {
        None => {}
        Some(r) => {
            assert!(r.pass, "{:?} failed:\n{}", sim, r.log);
            assert!(r.cycles > 500 && r.log.contains("PASS"));
        }
    }
}

#[test]
fn icarus_matches_golden_vectors() {
    check(ExternalSim::Icarus, "icarus");
}

#[test]
fn verilator_matches_golden_vectors() {
    check(ExternalSim::Verilator, "verilator");
}
