//! The command line: commands, their flags, and the mapping of the anti-aliasing flags onto
//! the typed configuration of `pixelproc_sim::plan`.

use anyhow::{bail, Result};
use clap::builder::PossibleValuesParser;
use clap::{Args, Parser, Subcommand};
use pixelproc_sim::plan::{parse_mask, parse_param, AaKind, AaSpec, Key, Named, Overrides};
use pixelproc_sim::shadow::{Shading, ShadowForm};
use std::ffi::OsString;
use std::path::PathBuf;

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
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) cmd: Option<Cmd>,
}

#[derive(Subcommand)]
pub(crate) enum Cmd {
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
pub(crate) struct VerilogArgs {
    /// Scene whose effects choose the top's blocks (shadows → span-parity logic).
    #[arg(default_value = "@default")]
    pub(crate) scene: OsString,
    /// Output directory.
    #[arg(
        short,
        long,
        value_name = "DIR",
        default_value = "pixelproc-out/verilog"
    )]
    pub(crate) output: PathBuf,
    #[command(flatten)]
    pub(crate) fx: EffectArgs,
    #[command(flatten)]
    pub(crate) input: InputArgs,
}

#[derive(Args)]
pub(crate) struct TestbenchArgs {
    /// Scene whose span-word stream (and shadow commands) drives the RTL.
    #[arg(default_value = "@default")]
    pub(crate) scene: OsString,
    /// Simulator: the built-in RustHDL model (every register compared every clock), or the
    /// exported Verilog in Icarus Verilog or Verilator (every output compared every clock).
    #[arg(long, default_value = "rusthdl", value_parser = ["rusthdl", "icarus", "verilator"])]
    pub(crate) sim: String,
    /// Only the scanlines FIRST..LAST (inclusive), e.g. 100..120.
    #[arg(long, value_name = "FIRST..LAST")]
    pub(crate) rows: Option<String>,
    /// Folder for vector files, simulator builds and the VCD of a mismatch.
    #[arg(long, value_name = "DIR", default_value = "pixelproc-out/testbench")]
    pub(crate) work: PathBuf,
    /// A whole frame through the core (`pixelproc_core`): its binned command stream in,
    /// its pixel stream collected into an image, every pixel compared with the golden
    /// image, both written as PNGs into the work folder, cycles reported. Runs in
    /// Verilator (`--sim verilator`, any scene) or RustHDL (small scenes).
    #[arg(long, conflicts_with = "rows")]
    pub(crate) frame: bool,
    /// With --frame: the core's debug configuration; depth, shadow flags, light mask,
    /// counter and normal class are compared too.
    #[arg(long, requires = "frame")]
    pub(crate) debug: bool,
    /// Seed of the random input gaps and output back-pressure (--frame, and the search
    /// units' stream run of an A-buffer scene in Verilator).
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// With --frame: percent of clocks the source leaves a gap (0..=90).
    #[arg(long, value_name = "PCT", default_value_t = 20, requires = "frame",
          value_parser = clap::value_parser!(u32).range(0..=90))]
    pub(crate) gaps: u32,
    /// With --frame: percent of clocks the sink drops `tready` (0..=90).
    #[arg(long, value_name = "PCT", default_value_t = 20, requires = "frame",
          value_parser = clap::value_parser!(u32).range(0..=90))]
    pub(crate) stalls: u32,
    /// With --frame: clock for the frame time, in MHz (default: the routed Fmax of the
    /// core in docs/fpga_results/ecp5_n8.md).
    #[arg(long, value_name = "MHZ", default_value_t = pixelproc_testbench::frame::DEFAULT_CLOCK_MHZ,
          value_parser = parse_mhz)]
    pub(crate) clock_mhz: f64,
    #[command(flatten)]
    pub(crate) fx: EffectArgs,
    #[command(flatten)]
    pub(crate) input: InputArgs,
}

/// A clock frequency: a finite number above 0 and at most 10 GHz.
fn parse_mhz(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number of MHz"))?;
    if v.is_finite() && v > 0.0 && v <= 10_000.0 {
        Ok(v)
    } else {
        Err(format!("{s} MHz is outside (0, 10000]"))
    }
}

