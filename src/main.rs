//! `pixelproc`: command-line front of the bit-exact scanline back-end model.
//!
//! Thin by design: parse the command line, call the `pixelproc-sim` library, print.

use anyhow::{bail, Context, Result};
use clap::Parser;
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_rtl::verilog::TopConfig;
use pixelproc_sim::input::ReadPolicy;
use pixelproc_sim::pipeline::{render, AaReport, Image, RenderOutput};
use pixelproc_sim::plan::{AaMethod, Effects, Named, Overrides};
use pixelproc_sim::scene::{self, LoadedScene};
use pixelproc_testbench::{Outcome, SimKind};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

mod alloc;
mod args;

use args::*;

/// Large blocks in huge pages where the system offers them (`alloc.rs`).
#[global_allocator]
static GLOBAL: alloc::HugePageAlloc = alloc::HugePageAlloc;
use pixelproc_output::OutputSet;

/// `println!` that ignores a closed stdout (e.g. piped into `head`) instead of panicking.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

/// Loads a scene file or a built-in (`@name`) under the input flags; prints warnings, or
/// fails on them under `--strict`.
fn load(spec: &OsStr, input: &InputArgs) -> Result<LoadedScene> {
    let ls = match spec.to_str().and_then(|s| s.strip_prefix('@')) {
        Some(name) => scene::load_builtin(name)?,
        None => {
            let path = Path::new(spec);
            let policy = ReadPolicy {
                max_bytes: input.max_input_mb << 20,
                sandbox: input.sandbox.then(|| scene::scene_folder(path)),
            };
            scene::load_file_with(path, &policy)?
        }
    };
    if input.strict && !ls.warnings.is_empty() {
        bail!("{} (--strict)", ls.warnings.join("; "));
    }
    for w in &ls.warnings {
        eprintln!("warning: {w}");
    }
    Ok(ls)
}

/// Adds a PNG to an output set (encoded into its temporary file).
fn add_png(out: &mut OutputSet, path: &Path, img: &Image) -> Result<()> {
    let ct = if img.channels == 3 {
        image::ExtendedColorType::Rgb8
    } else {
        image::ExtendedColorType::L8
    };
    out.add_with(path, |f| {
        let enc = image::codecs::png::PngEncoder::new(std::io::BufWriter::new(f));
        image::ImageEncoder::write_image(enc, &img.data, img.width, img.height, ct)?;
        Ok(())
    })
}

fn scene_stem(spec: &OsStr) -> String {
    match spec.to_str().and_then(|s| s.strip_prefix('@')) {
        Some(n) => n.to_string(),
        None => Path::new(spec)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or("out".into()),
    }
}

fn print_timings(out: &RenderOutput) {
    let total: Duration = out.timings.iter().map(|t| t.1).sum();
    for (st, d) in &out.timings {
        say!("  {:<34} {:>9.2} ms", st.to_string(), d.as_secs_f64() * 1e3);
    }
    say!("  {:<34} {:>9.2} ms", "total", total.as_secs_f64() * 1e3);
}

/// Prints the anti-aliasing stage's counters, and the depth-selection comparison when
/// it ran.
fn print_aa_report(aa: &AaMethod, out: &RenderOutput) {
    match &out.aa {
        Some(AaReport::Abuffer(st)) => say!(
            "a-buffer: {} fragments, {} in {} multi-fragment pixels, {} merges, {} depth evaluations ({:.2} per sorted fragment), {} search steps",
            st.fragments,
            st.sorted_fragments,
            st.multi_pixels,
            st.merges,
            st.depth_evals,
            st.depth_evals as f64 / st.sorted_fragments.max(1) as f64,
            st.search_steps
        ),
        Some(AaReport::Other(st)) => say!(
            "{}: {:.2} depth evaluations and {:.3} sample-memory reads per pixel",
            aa.label(),
            st.depth_evals_per_pixel(),
            st.reads_per_pixel()
        ),
        None => {}
    }
    if let Some(AaReport::Abuffer(st)) = &out.aa {
        if st.variant_evals.iter().any(|&e| e > 0) {
            say!(
                "  depth selection vs exhaustive, over {} multi-fragment pixels:",
                st.multi_pixels
            );
            for (k, v) in pixelproc_sim::mask_search::DepthSelect::ALL
                .iter()
                .enumerate()
            {
                say!(
                    "    {:<10} {:>9} evaluations ({:.2}/sorted fragment), order differs in {:>6} px, visible bits in {:>6} px, colour in {:>6} px",
                    v.name(),
                    st.variant_evals[k],
                    st.variant_evals[k] as f64 / st.sorted_fragments.max(1) as f64,
                    st.order_diff[k],
                    st.visible_diff[k],
                    st.rgb_diff[k]
                );
            }
        }
    }
}

