//! `pixelproc`: command-line front of the bit-exact scanline back-end model.
//!
//! Thin by design: parse the command line, call the `pixelproc-sim` library, print.

use anyhow::{bail, Context, Result};
use clap::builder::PossibleValuesParser;
use clap::{Args, Parser, Subcommand};
use pixelproc_rtl::verilog::TopConfig;
use pixelproc_sim::pipeline::{render, AaReport, Image, RenderOutput};
use pixelproc_sim::plan::{
    parse_mask, parse_param, AaKind, AaMethod, AaSpec, Effects, Key, Named, Overrides,
};
use pixelproc_sim::scene::{self, LoadedScene};
use pixelproc_sim::shadow::ShadowForm;
use pixelproc_testbench::{Outcome, SimKind};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// `println!` that ignores a closed stdout (e.g. piped into `head`) instead of panicking.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

#[derive(Parser)]
#[command(
    name = "pixelproc",
    version,
    about = "Bit-exact model of a scanline pixel-processor rendering back-end",
    long_about = "Bit-exact model of a scanline pixel-processor rendering back-end.\n\n\
        With no command, renders the embedded default scene into pixelproc-out/ and \
        prints the stages it ran.\nScenes are JSON files (see docs/scenes.md) or a \
        built-in name: @default, @boxes."
)]
struct Cli {
    #[command(subcommand)]
    cmd: Option<Cmd>,
}

#[derive(Subcommand)]
enum Cmd {
    /// Render a scene to a PNG.
    Render(RenderArgs),
    /// Render a scene several times and print the median time of each stage.
    Bench(BenchArgs),
    /// Write the Verilog of the blocks a scene's effects call for (and every block).
    Verilog(VerilogArgs),
    /// Run a scene's span-word stream through the RTL and the golden model, clock by
    /// clock, and report whether they agree bit for bit.
    Testbench(TestbenchArgs),
    /// Measure every anti-aliasing method and setting: error against the exact
    /// reference, time, cost; writes CSV, Markdown, a chart and heat maps.
    Tradeoff(TradeoffArgs),
}

#[derive(Args)]
struct VerilogArgs {
    /// Scene whose effects choose the top's blocks (shadows → span-parity logic).
    #[arg(default_value = "@default")]
    scene: String,
    /// Output directory.
    #[arg(
        short,
        long,
        value_name = "DIR",
        default_value = "pixelproc-out/verilog"
    )]
    output: PathBuf,
    #[command(flatten)]
    fx: EffectArgs,
}

#[derive(Args)]
struct TestbenchArgs {
    /// Scene whose span-word stream (and shadow commands) drives the RTL.
    #[arg(default_value = "@default")]
    scene: String,
    /// Simulator: the built-in RustHDL model (every register compared every clock), or the
    /// exported Verilog in Icarus Verilog or Verilator (every output compared every clock).
    #[arg(long, default_value = "rusthdl", value_parser = ["rusthdl", "icarus", "verilator"])]
    sim: String,
    /// Only the scanlines FIRST..LAST (inclusive), e.g. 100..120.
    #[arg(long, value_name = "FIRST..LAST")]
    rows: Option<String>,
    /// Folder for vector files, simulator builds and the VCD of a mismatch.
    #[arg(long, value_name = "DIR", default_value = "pixelproc-out/testbench")]
    work: PathBuf,
    #[command(flatten)]
    fx: EffectArgs,
}

#[derive(Args)]
struct TradeoffArgs {
    /// Folder of scene files (*.json) instead of the built-in scene set.
    #[arg(long, value_name = "DIR")]
    scenes: Option<PathBuf>,
    /// Output folder.
    #[arg(
        short,
        long,
        value_name = "DIR",
        default_value = "pixelproc-out/tradeoff"
    )]
    output: PathBuf,
    /// Timed runs per setting and scene (the median is reported).
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// A small subset of scenes and settings (tests, CI).
    #[arg(long)]
    quick: bool,
}