#[derive(Args)]
pub(crate) struct TradeoffArgs {
    /// Folder of scene files (*.json) instead of the built-in scene set.
    #[arg(long, value_name = "DIR")]
    pub(crate) scenes: Option<PathBuf>,
    /// Output folder.
    #[arg(
        short,
        long,
        value_name = "DIR",
        default_value = "pixelproc-out/tradeoff"
    )]
    pub(crate) output: PathBuf,
    /// Timed runs per setting and scene (the median is reported), 1 to 10000.
    #[arg(long, default_value_t = 3)]
    pub(crate) runs: usize,
    /// A small subset of scenes and settings (tests, CI).
    #[arg(long)]
    pub(crate) quick: bool,
    /// Hardware figures: processors in the array, 1..=4096 (default 64; only N = 8 was
    /// placed and routed, so other widths extrapolate its clock).
    #[arg(
        long,
        value_name = "N",
        default_value = "64",
        allow_hyphen_values = true
    )]
    pub(crate) array_width: String,
    /// Hardware figures: clock in MHz, above 0 and at most 2000 (default: the routed Fmax
    /// of the core at N = 8 without shadows on an ECP5, docs/fpga_results/ecp5_n8_noshadow.md).
    #[arg(
        long,
        value_name = "MHZ",
        default_value_t = pixelproc_bench::HwConfig::DEFAULT.clock_mhz.to_string(),
        allow_hyphen_values = true
    )]
    pub(crate) clock_mhz: String,
}

#[derive(Args, Default)]
pub(crate) struct EffectArgs {
    /// Anti-aliasing method (overrides the scene's `effects.aa`).
    #[arg(long, value_name = "METHOD", value_parser = PossibleValuesParser::new(AaKind::names()))]
    pub(crate) aa: Option<String>,
    /// A-buffer: subpixel grid NxM, e.g. 4x4 (default) or 8x8.
    #[arg(long, value_name = "NxM", help_heading = "Anti-aliasing parameters")]
    pub(crate) mask: Option<String>,
    /// A-buffer: depth per fragment: search (seed 000, default), center, slope, exhaustive.
    #[arg(long, value_name = "SELECT", help_heading = "Anti-aliasing parameters")]
    pub(crate) depth: Option<String>,
    /// Multi-scanning: sub-scanlines per pixel row, 1..=16 (default 3).
    #[arg(long, value_name = "N", help_heading = "Anti-aliasing parameters")]
    pub(crate) subscanlines: Option<u32>,
    /// Multi-scanning: filter box (default), gauss or cone.
    #[arg(long, value_name = "FILTER", help_heading = "Anti-aliasing parameters")]
    pub(crate) filter: Option<String>,
    /// Corner sampling: samples per pixel, 1 (default) or 2 (adds the centre sample).
    #[arg(long, value_name = "N", help_heading = "Anti-aliasing parameters")]
    pub(crate) samples: Option<u32>,
    /// Corner sampling: pattern corner (seed 003, default), d3d4x or grid2x2.
    #[arg(
        long,
        value_name = "PATTERN",
        help_heading = "Anti-aliasing parameters"
    )]
    pub(crate) pattern: Option<String>,
    /// Supersampling: k×k samples per pixel, 1..=64 (default 4).
    #[arg(long, value_name = "K", help_heading = "Anti-aliasing parameters")]
    pub(crate) ssaa: Option<u32>,
    /// Post-process: lines in the pattern window, 5 (seed 004, default) or 3.
    #[arg(long, value_name = "LINES", help_heading = "Anti-aliasing parameters")]
    pub(crate) postfx_window: Option<u32>,
    /// Post-process: edges from normals: off (default), recon (from z) or stored.
    #[arg(long, value_name = "SRC", help_heading = "Anti-aliasing parameters")]
    pub(crate) postfx_normals: Option<String>,
    /// Post-process: second differences from the final z-buffer (final, default) or kept
    /// during drawing (draw).
    #[arg(long, value_name = "SRC", help_heading = "Anti-aliasing parameters")]
    pub(crate) postfx_d2: Option<String>,
    /// A-buffer: also run every depth-selection variant and report where each orders or
    /// resolves fragments differently from exhaustive (slower).
    #[arg(long, help_heading = "Anti-aliasing parameters")]
    pub(crate) compare_depth: bool,
    /// Turn shadows off whatever the scene's lights say.
    #[arg(long)]
    pub(crate) no_shadows: bool,
    /// Number of processors in the array (a wider line is processed in tiles).
    #[arg(long, value_name = "N")]
    pub(crate) array_width: Option<usize>,
    /// How a shadow volume ends: `ev` (hardware: EV span, every processor checks) or
    /// `check` (software form of seed 001: a dummy check span over the volume's range).
    #[arg(long, value_name = "FORM", value_parser = PossibleValuesParser::new(ShadowForm::names()))]
    pub(crate) shadow_form: Option<String>,
    /// How shadowed pixels are shaded: `exact` (spans carry each polygon's intensity
    /// without each shadowing light; the default) or `table` (seed 001 §6: a factor from
    /// the normal class and the light mask).
    #[arg(long, value_name = "MODE", value_parser = PossibleValuesParser::new(Shading::names()))]
    pub(crate) shading: Option<String>,
}