fn cmd_render(a: &RenderArgs) -> Result<()> {
    let ls = load(&a.scene, &a.input)?;
    let ov = overrides(&a.fx, &a.aov)?;
    let fx = Effects::resolve(&ls, &ov)?;
    let out_path = a.output.clone().unwrap_or_else(|| {
        PathBuf::from("pixelproc-out").join(format!("{}.png", scene_stem(&a.scene)))
    });
    if out_path.extension().map(|e| e != "png").unwrap_or(true) {
        bail!("-o {}: the output must end in .png", out_path.display());
    }
    let out = render(&ls, &fx)?;
    say!(
        "rendered {} ({}x{}, {} triangles, {} span words, aa {}, array width {})",
        ls.name,
        ls.scene.width,
        ls.scene.height,
        out.triangles,
        out.span_words,
        fx.aa.label(),
        fx.array_width
    );
    if !fx.shadow_lights.is_empty() {
        say!(
            "shadows: lights {:?} ({} shading), {} volumes ({} contain the eye, {} cut by the near plane), {} shadow span words",
            fx.shadow_lights,
            fx.shading.name(),
            out.shadow.volumes,
            out.shadow.eye_inside,
            out.shadow.near_caps,
            out.shadow.span_words
        );
        if out.shadow.sample_passes > 0 {
            say!(
                "shadows sampled like the image: {} array passes at {}'s sample positions",
                out.shadow.sample_passes,
                fx.aa.label()
            );
        }
    }
    print_timings(&out);
    print_aa_report(&fx.aa, &out);
    // The image and its AOVs are written together or not at all.
    let mut files = OutputSet::new();
    add_png(&mut files, &out_path, &out.image)?;
    let stem = out_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    for (aov, img) in &out.aovs {
        let p = out_path.with_file_name(format!("{stem}.{}.png", aov.name()));
        add_png(&mut files, &p, img)?;
    }
    for p in files.commit()? {
        say!("wrote {}", p.display());
    }
    Ok(())
}

/// `--runs`, checked before anything runs (a usage error).
fn check_runs(runs: usize) -> Result<()> {
    pixelproc_bench::timing::check_runs(runs).map_err(|e| UsageError(e).into())
}

fn cmd_bench(a: &BenchArgs) -> Result<()> {
    check_runs(a.runs)?;
    if a.all_methods {
        if let Some(flag) = a.fx.given().first() {
            return Err(UsageError(format!(
                "{flag} cannot be used with --all-methods (it runs every method at its default setting, with and without the scene's lights)"
            ))
            .into());
        }
        return bench_all_methods(a.scene.as_deref(), &a.input, a.runs);
    }
    let ls = load(a.scene.as_deref().unwrap_or("@boxes".as_ref()), &a.input)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    // Long runs say so before they start (stderr, so stdout stays the report).
    eprintln!(
        "bench: {} ({}x{}), 1 warm-up and {} timed runs…",
        ls.name, ls.scene.width, ls.scene.height, a.runs
    );
    let first = render(&ls, &fx)?;
    // Only each run's stage times are kept (not its image): memory stays that of one
    // render however many runs are asked for.
    let mut runs = Vec::with_capacity(a.runs);
    for _ in 0..a.runs {
        runs.push(render(&ls, &fx)?.timings);
    }
    say!(
        "bench {} ({}x{}, {} triangles, aa {}): median of {} runs after 1 warm-up, {} threads",
        ls.name,
        ls.scene.width,
        ls.scene.height,
        first.triangles,
        fx.aa.label(),
        a.runs,
        rayon::current_num_threads()
    );
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    for (k, (st, _)) in first.timings.iter().enumerate() {
        let m = median(runs.iter().map(|r| r[k].1.as_secs_f64()).collect());
        say!("  {:<34} {:>9.2} ms", st.to_string(), m * 1e3);
    }
    let tot = median(
        runs.iter()
            .map(|r| r.iter().map(|t| t.1.as_secs_f64()).sum())
            .collect(),
    );
    say!("  {:<34} {:>9.2} ms", "total", tot * 1e3);
    Ok(())
}

