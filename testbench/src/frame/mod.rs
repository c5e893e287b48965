//! Whole frames through the exported Verilog of the core
//! (`pixelproc_rtl::core_top::PixelprocCore`), every pixel compared with the golden
//! image.
//!
//! The golden model writes the frame's binned command stream
//! (`pixelproc_sim::core_model::CoreStream`) as `beats.bin`; a C++ harness drives the
//! Verilated core with it, one beat per clock when the core is ready, with seeded random
//! gaps on the input and random `tready` drops on the output (the same xorshift64*
//! sequence as `pixelproc_sim::core_model::Stalls`, so the cycle-level golden model runs
//! the very same clocks), and writes every pixel it takes, with its clock, to
//! `pixels.bin`. The pixels, in stream order, are placed into an image and compared with
//! the golden renderer's no-AA image (and, in the debug configuration, depth, flags,
//! light mask and counter). The cycle counts of the Verilog run must equal the model's.
//!
//! `beats.bin`: per beat five little-endian `u64`: `tdata[63:0]`, …, `tdata[255:192]`,
//! then the kind. `pixels.bin`: per pixel `u32` RGB, `u32` 0, `u64` `tuser | tlast << 63`,
//! `u64` the clock it was taken on (edges after reset).

use crate::TbError;
use pixelproc_rtl::core_top::core_verilog;
use pixelproc_sim::core_model::{
    run_frame, Beat, CoreModel, CoreStream, FrameCycles, PixelBeat, Stalls, DEFAULT_IN_ABITS,
};
use pixelproc_sim::pipeline::render;
use pixelproc_sim::pixel_array::ProcState;
use pixelproc_sim::plan::{AaMethod, Effects};
use pixelproc_sim::scene::LoadedScene;
use pixelproc_sim::shadow::{shadow_lights, FactorTable};
use pixelproc_sim::stream::SceneStream;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command as Proc;

/// The clock the frame time is given at by default, MHz: the routed Fmax of the core
/// (N = 8 with shadows, ECP5, `docs/fpga_results/ecp5_n8.md`; a test keeps the two equal).
pub const DEFAULT_CLOCK_MHZ: f64 = 152.84;

/// What to run.
#[derive(Clone, Debug)]
pub struct FrameSpec {
    /// Array width `N`.
    pub array_width: usize,
    /// Debug configuration: compare depth, flags, mask and counter too.
    pub debug: bool,
    /// Seed of the stall pattern.
    pub seed: u64,
    /// Input gap probability, percent.
    pub gap_pct: u32,
    /// Output stall probability, percent.
    pub stall_pct: u32,
    /// Work folder (Verilog, harness, vectors, VCD).
    pub work: PathBuf,
    /// Folder of cached Verilator builds, one subfolder per hash of the Verilog, the
    /// harness, the flags and the Verilator version.
    pub cache: PathBuf,
    /// Testing the mismatch report: flip the red LSB of the golden value of the `k`-th
    /// streamed pixel, so that the run must report it (position, tile, clock, VCD).
    pub corrupt_golden: Option<usize>,
}

/// The first pixel that differs.
#[derive(Clone, Debug)]
pub struct PixelMismatch {
    /// Screen position.
    pub x: u32,
    /// Screen row.
    pub y: u32,
    /// First column of its tile.
    pub tile_base: u32,
    /// Clock it left the core on (edges after reset), if it did.
    pub clock: Option<u64>,
    /// Golden value.
    pub golden: ProcState,
    /// Verilog value (`None`: never came out).
    pub rtl: Option<ProcState>,
    /// VCD of the clocks around it, when written.
    pub vcd: Option<PathBuf>,
}