#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Scene file (JSON), or @default / @boxes.
    #[arg(default_value = "@default")]
    pub(crate) scene: OsString,
    /// Output PNG (default: pixelproc-out/<scene name>.png).
    #[arg(short, long, value_name = "OUT.png")]
    pub(crate) output: Option<PathBuf>,
    /// Also write debug images beside the output: depth, shadow, coverage.
    #[arg(long, value_name = "KIND", value_delimiter = ',')]
    pub(crate) aov: Vec<String>,
    #[command(flatten)]
    pub(crate) fx: EffectArgs,
    #[command(flatten)]
    pub(crate) input: InputArgs,
}

#[derive(Args)]
pub(crate) struct BenchArgs {
    /// Scene file (JSON), or @default / @boxes [default: @boxes; with --all-methods: the
    /// generated 1080p scenes].
    pub(crate) scene: Option<OsString>,
    /// Timed runs (after one warm-up), 1 to 10000.
    #[arg(long, default_value_t = 7)]
    pub(crate) runs: usize,
    /// Every anti-aliasing method at its default setting, and shadows, as a table (ratio
    /// to the plain frame, time per unit of work, peak memory): on SCENE if given (at its
    /// own resolution), else on scenes generated at 1920x1080.
    #[arg(long)]
    pub(crate) all_methods: bool,
    #[command(flatten)]
    pub(crate) fx: EffectArgs,
    #[command(flatten)]
    pub(crate) input: InputArgs,
}

impl EffectArgs {
    /// The anti-aliasing parameter flags given, each with the method it belongs to.
    pub(crate) fn aa_flags(&self) -> Vec<(&'static str, AaKind)> {
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

    /// Every effect flag given (`--aa`, its parameters, `--no-shadows`, `--array-width`,
    /// `--shadow-form`, `--shading`), by name.
    pub(crate) fn given(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        if self.aa.is_some() {
            out.push("--aa");
        }
        out.extend(self.aa_flags().into_iter().map(|f| f.0));
        for (on, flag) in [
            (self.no_shadows, "--no-shadows"),
            (self.array_width.is_some(), "--array-width"),
            (self.shadow_form.is_some(), "--shadow-form"),
            (self.shading.is_some(), "--shading"),
        ] {
            if on {
                out.push(flag);
            }
        }
        out
    }

    /// `--aa` and its parameter flags as a typed request; a flag of another method, or
    /// one without `--aa`, is an error.
    pub(crate) fn aa_spec(&self) -> Result<Option<AaSpec>> {
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

pub(crate) fn overrides(fx: &EffectArgs, aovs: &[String]) -> Result<Overrides> {
    Ok(Overrides {
        aa: fx.aa_spec()?,
        no_shadows: fx.no_shadows,
        aovs: aovs.iter().map(|a| a.parse()).collect::<Result<_, _>>()?,
        array_width: fx.array_width,
        shadow_form: fx.shadow_form.as_deref().map(str::parse).transpose()?,
        shading: fx.shading.as_deref().map(str::parse).transpose()?,
    })
}

/// How scene and mesh files are read (`docs/scenes.md`, "Reading rules").
#[derive(Args, Clone, Debug, Default)]
#[command(next_help_heading = "Input")]
pub(crate) struct InputArgs {
    /// Unknown keys in the scene and skipped OBJ statements are errors, not warnings.
    #[arg(long)]
    pub(crate) strict: bool,
    /// Read OBJ meshes only from inside the scene file's folder (no absolute paths, no
    /// `..` out of it, no symlinks leading out).
    #[arg(long)]
    pub(crate) sandbox: bool,
    /// Largest scene or OBJ file read, in MiB.
    #[arg(long, value_name = "MIB", default_value_t = 256, value_parser = clap::value_parser!(u64).range(1..=65536))]
    pub(crate) max_input_mb: u64,
}