/// `bench --all-methods [SCENE]`: the table of `pixelproc_bench::methods`, on `scene` if
/// given, else on the generated scenes.
fn bench_all_methods(scene: Option<&OsStr>, input: &InputArgs, runs: usize) -> Result<()> {
    use pixelproc_bench::methods::{bench_scenes, run_all_methods, table};
    let scenes = match scene {
        Some(s) => vec![load(s, input)?],
        None => bench_scenes()?,
    };
    say!(
        "bench --all-methods: median of {runs} interleaved runs after 1 warm-up, {} threads",
        rayon::current_num_threads()
    );
    let rows = run_all_methods(&scenes, runs, |s| eprintln!("  {s}…"))?;
    say!("{}", table(&rows));
    Ok(())
}

/// The hardware configuration a scene's effects call for.
fn top_config(fx: &Effects) -> TopConfig {
    TopConfig {
        width: fx.array_width,
        shadows: !fx.shadow_lights.is_empty(),
    }
}

fn parse_rows(spec: &str, height: u32) -> Result<std::ops::RangeInclusive<u32>> {
    let (a, b) = spec
        .split_once("..")
        .with_context(|| format!("--rows {spec}: expected FIRST..LAST, e.g. 100..120"))?;
    let num = |v: &str| -> Result<u32> {
        v.trim()
            .parse()
            .map_err(|_| anyhow::anyhow!("--rows {spec}: `{}` is not a row number", v.trim()))
    };
    let (a, b) = (num(a)?, num(b)?);
    if a > b || b >= height {
        bail!("--rows {spec}: need FIRST <= LAST < {height}");
    }
    Ok(a..=b)
}

/// Runs the scene's stream on the RTL; prints the summary. Returns bit-exactness.
fn run_testbench(
    ls: &LoadedScene,
    fx: &Effects,
    sim: SimKind,
    rows: Option<&str>,
    work: &Path,
) -> Result<bool> {
    let (mut lines, bg) = pixelproc_testbench::scene_stream(ls, fx)?;
    let mut first = 0;
    if let Some(r) = rows {
        let r = parse_rows(r, ls.scene.height)?;
        first = *r.start();
        lines = lines
            .drain(*r.start() as usize..=*r.end() as usize)
            .collect();
    }
    let top = top_config(fx);
    let n_lines = lines.len();
    // Long runs say so before they start (stderr, so stdout stays the report).
    eprintln!(
        "testbench: {} scanlines of {} on {:?}{}…",
        n_lines,
        ls.name,
        sim,
        match sim {
            SimKind::RustHdl => ", every register compared every clock",
            SimKind::Verilator =>
                ", compiling the exported Verilog first (about a minute on 2 cores)",
            SimKind::Icarus => ", compiling the exported Verilog first",
        }
    );
    let s = pixelproc_testbench::testbench(
        lines,
        bg,
        ls.scene.width,
        top.width,
        top.shadows,
        sim,
        work,
    )?;
    if s.outcome.skipped() {
        say!("{}", s.outcome);
        return Ok(true);
    }
    say!(
        "testbench {} on {:?}: rows {}..{} ({} scanlines), array of {} processors {} shadow logic",
        ls.name,
        sim,
        first,
        first as usize + n_lines.saturating_sub(1),
        n_lines,
        top.width,
        if top.shadows { "with" } else { "without" }
    );
    say!(
        "  bit-exact: {}  ({} span words, {} cycles compared, run {:.2} s, {:.0} cycles/s{})",
        if s.outcome.bit_exact() { "yes" } else { "NO" },
        s.span_words,
        s.cycles,
        s.seconds,
        s.cycles as f64 / s.seconds.max(1e-9),
        if sim == SimKind::RustHdl {
            String::new()
        } else {
            format!(", build {:.1} s", s.build_seconds)
        }
    );
    if let Outcome::Mismatch(detail) = &s.outcome {
        say!("{detail}");
    }
    Ok(s.outcome.bit_exact())
}