#[derive(Args)]
struct EffectArgs {
    /// Anti-aliasing method (overrides the scene's `effects.aa`).
    #[arg(long, value_name = "METHOD", value_parser = PossibleValuesParser::new(AaKind::names()))]
    aa: Option<String>,
    /// A-buffer: subpixel grid NxM, e.g. 4x4 (default) or 8x8.
    #[arg(long, value_name = "NxM", help_heading = "Anti-aliasing parameters")]
    mask: Option<String>,
    /// A-buffer: depth per fragment: search (seed 000, default), center, slope, exhaustive.
    #[arg(long, value_name = "SELECT", help_heading = "Anti-aliasing parameters")]
    depth: Option<String>,
    /// Multi-scanning: sub-scanlines per pixel row, 1..=16 (default 3).
    #[arg(long, value_name = "N", help_heading = "Anti-aliasing parameters")]
    subscanlines: Option<u32>,
    /// Multi-scanning: filter box (default), gauss or cone.
    #[arg(long, value_name = "FILTER", help_heading = "Anti-aliasing parameters")]
    filter: Option<String>,
    /// Corner sampling: samples per pixel, 1 (default) or 2 (adds the centre sample).
    #[arg(long, value_name = "N", help_heading = "Anti-aliasing parameters")]
    samples: Option<u32>,
    /// Corner sampling: pattern corner (seed 003, default), d3d4x or grid2x2.
    #[arg(
        long,
        value_name = "PATTERN",
        help_heading = "Anti-aliasing parameters"
    )]
    pattern: Option<String>,
    /// Supersampling: k×k samples per pixel, 1..=64 (default 4).
    #[arg(long, value_name = "K", help_heading = "Anti-aliasing parameters")]
    ssaa: Option<u32>,
    /// Post-process: lines in the pattern window, 5 (seed 004, default) or 3.
    #[arg(long, value_name = "LINES", help_heading = "Anti-aliasing parameters")]
    postfx_window: Option<u32>,
    /// Post-process: edges from normals: off (default), recon (from z) or stored.
    #[arg(long, value_name = "SRC", help_heading = "Anti-aliasing parameters")]
    postfx_normals: Option<String>,
    /// Post-process: second differences from the final z-buffer (final, default) or kept
    /// during drawing (draw).
    #[arg(long, value_name = "SRC", help_heading = "Anti-aliasing parameters")]
    postfx_d2: Option<String>,
    /// A-buffer: also run every depth-selection variant and report where each orders or
    /// resolves fragments differently from exhaustive (slower).
    #[arg(long, help_heading = "Anti-aliasing parameters")]
    compare_depth: bool,
    /// Turn shadows off whatever the scene's lights say.
    #[arg(long)]
    no_shadows: bool,
    /// Number of processors in the array (a wider line is processed in tiles).
    #[arg(long, value_name = "N")]
    array_width: Option<usize>,
    /// How a shadow volume ends: `ev` (hardware: EV span, every processor checks) or
    /// `check` (software form of seed 001: a dummy check span over the volume's range).
    #[arg(long, value_name = "FORM", value_parser = PossibleValuesParser::new(ShadowForm::names()))]
    shadow_form: Option<String>,
}

impl EffectArgs {
    fn none() -> EffectArgs {
        EffectArgs {
            aa: None,
            mask: None,
            depth: None,
            subscanlines: None,
            filter: None,
            samples: None,
            pattern: None,
            ssaa: None,
            postfx_window: None,
            postfx_normals: None,
            postfx_d2: None,
            compare_depth: false,
            no_shadows: false,
            array_width: None,
            shadow_form: None,
        }
    }
}

#[derive(Args)]
struct RenderArgs {
    /// Scene file (JSON), or @default / @boxes.
    #[arg(default_value = "@default")]
    scene: String,
    /// Output PNG (default: pixelproc-out/<scene name>.png).
    #[arg(short, long, value_name = "OUT.png")]
    output: Option<PathBuf>,
    /// Also write debug images beside the output: depth, shadow, coverage.
    #[arg(long, value_name = "KIND", value_delimiter = ',')]
    aov: Vec<String>,
    #[command(flatten)]
    fx: EffectArgs,
}

#[derive(Args)]
struct BenchArgs {
    /// Scene file (JSON), or @default / @boxes.
    #[arg(default_value = "@boxes")]
    scene: String,
    /// Timed runs (after one warm-up).
    #[arg(long, default_value_t = 7)]
    runs: usize,
    #[command(flatten)]
    fx: EffectArgs,
}

fn load(spec: &str) -> Result<LoadedScene> {
    Ok(match spec.strip_prefix('@') {
        Some(name) => scene::load_builtin(name)?,
        None => scene::load_file(Path::new(spec))?,
    })
}

impl EffectArgs {
    /// The anti-aliasing parameter flags given, each with the method it belongs to.
    fn aa_flags(&self) -> Vec<(&'static str, AaKind)> {
        use AaKind::*;
        [
            (self.mask.is_some(), "--mask", Abuffer),
            (self.depth.is_some(), "--depth", Abuffer),
            (self.subscanlines.is_some(), "--subscanlines", Multiscan),
            (self.filter.is_some(), "--filter", Multiscan),
            (self.samples.is_some(), "--samples", Corner),
            (self.pattern.is_some(), "--pattern", Corner),
            (self.ssaa.is_some(), "--ssaa", Ssaa),
            (self.postfx_window.is_some(), "--postfx-window", PostFx),
            (self.postfx_normals.is_some(), "--postfx-normals", PostFx),
            (self.postfx_d2.is_some(), "--postfx-d2", PostFx),
            (self.compare_depth, "--compare-depth", Abuffer),
        ]
        .into_iter()
        .filter(|f| f.0)
        .map(|(_, flag, owner)| (flag, owner))
        .collect()
    }