/// The outcome of a whole-frame run.
#[derive(Clone, Debug)]
pub struct FrameResult {
    /// Every pixel identical (and the cycle counts equal to the model's).
    pub identical: bool,
    /// Pixels compared.
    pub pixels: usize,
    /// Cycle accounting of the Verilog run (stall figures from its ports).
    pub cycles: FrameCycles,
    /// The model's cycle accounting for the same stall pattern.
    pub model_cycles: FrameCycles,
    /// The model's cycles for the same stream with no stalls (back-to-back input, always
    /// ready output): the frame's own cost.
    pub free_cycles: FrameCycles,
    /// The model's cycles with no stalls for the unbinned stream (every tile fed the
    /// whole row).
    pub unbinned_cycles: u64,
    /// Tile-lines in the frame.
    pub tile_lines: u64,
    /// Verilator build seconds (0 when cached).
    pub build_seconds: f64,
    /// The build came from the cache.
    pub build_cached: bool,
    /// Simulation seconds.
    pub run_seconds: f64,
    /// First differing pixel.
    pub mismatch: Option<PixelMismatch>,
    /// The Verilog's image, RGB8 row-major (unwritten pixels black).
    pub rtl_rgb: Vec<u8>,
    /// The golden image, RGB8.
    pub golden_rgb: Vec<u8>,
    /// Screen width.
    pub width: u32,
    /// Screen height.
    pub height: u32,
    /// The core's `proto_err` at the end.
    pub proto_err: bool,
    /// The Verilog module simulated.
    pub module: String,
}

/// Everything about a scene the core needs, checked before any simulation.
pub struct FramePlan {
    /// The binned stream.
    pub stream: CoreStream,
    /// The model's cycles, no stalls, for the same frame unbinned (every tile fed its
    /// whole row).
    pub unbinned_cycles: u64,
    /// Shadows on.
    pub shadows: bool,
}

/// Builds the core's streams for `ls` under `fx`; a scene the core cannot take is an
/// error here, before any simulation.
pub fn plan_frame(ls: &LoadedScene, fx: &Effects, n: usize) -> Result<FramePlan, TbError> {
    if !matches!(fx.aa, AaMethod::None) {
        return Err(TbError::Core(
            "--frame: the core renders the image without anti-aliasing; use --aa none".into(),
        ));
    }
    let s = SceneStream::of_scene(ls, &fx.shadow_lights, fx.shadow_form, fx.shading)
        .map_err(pixelproc_sim::pipeline::RenderError::from)?;
    let shadows = !fx.shadow_lights.is_empty();
    let table = if shadows {
        let lights =
            shadow_lights(ls, &fx.shadow_lights).map_err(|e| TbError::Core(e.to_string()))?;
        Some(FactorTable::for_mode(ls, &lights, fx.shading))
    } else {
        None
    };
    let core_err = |e: pixelproc_sim::core_model::CoreError| TbError::Core(e.to_string());
    let stream = CoreStream::of_scene(&s, n, table.as_ref()).map_err(core_err)?;
    let unbinned_cycles =
        pixelproc_sim::core_model::unbinned_cycles(&s, n, table.as_ref(), false, DEFAULT_IN_ABITS)
            .map_err(core_err)?
            .cycles;
    Ok(FramePlan {
        stream,
        unbinned_cycles,
        shadows,
    })
}

mod icarus;
mod verilator;

pub use icarus::harness_verilog;
use icarus::run_icarus;
pub use verilator::{harness_cpp, read_pixels, write_beats};
use verilator::{mismatch_vcd, run_verilator};

/// The cycle figures a harness printed (`CYCLES`, `TAKEN`, `IN_STALL`, `OUT_STALL`,
/// `ERR`), with the hazard and issue counts only the model sees; and `proto_err`.
fn harness_report(out: &str, model: &pixelproc_sim::core_model::FrameRun) -> (FrameCycles, bool) {
    let field = |k: &str| stat(out, k).unwrap_or(0.0) as u64;
    (
        FrameCycles {
            cycles: field("CYCLES"),
            beats: field("TAKEN"),
            in_stall: field("IN_STALL"),
            hazard_stall: model.cycles.hazard_stall,
            out_stall: field("OUT_STALL"),
            issued: model.cycles.issued,
        },
        stat(out, "ERR").unwrap_or(1.0) != 0.0,
    )
}