fn cmd_testbench(a: &TestbenchArgs) -> Result<bool> {
    let ls = load(&a.scene, &a.input)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    let sim = match a.sim.as_str() {
        "icarus" => SimKind::Icarus,
        "verilator" => SimKind::Verilator,
        _ => SimKind::RustHdl,
    };
    // Everything the run needs is checked before the first clock.
    if let Some(r) = &a.rows {
        parse_rows(r, ls.scene.height)?;
    }
    if let AaMethod::Abuffer(p) = &fx.aa {
        if ![MaskSize::S4X4, MaskSize::S8X8].contains(&p.size) {
            bail!(
                "--mask {}: the RTL mask search unit exists for 4x4 and 8x8 only",
                p.size
            );
        }
    }
    if a.frame {
        return cmd_frame(a, &ls, &fx, sim);
    }
    let mut ok = run_testbench(&ls, &fx, sim, a.rows.as_deref(), &a.work)?;
    // The search unit only when the scene asks for the A-buffer.
    if let AaMethod::Abuffer(p) = &fx.aa {
        use pixelproc_testbench::mask_search_tb::{loaded_scene_jobs, search_unit_check_jobs};
        let jobs = loaded_scene_jobs(&ls, p.size)?;
        for v in pixelproc_rtl::mask_search::Variant::ALL {
            let s = search_unit_check_jobs(v, p.size, &jobs, sim, &a.work.join("mask_search"))?;
            if s.skipped() {
                say!("{}", s.detail);
                continue;
            }
            say!(
                "testbench {} mask search unit {:?} {} on {:?}: bit-exact: {}  ({} fragment searches, {} cycles, {:.2} s)",
                ls.name,
                v,
                p.size,
                sim,
                if s.bit_exact { "yes" } else { "NO" },
                s.jobs,
                s.cycles,
                s.seconds
            );
            if !s.bit_exact {
                say!("{}", s.detail);
            }
            ok &= s.bit_exact;
        }
        // The stream version of each unit on the scene's whole search stream, with random
        // gaps and back-pressure (Verilator: the whole stream is long).
        if sim == SimKind::Verilator {
            use pixelproc_testbench::mask_search_tb::run_search_stream;
            for v in pixelproc_rtl::mask_search::Variant::ALL {
                let s = run_search_stream(&ls, p.size, v, sim, a.seed)?;
                say!("testbench {} search stream: {s}", ls.name);
                if !s.identical {
                    say!("{}", s.detail);
                }
                ok &= s.identical;
            }
        }
    }
    Ok(ok)
}