    /// `--aa` and its parameter flags as a typed request; a flag of another method, or
    /// one without `--aa`, is an error.
    fn aa_spec(&self) -> Result<Option<AaSpec>> {
        let flags = self.aa_flags();
        let Some(m) = &self.aa else {
            if !flags.is_empty() {
                bail!("anti-aliasing parameters need --aa METHOD");
            }
            return Ok(None);
        };
        let kind: AaKind = m.parse()?;
        if let Some((flag, owner)) = flags.iter().find(|f| f.1 != kind) {
            bail!("{flag} applies to --aa {owner}, not --aa {kind}");
        }
        /// Overwrites a default with a flag's value, if given.
        fn set<T>(dst: &mut T, v: Option<T>) {
            if let Some(v) = v {
                *dst = v;
            }
        }
        /// A named flag's value, parsed.
        fn name<T: Named>(field: &'static str, v: &Option<String>) -> Result<Option<T>> {
            Ok(v.as_deref()
                .map(|s| parse_param(Key::flag(field), s))
                .transpose()?)
        }
        let mut spec = AaSpec::default_for(kind);
        match &mut spec {
            AaSpec::None => {}
            AaSpec::Abuffer(p) => {
                if let Some(s) = &self.mask {
                    p.mask = parse_mask(Key::flag("mask"), s)?;
                }
                set(&mut p.depth, name("depth", &self.depth)?);
                p.compare_depth = self.compare_depth;
            }
            AaSpec::Multiscan(p) => {
                set(&mut p.subscanlines, self.subscanlines);
                set(&mut p.filter, name("filter", &self.filter)?);
            }
            AaSpec::Corner(p) => {
                set(&mut p.samples, self.samples);
                set(&mut p.pattern, name("pattern", &self.pattern)?);
            }
            AaSpec::PostFx(p) => {
                set(&mut p.postfx_window, self.postfx_window);
                set(
                    &mut p.postfx_normals,
                    name("postfx_normals", &self.postfx_normals)?,
                );
                set(&mut p.postfx_d2, name("postfx_d2", &self.postfx_d2)?);
            }
            AaSpec::Ssaa(p) => set(&mut p.ssaa, self.ssaa),
        }
        Ok(Some(spec))
    }
}

fn overrides(fx: &EffectArgs, aovs: &[String]) -> Result<Overrides> {
    Ok(Overrides {
        aa: fx.aa_spec()?,
        no_shadows: fx.no_shadows,
        aovs: aovs.iter().map(|a| a.parse()).collect::<Result<_, _>>()?,
        array_width: fx.array_width,
        shadow_form: fx.shadow_form.as_deref().map(str::parse).transpose()?,
    })
}

/// Writes a PNG atomically: a temporary file in the same directory, renamed on success.
fn write_png(path: &Path, img: &Image) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let tmp = tempfile::Builder::new()
        .prefix(".pixelproc-")
        .suffix(".png")
        .tempfile_in(dir)
        .with_context(|| format!("cannot write into {}", dir.display()))?;
    let ct = if img.channels == 3 {
        image::ExtendedColorType::Rgb8
    } else {
        image::ExtendedColorType::L8
    };
    image::save_buffer_with_format(
        tmp.path(),
        &img.data,
        img.width,
        img.height,
        ct,
        image::ImageFormat::Png,
    )
    .with_context(|| format!("cannot encode {}", path.display()))?;
    tmp.persist(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

fn scene_stem(spec: &str) -> String {
    match spec.strip_prefix('@') {
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
    let ls = load(&a.scene)?;
    let ov = overrides(&a.fx, &a.aov)?;
    let fx = Effects::resolve(&ls, &ov)?;
    let out_path = a.output.clone().unwrap_or_else(|| {
        PathBuf::from("pixelproc-out").join(format!("{}.png", scene_stem(&a.scene)))
    });
    if out_path.extension().map(|e| e != "png").unwrap_or(true) {
        bail!("output {} must end in .png", out_path.display());
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
            "shadows: lights {:?}, {} volumes ({} contain the eye), {} shadow span words",
            fx.shadow_lights,
            out.shadow.volumes,
            out.shadow.eye_inside,
            out.shadow.span_words
        );
    }
    print_timings(&out);
    print_aa_report(&fx.aa, &out);
    write_png(&out_path, &out.image)?;
    say!("wrote {}", out_path.display());
    for (aov, img) in &out.aovs {
        let stem = out_path.file_stem().unwrap().to_string_lossy();
        let p = out_path.with_file_name(format!("{stem}.{}.png", aov.name()));
        write_png(&p, img)?;
        say!("wrote {}", p.display());
    }
    Ok(())
}

fn cmd_bench(a: &BenchArgs) -> Result<()> {
    if a.runs == 0 {
        bail!("--runs must be at least 1");
    }
    let ls = load(&a.scene)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    let first = render(&ls, &fx)?;
    let mut runs = Vec::new();
    for _ in 0..a.runs {
        runs.push(render(&ls, &fx)?);
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
        let m = median(runs.iter().map(|r| r.timings[k].1.as_secs_f64()).collect());
        say!("  {:<34} {:>9.2} ms", st.to_string(), m * 1e3);
    }
    let tot = median(
        runs.iter()
            .map(|r| r.timings.iter().map(|t| t.1.as_secs_f64()).sum())
            .collect(),
    );
    say!("  {:<34} {:>9.2} ms", "total", tot * 1e3);
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
        .context("--rows takes FIRST..LAST, e.g. 100..120")?;
    let (a, b): (u32, u32) = (a.trim().parse()?, b.trim().parse()?);
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
        "  bit-exact: {}  ({} span words, {} cycles compared, {:.2} s, {:.0} cycles/s)",
        if s.outcome.bit_exact() { "yes" } else { "NO" },
        s.span_words,
        s.cycles,
        s.seconds,
        s.cycles as f64 / s.seconds.max(1e-9)
    );
    if let Outcome::Mismatch(detail) = &s.outcome {
        say!("{detail}");
    }
    Ok(s.outcome.bit_exact())
}