/// Writes the core's Verilog into the work folder; returns the folder, the text and the
/// module name.
fn write_core(
    cs: &CoreStream,
    plan: &FramePlan,
    spec: &FrameSpec,
) -> Result<(PathBuf, String, String), TbError> {
    std::fs::create_dir_all(&spec.work)?;
    let work = spec.work.canonicalize()?;
    let (verilog, module) = core_verilog(cs.array_width as usize, plan.shadows, spec.debug)?;
    std::fs::write(work.join(format!("{module}.v")), &verilog)?;
    Ok((work, verilog, module))
}

fn stat(out: &str, key: &str) -> Option<f64> {
    let mut it = out.split_whitespace();
    while let Some(w) = it.next() {
        if w == key {
            return it.next()?.parse().ok();
        }
    }
    None
}

/// Which simulator runs a whole frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSim {
    /// The exported Verilog in Verilator (any scene).
    Verilator,
    /// The RustHDL core itself, every control register compared with the cycle-level
    /// model every clock (small scenes: a few thousand clocks per second).
    RustHdl,
    /// The exported Verilog in Icarus Verilog (small scenes).
    Icarus,
}

/// What the golden renderer says about every pixel: final RGB (shaded) with the array's
/// depth, flags, mask, counter and normal class.
fn golden_pixels(ls: &LoadedScene, fx: &Effects) -> Result<(Vec<ProcState>, Vec<u8>), TbError> {
    let golden = render(ls, fx)?;
    let gframe = golden
        .frame
        .ok_or_else(|| TbError::Core("the plan ran no pixel-processor array".into()))?;
    let px = gframe
        .px
        .iter()
        .zip(golden.image.data.chunks_exact(3))
        .map(|(s, c)| ProcState {
            rgb: pixelproc_formats::pack_rgb([c[0], c[1], c[2]]),
            ..*s
        })
        .collect();
    Ok((px, golden.image.data))
}

/// Places the pixels `got` (in stream order, with their clocks) and compares them with
/// `golden`: the Verilog image and the first difference (value or framing).
fn compare_pixels(
    cs: &CoreStream,
    golden: &[ProcState],
    got: &[(PixelBeat, u64)],
    debug: bool,
) -> (Vec<u8>, Option<PixelMismatch>) {
    let (w, n) = (cs.width, cs.array_width);
    let mut rtl_rgb = vec![0u8; 3 * cs.pixels()];
    let mut mismatch = None;
    for k in 0..cs.pixels() {
        let (x, y) = cs.position(k);
        let i = (y * w + x) as usize;
        let g = golden[i].without_shade_channel();
        let r = got.get(k).map(|(p, c)| {
            let s = if debug {
                p.state()
            } else {
                ProcState { rgb: p.rgb, ..g }
            };
            let framing = p.sof() == (k == 0) && p.last == (x == w - 1 || (x + 1) % n == 0);
            (s, *c, framing)
        });
        if let Some((s, _, _)) = &r {
            rtl_rgb[3 * i..3 * i + 3].copy_from_slice(&pixelproc_formats::unpack_rgb(s.rgb));
        }
        let ok = r.as_ref().is_some_and(|(s, _, f)| *s == g && *f);
        if mismatch.is_none() && !ok {
            mismatch = Some(PixelMismatch {
                x,
                y,
                tile_base: x / n * n,
                clock: r.as_ref().map(|(_, c, _)| *c),
                golden: g,
                rtl: r.map(|(s, _, _)| s),
                vcd: None,
            });
        }
    }
    (rtl_rgb, mismatch)
}