/// `testbench --frame`: a whole frame through the core, every pixel compared.
fn cmd_frame(a: &TestbenchArgs, ls: &LoadedScene, fx: &Effects, sim: SimKind) -> Result<bool> {
    use pixelproc_testbench::frame::{plan_frame, run_frame_check, FrameSim, FrameSpec};
    let fsim = match sim {
        SimKind::Verilator => FrameSim::Verilator,
        SimKind::RustHdl => FrameSim::RustHdl,
        SimKind::Icarus => FrameSim::Icarus,
    };
    // Everything the core cannot take is an error before any simulation.
    let plan = plan_frame(ls, fx, fx.array_width)?;
    let spec = FrameSpec {
        array_width: fx.array_width,
        debug: a.debug,
        seed: a.seed,
        gap_pct: a.gaps,
        stall_pct: a.stalls,
        work: a.work.clone(),
        cache: pixelproc_testbench::external::verilator_cache_dir(),
        corrupt_golden: None,
    };
    if fsim != FrameSim::Verilator && plan.stream.pixels() > 100_000 {
        eprintln!(
            "testbench: {} pixels in {:?} runs at a few thousand clocks per second; --sim verilator is much faster",
            plan.stream.pixels(),
            fsim
        );
    }
    let progress = indicatif::ProgressBar::new_spinner();
    if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        progress.enable_steady_tick(std::time::Duration::from_millis(120));
    } else {
        progress.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let mut say_progress = |m: &str| {
        if progress.is_hidden() {
            eprintln!("testbench: {m}");
        } else {
            progress.set_message(m.to_string());
        }
    };
    let r = run_frame_check(ls, fx, &spec, fsim, &mut say_progress)?;
    progress.finish_and_clear();
    let mut files = OutputSet::new();
    let img = |data: Vec<u8>| Image {
        width: r.width,
        height: r.height,
        channels: 3,
        data,
    };
    let rtl_png = a.work.join("frame_rtl.png");
    let golden_png = a.work.join("frame_golden.png");
    add_png(&mut files, &rtl_png, &img(r.rtl_rgb.clone()))?;
    add_png(&mut files, &golden_png, &img(r.golden_rgb.clone()))?;
    files.commit()?;
    let c = &r.cycles;
    say!(
        "frame {} {}x{} through {} ({:?}): identical: {}",
        ls.name,
        r.width,
        r.height,
        r.module,
        fsim,
        if r.identical { "yes" } else { "NO" }
    );
    say!(
        "  pixels compared: {} ({})",
        r.pixels,
        if a.debug {
            "RGB, depth, DSF, FSF, counter, light mask, normal class"
        } else {
            "RGB"
        }
    );
    say!(
        "  cycles: {} with stalls (seed {}, input gaps {} %, output stalls {} %): source held by the core {}, readout-hazard waits {}, sink not ready {}; the cycle model {}",
        c.cycles,
        a.seed,
        a.gaps,
        a.stalls,
        c.in_stall,
        c.hazard_stall,
        c.out_stall,
        if c.cycles == r.model_cycles.cycles && c.in_stall == r.model_cycles.in_stall && c.out_stall == r.model_cycles.out_stall {
            "agrees".to_string()
        } else {
            format!("says {} cycles", r.model_cycles.cycles)
        }
    );
    let per_line = r.free_cycles.cycles as f64 / r.height.max(1) as f64;
    let ms = r.free_cycles.cycles as f64 / (a.clock_mhz * 1e3);
    say!(
        "  frame cost (no stalls): {} cycles, {:.1} per scanline, {} beats, {} tile-lines; unbinned stream: {} cycles ({:.2}x)",
        r.free_cycles.cycles,
        per_line,
        r.free_cycles.beats,
        r.tile_lines,
        r.unbinned_cycles,
        r.unbinned_cycles as f64 / r.free_cycles.cycles.max(1) as f64
    );
    say!(
        "  at {} MHz: {:.3} ms per frame, {:.1} frames/s",
        a.clock_mhz,
        ms,
        1e3 / ms.max(1e-12)
    );
    say!(
        "  build: {}, run: {:.2} s ({:.0} cycles/s)",
        if fsim == FrameSim::RustHdl {
            "none (RustHDL)".to_string()
        } else if fsim == FrameSim::Icarus {
            format!("{:.1} s (iverilog)", r.build_seconds)
        } else if r.build_cached {
            "cached".to_string()
        } else {
            format!("{:.1} s", r.build_seconds)
        },
        r.run_seconds,
        c.cycles as f64 / r.run_seconds.max(1e-9)
    );
    if r.proto_err {
        say!("  the core raised proto_err");
    }
    if let Some(m) = &r.mismatch {
        say!(
            "  first differing pixel ({}, {}) in the tile at column {} of row {}, clock {}:\n    golden {:?}\n    rtl    {}",
            m.x,
            m.y,
            m.tile_base,
            m.y,
            m.clock.map_or("-".into(), |c| c.to_string()),
            m.golden,
            m.rtl.map_or("never streamed out".into(), |s| format!("{s:?}"))
        );
        if let Some(v) = &m.vcd {
            say!("  trace of the clocks around it: {}", v.display());
        }
    }
    say!("wrote {} and {}", rtl_png.display(), golden_png.display());
    Ok(r.identical)
}

/// The no-argument run: render the embedded scene, check a few of its scanlines on the
/// RTL in the built-in RustHDL simulator, and export its Verilog.
fn cmd_default() -> Result<()> {
    cmd_render(&RenderArgs {
        scene: "@default".into(),
        output: None,
        aov: vec![],
        fx: EffectArgs::default(),
        input: InputArgs::default(),
    })?;
    let ls = load(OsStr::new("@default"), &InputArgs::default())?;
    let fx = Effects::resolve(&ls, &Overrides::default())?;
    if !run_testbench(
        &ls,
        &fx,
        SimKind::RustHdl,
        Some("176..179"),
        Path::new("pixelproc-out/testbench"),
    )? {
        bail!("the RTL and the golden model disagree on the embedded scene");
    }
    cmd_verilog(&VerilogArgs {
        scene: "@default".into(),
        output: PathBuf::from("pixelproc-out/verilog"),
        fx: EffectArgs::default(),
        input: InputArgs::default(),
    })
}