fn cmd_testbench(a: &TestbenchArgs) -> Result<bool> {
    let ls = load(&a.scene)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    let sim = match a.sim.as_str() {
        "icarus" => SimKind::Icarus,
        "verilator" => SimKind::Verilator,
        _ => SimKind::RustHdl,
    };
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
    }
    Ok(ok)
}

/// The no-argument run: render the embedded scene, check a few of its scanlines on the
/// RTL in the built-in RustHDL simulator, and export its Verilog.
fn cmd_default() -> Result<()> {
    cmd_render(&RenderArgs {
        scene: "@default".into(),
        output: None,
        aov: vec![],
        fx: EffectArgs::none(),
    })?;
    let ls = load("@default")?;
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
        fx: EffectArgs::none(),
    })
}

fn cmd_verilog(a: &VerilogArgs) -> Result<()> {
    let ls = load(&a.scene)?;
    let fx = Effects::resolve(&ls, &overrides(&a.fx, &[])?)?;
    let top = top_config(&fx);
    let files = pixelproc_rtl::verilog::write_verilog_dir(&a.output, top)
        .with_context(|| format!("cannot write Verilog into {}", a.output.display()))?;
    say!(
        "{}: top = pixel-processor array of {} processors, {} span-parity logic",
        ls.name,
        top.width,
        if top.shadows { "with" } else { "without" }
    );
    for f in files {
        say!("wrote {}", f.display());
    }
    if matches!(fx.aa, AaMethod::Abuffer(_)) {
        say!("{}: the scene asks for the A-buffer: mask search unit (iterative and pipelined, 4x4 and 8x8)", ls.name);
        let files = pixelproc_rtl::verilog::write_mask_search_verilog(&a.output)
            .with_context(|| format!("cannot write Verilog into {}", a.output.display()))?;
        for f in files {
            say!("wrote {}", f.display());
        }
    }
    Ok(())
}

fn cmd_tradeoff(a: &TradeoffArgs) -> Result<()> {
    use pixelproc_bench::{run_tradeoff, TradeoffOptions};
    let mut command = String::from("pixelproc tradeoff");
    if let Some(d) = &a.scenes {
        command += &format!(" --scenes {}", d.display());
    }
    command += &format!(" -o {} --runs {}", a.output.display(), a.runs);
    if a.quick {
        command += " --quick";
    }
    let (sw, w) = run_tradeoff(&TradeoffOptions {
        scenes_dir: a.scenes.clone(),
        out_dir: a.output.clone(),
        runs: a.runs,
        quick: a.quick,
        progress: true,
        command,
    })?;
    say!(
        "{} settings × {} scenes, median of {} runs on one thread",
        sw.rows.len(),
        sw.scenes.len(),
        sw.runs
    );
    for p in [&w.csv, &w.scenes_csv, &w.markdown, &w.chart]
        .into_iter()
        .chain(w.heatmap.as_ref())
    {
        say!("wrote {}", p.display());
    }
    Ok(())
}

fn main() {
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
    if let Err(e) = res {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
