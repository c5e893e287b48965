//! The cocotb testbench (`testbench/cocotb/`) on the exported core, in CI: the golden
//! model writes a small scene's command stream (`frame::plan_frame`, the same `beats.hex`
//! as the Icarus frame check) and the expected image in stream order; cocotb drives the
//! core's AXI4-Stream input and sinks its pixels with random stalls and back-pressure
//! (Icarus Verilog; `PIXELPROC_COCOTB_SIMS=icarus,verilator` adds Verilator). A second
//! run with one expected pixel corrupted must fail, so the bench can fail.
//!
//! Needs python3 with cocotb (`pip install cocotb`) and iverilog. Missing tools print
//! `SKIPPED: ...`, and fail under `CI=true`.

use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::load_builtin;
use pixelproc_testbench::frame::plan_frame;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

const N: usize = 8;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// `Some(reason)` when a tool the bench needs is missing.
fn missing_tool(sim: &str) -> Option<String> {
    let py = Command::new("python3")
        .args(["-c", "import cocotb; print(cocotb.__version__)"])
        .output();
    match py {
        Ok(o) if o.status.success() => {}
        _ => return Some("python3 with cocotb (pip install cocotb)".into()),
    }
    let tool = if sim == "icarus" {
        "iverilog"
    } else {
        "verilator"
    };
    if !pixelproc_testbench::external::tool_available(tool) {
        return Some(format!("{tool} (apt-get install {tool})"));
    }
    None
}

/// Writes the core's Verilog, `beats.hex` and `expect.txt` into `dir`; returns the
/// Verilog file, the module and the pixel count.
fn write_inputs(dir: &Path, corrupt: Option<usize>) -> (PathBuf, String, usize) {
    let mut ls = load_builtin("default").unwrap();
    ls.scene.width = 40;
    ls.scene.height = 12;
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    assert!(
        !fx.shadow_lights.is_empty(),
        "the scene exercises the shading step"
    );
    let plan = plan_frame(&ls, &fx, N).unwrap();
    let cs = &plan.stream;
    let mut beats = String::new();
    for b in &cs.beats {
        let d = b.data;
        writeln!(
            beats,
            "{:x}{:016x}{:016x}{:016x}{:016x}",
            b.kind, d[3], d[2], d[1], d[0]
        )
        .unwrap();
    }
    std::fs::write(dir.join("beats.hex"), beats).unwrap();
    let img = render(&ls, &fx).unwrap().image.data;
    let (w, n) = (cs.width, N as u32);
    let mut exp = format!("{} {} {}\n", cs.width, cs.height, N);
    for k in 0..cs.pixels() {
        let (x, y) = cs.position(k);
        let i = 3 * (y * w + x) as usize;
        let mut rgb = (img[i] as u32) << 16 | (img[i + 1] as u32) << 8 | img[i + 2] as u32;
        if corrupt == Some(k) {
            rgb ^= 1 << 16;
        }
        let last = x == w - 1 || (x + 1) % n == 0;
        writeln!(exp, "{rgb:06x} {} {}", u8::from(k == 0), u8::from(last)).unwrap();
    }
    std::fs::write(dir.join("expect.txt"), exp).unwrap();
    let (verilog, module) = pixelproc_rtl::core_top::core_verilog(N, plan.shadows, false).unwrap();
    let vfile = dir.join(format!("{module}.v"));
    std::fs::write(&vfile, verilog).unwrap();
    (vfile, module, cs.pixels())
}

fn run_cocotb(dir: &Path, sim: &str, vfile: &Path, module: &str) -> (bool, String) {
    let t = std::time::Instant::now();
    let o = Command::new("python3")
        .arg(repo().join("testbench/cocotb/run.py"))
        .args(["--sim", sim, "--top", module, "--seed", "5"])
        .arg("--verilog")
        .arg(vfile)
        .arg("--beats")
        .arg(dir.join("beats.hex"))
        .arg("--expect")
        .arg(dir.join("expect.txt"))
        .arg("--build")
        .arg(dir.join(format!("build_{sim}")))
        .current_dir(dir)
        .output()
        .expect("python3 runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    println!(
        "cocotb {sim}: exit {:?}, {:.1} s",
        o.status.code(),
        t.elapsed().as_secs_f64()
    );
    (o.status.success(), text)
}

#[test]
fn cocotb_frame_on_the_exported_core() {
    let sims = std::env::var("PIXELPROC_COCOTB_SIMS").unwrap_or_else(|_| "icarus".into());
    for sim in sims.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        if let Some(what) = missing_tool(sim) {
            let msg = format!("SKIPPED: cocotb frame test ({sim}): {what} not installed");
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!("{msg}");
            }
            println!("{msg}");
            continue;
        }
        let good = tempfile::tempdir().unwrap();
        let (vfile, module, pixels) = write_inputs(good.path(), None);
        let (ok, text) = run_cocotb(good.path(), sim, &vfile, &module);
        assert!(ok, "cocotb on {sim} failed:\n{text}");
        assert!(
            text.contains(&format!("PIXELS {pixels} identical")),
            "no pixel report:\n{text}"
        );
        // The same bench must notice one wrong pixel.
        let bad = tempfile::tempdir().unwrap();
        let (vfile, module, _) = write_inputs(bad.path(), Some(pixels / 2));
        let (ok, text) = run_cocotb(bad.path(), sim, &vfile, &module);
        assert!(
            !ok,
            "cocotb on {sim} passed with a corrupted golden pixel:\n{text}"
        );
        assert!(
            text.contains("golden"),
            "the failure names the pixel:\n{text}"
        );
    }
}