fn cmd_verilog(a: &VerilogArgs) -> Result<()> {
    use pixelproc_rtl::verilog::{is_exported_file_name, mask_search_files, verilog_files};
    let ls = load(&a.scene, &a.input)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    let top = top_config(&fx);
    say!(
        "{}: top (pixelproc_top) = the streaming core around a pixel-processor array of {} processors, {} (docs/core.md)",
        ls.name,
        top.width,
        if top.shadows {
            "with span-parity logic and the shading table"
        } else {
            "without shadow logic"
        }
    );
    let mut texts = verilog_files(top)?;
    if matches!(fx.aa, AaMethod::Abuffer(_)) {
        say!("{}: the scene asks for the A-buffer: mask search unit (iterative and pipelined, 4x4 and 8x8)", ls.name);
        texts.extend(mask_search_files()?);
    }
    let mut files = OutputSet::new();
    for (name, text) in &texts {
        files.add(&a.output.join(name), text.as_bytes())?;
    }
    let written = files.commit()?;
    for f in &written {
        say!("wrote {}", f.display());
    }
    // The command owns the exported file names in its folder: remove the ones this run
    // did not write (e.g. an array of another width from an earlier run).
    for e in std::fs::read_dir(&a.output)?.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if is_exported_file_name(&name) && !written.contains(&e.path()) && e.path().is_file() {
            std::fs::remove_file(e.path())
                .with_context(|| format!("cannot remove stale {}", e.path().display()))?;
            say!("removed stale {}", e.path().display());
        }
    }
    Ok(())
}

/// The hardware configuration of `pixelproc tradeoff`, checked (one-line errors).
/// A bad flag value found after parsing: reported on one line, exit code 2 (a usage error,
/// as clap's own).
#[derive(Debug)]
struct UsageError(String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

fn tradeoff_hw(a: &TradeoffArgs) -> Result<pixelproc_bench::HwConfig> {
    let width_err = || {
        UsageError(format!(
            "--array-width {}: expected a whole number of processors, 1..=4096",
            a.array_width
        ))
    };
    let clock_err = || {
        UsageError(format!(
            "--clock-mhz {}: expected a frequency in MHz above 0 and at most 2000",
            a.clock_mhz
        ))
    };
    let n: u64 = a.array_width.trim().parse().map_err(|_| width_err())?;
    let mhz: f64 = a.clock_mhz.trim().parse().map_err(|_| clock_err())?;
    // Errors name the value as typed (`nan`, not `NaN`).
    pixelproc_bench::HwConfig::new(n, mhz).map_err(|e| {
        anyhow::Error::new(match e {
            pixelproc_sim::hwcost::HwCostError::Clock(_) => clock_err(),
            _ => width_err(),
        })
    })
}

fn cmd_tradeoff(a: &TradeoffArgs) -> Result<()> {
    use pixelproc_bench::{run_tradeoff_with, TradeoffOptions};
    check_runs(a.runs)?;
    let hw = tradeoff_hw(a)?;
    let mut command = String::from("pixelproc tradeoff");
    if let Some(d) = &a.scenes {
        command += &format!(" --scenes {}", d.display());
    }
    command += &format!(" -o {} --runs {}", a.output.display(), a.runs);
    if a.quick {
        command += " --quick";
    }
    command += &format!(
        " --array-width {} --clock-mhz {}",
        hw.array_width, hw.clock_mhz
    );
    let (sw, w) = run_tradeoff_with(
        &TradeoffOptions {
            scenes_dir: a.scenes.clone(),
            out_dir: a.output.clone(),
            runs: a.runs,
            quick: a.quick,
            progress: true,
            command,
        },
        &hw,
    )?;
    say!(
        "{} settings × {} scenes, median of {} runs on one thread; hardware model at 1920x1080, N = {}, {} MHz",
        sw.rows.len(),
        sw.scenes.len(),
        sw.runs,
        hw.array_width,
        hw.clock_mhz
    );
    for p in [&w.csv, &w.scenes_csv, &w.markdown, &w.chart]
        .into_iter()
        .chain(w.hw_chart.as_ref())
        .chain(w.heatmap.as_ref())
        .chain(w.hd_csv.as_ref())
    {
        say!("wrote {}", p.display());
    }
    Ok(())
}

/// Exit codes: 0 success; 1 an error (bad input, a failed run, RTL and golden model
/// disagree); 2 a command-line usage error (from clap, or a flag value checked after
/// parsing).
fn main() -> ExitCode {
    let cli = Cli::parse();
    let res = match &cli.cmd {
        None => cmd_default(),
        Some(Cmd::Render(a)) => cmd_render(a),
        Some(Cmd::Bench(a)) => cmd_bench(a),
        Some(Cmd::Verilog(a)) => cmd_verilog(a),
        Some(Cmd::Testbench(a)) => cmd_testbench(a).and_then(|ok| {
            if ok {
                Ok(())
            } else {
                bail!("the RTL and the golden model disagree")
            }
        }),
        Some(Cmd::Tradeoff(a)) => cmd_tradeoff(a),
    };
    match res {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Returning (not `process::exit`) runs every destructor: temporaries go.
            eprintln!("error: {e:#}");
            if e.downcast_ref::<UsageError>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