/// Runs the whole frame of `ls` under `fx` through the core in `sim` and compares every
/// pixel with the golden image; `say` receives progress lines.
pub fn run_frame_check(
    ls: &LoadedScene,
    fx: &Effects,
    spec: &FrameSpec,
    sim: FrameSim,
    say: &mut dyn FnMut(&str),
) -> Result<FrameResult, TbError> {
    let n = spec.array_width;
    let plan = plan_frame(ls, fx, n)?;
    for (kind, tool) in [
        (FrameSim::Verilator, "verilator"),
        (FrameSim::Icarus, "iverilog"),
    ] {
        if sim == kind && !crate::external::tool_available(tool) {
            return Err(TbError::ToolMissing(tool.into()));
        }
    }
    let cs = &plan.stream;
    let (w, h) = (cs.width, cs.height);
    let (mut golden, golden_rgb) = golden_pixels(ls, fx)?;
    if let Some(k) = spec.corrupt_golden.filter(|k| *k < cs.pixels()) {
        let (x, y) = cs.position(k);
        golden[(y * w + x) as usize].rgb ^= 1 << 16;
    }
    // The model: the same clocks as the RTL run, then the stream's own cost.
    let max_cycles = 64 * (cs.beats.len() as u64 + cs.pixels() as u64) + 10_000;
    let new_model = || {
        CoreModel::new(n, plan.shadows, spec.debug, DEFAULT_IN_ABITS)
            .map_err(|e| TbError::Core(e.to_string()))
    };
    let model_run = |beats: &[Beat], px: usize, st: &mut Stalls| -> Result<_, TbError> {
        run_frame(&mut new_model()?, beats, px, st, max_cycles)
            .ok_or_else(|| TbError::Sim("the core model made no progress".into()))
    };
    let stalls = || Stalls::new(spec.seed, spec.gap_pct, spec.stall_pct);
    let model = model_run(&cs.beats, cs.pixels(), &mut stalls())?;
    let free = model_run(&cs.beats, cs.pixels(), &mut Stalls::new(1, 0, 0))?;
    let module = pixelproc_rtl::core_top::core_module_name(n, plan.shadows, spec.debug);
    let mut r = FrameResult {
        identical: false,
        pixels: cs.pixels(),
        cycles: FrameCycles::default(),
        model_cycles: model.cycles.clone(),
        free_cycles: free.cycles,
        unbinned_cycles: plan.unbinned_cycles,
        tile_lines: (h as u64) * (w as u64).div_ceil(n as u64),
        build_seconds: 0.0,
        build_cached: false,
        run_seconds: 0.0,
        mismatch: None,
        rtl_rgb: Vec::new(),
        golden_rgb,
        width: w,
        height: h,
        proto_err: false,
        module: module.clone(),
    };
    let got = match sim {
        FrameSim::Verilator => run_verilator(cs, &plan, spec, max_cycles, &model, &mut r, say)?,
        FrameSim::Icarus => run_icarus(cs, &plan, spec, max_cycles, &model, &mut r, say)?,
        FrameSim::RustHdl => {
            say(&format!(
                "simulating {} beats, {} pixels in RustHDL, every control register compared with the model every clock (seed {}, input gaps {} %, output stalls {} %) ...",
                cs.beats.len(), cs.pixels(), spec.seed, spec.gap_pct, spec.stall_pct
            ));
            let mut uut = pixelproc_rtl::core_top::DefaultCore::new(n, plan.shadows, spec.debug)?;
            rust_hdl::prelude::Block::connect_all(&mut uut);
            let mut m = new_model()?;
            let c = crate::core_tb::compare_core(
                &mut uut,
                &mut m,
                &cs.beats,
                cs.pixels(),
                &mut stalls(),
                max_cycles,
            )?;
            r.run_seconds = c.seconds;
            r.cycles = c.cycles;
            r.proto_err = uut.proto_err.val();
            if let Some(mm) = c.mismatch {
                return Err(TbError::Sim(format!(
                    "the RustHDL core left its cycle model after cycle {}: {}",
                    mm.cycle, mm.what
                )));
            }
            c.pixels
        }
    };
    let (rtl_rgb, mismatch) = compare_pixels(cs, &golden, &got, spec.debug);
    r.rtl_rgb = rtl_rgb;
    r.mismatch = mismatch;
    if let (Some(m), FrameSim::Verilator) = (&mut r.mismatch, sim) {
        m.vcd = mismatch_vcd(
            &spec.work,
            &module,
            m.clock.unwrap_or(r.cycles.cycles),
            spec,
            cs,
            max_cycles,
            say,
        );
    }
    r.identical = r.mismatch.is_none()
        && got.len() == cs.pixels()
        && !r.proto_err
        && r.cycles.cycles == model.cycles.cycles
        && r.cycles.in_stall == model.cycles.in_stall
        && r.cycles.out_stall == model.cycles.out_stall;
    Ok(r)
}
