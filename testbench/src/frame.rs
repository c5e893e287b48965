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

/// The clock the frame time is given at by default, MHz: the routed figure of the array
/// (N = 8, ECP5, `docs/rtl.md`). The core at N = 64 is not yet routed at a higher clock.
pub const DEFAULT_CLOCK_MHZ: f64 = 116.95;

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
    let s = SceneStream::of_scene(ls, &fx.shadow_lights, fx.shadow_form)
        .map_err(pixelproc_sim::pipeline::RenderError::from)?;
    let shadows = !fx.shadow_lights.is_empty();
    let table = if shadows {
        let lights =
            shadow_lights(ls, &fx.shadow_lights).map_err(|e| TbError::Core(e.to_string()))?;
        Some(FactorTable::new(ls, &lights))
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

/// The C++ harness for the Verilated module `top` (see the module header).
pub fn harness_cpp(top: &str) -> String {
    format!(
        r#"// Frame harness for {top}: beats.bin in, pixels.bin out; generated by pixelproc.
#include "V{top}.h"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

static uint64_t xs;
static uint64_t xnext() {{
    xs ^= xs >> 12; xs ^= xs << 25; xs ^= xs >> 27;
    return xs * 0x2545F4914F6CDD1DULL;
}}

int main(int argc, char** argv) {{
    if (argc < 8) {{
        std::fprintf(stderr, "usage: %s beats.bin pixels.bin seed gap stall pixels max_cycles [vcd from to]\n", argv[0]);
        return 2;
    }}
    std::FILE* f = std::fopen(argv[1], "rb");
    if (!f) {{ std::perror(argv[1]); return 2; }}
    std::vector<uint64_t> b;
    uint64_t w;
    while (std::fread(&w, 8, 1, f) == 1) b.push_back(w);
    std::fclose(f);
    const size_t nbeats = b.size() / 5;
    uint64_t seed = std::strtoull(argv[3], nullptr, 10);
    xs = seed ? seed : 1;
    const uint64_t gap = std::strtoull(argv[4], nullptr, 10);
    const uint64_t stall = std::strtoull(argv[5], nullptr, 10);
    const uint64_t expect = std::strtoull(argv[6], nullptr, 10);
    const uint64_t max_cycles = std::strtoull(argv[7], nullptr, 10);
    VerilatedContext* ctx = new VerilatedContext;
    V{top}* top = new V{top}{{ctx}};
#if VM_TRACE
    VerilatedVcdC* tfp = nullptr;
    uint64_t vfrom = 0, vto = 0;
    if (argc >= 11) {{
        ctx->traceEverOn(true);
        tfp = new VerilatedVcdC;
        top->trace(tfp, 99);
        tfp->open(argv[8]);
        vfrom = std::strtoull(argv[9], nullptr, 10);
        vto = std::strtoull(argv[10], nullptr, 10);
    }}
#define DUMP(t) do {{ if (tfp && cycle >= vfrom && cycle <= vto) tfp->dump(t); }} while (0)
#else
#define DUMP(t) do {{}} while (0)
#endif
    uint64_t cycle = 0;
    top->rst = 1; top->s_axis_tvalid = 0; top->m_axis_tready = 0;
    top->clock = 0; top->eval();
    top->clock = 1; top->eval();
    top->rst = 0;
    std::FILE* o = std::fopen(argv[2], "wb");
    if (!o) {{ std::perror(argv[2]); return 2; }}
    size_t next = 0;
    bool offered = false;
    uint64_t pixels = 0, in_stall = 0, out_stall = 0;
    auto t0 = std::chrono::steady_clock::now();
    while (pixels < expect && cycle < max_cycles) {{
        uint64_t a = xnext() % 100, r = xnext() % 100;
        bool valid = next < nbeats && (offered || a >= gap);
        offered = valid;
        bool ready = r >= stall;
        top->s_axis_tvalid = valid;
        if (next < nbeats) {{
            for (int i = 0; i < 4; i++) {{
                uint64_t limb = b[5 * next + i];
                top->s_axis_tdata[2 * i] = (uint32_t)limb;
                top->s_axis_tdata[2 * i + 1] = (uint32_t)(limb >> 32);
            }}
            top->s_axis_tuser = (uint8_t)b[5 * next + 4];
        }}
        top->m_axis_tready = ready;
        top->clock = 0; top->eval();
        DUMP(2 * cycle);
        bool sready = top->s_axis_tready, mvalid = top->m_axis_tvalid;
        uint32_t rgb = top->m_axis_tdata;
        uint64_t user = top->m_axis_tuser;
        bool last = top->m_axis_tlast;
        top->clock = 1; top->eval();
        DUMP(2 * cycle + 1);
        if (valid && sready) {{ next++; offered = false; }}
        if (valid && !sready) in_stall++;
        if (mvalid && !ready) out_stall++;
        if (mvalid && ready) {{
            uint32_t rec32[2] = {{rgb, 0}};
            uint64_t rec64[2] = {{user | ((uint64_t)last << 63), cycle}};
            std::fwrite(rec32, 4, 2, o);
            std::fwrite(rec64, 8, 2, o);
            pixels++;
        }}
        cycle++;
    }}
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fclose(o);
    std::printf("CYCLES %llu BEATS %llu TAKEN %llu IN_STALL %llu OUT_STALL %llu PIXELS %llu ERR %d SECONDS %.6f\n",
        (unsigned long long)cycle, (unsigned long long)nbeats, (unsigned long long)next,
        (unsigned long long)in_stall, (unsigned long long)out_stall,
        (unsigned long long)pixels, (int)top->proto_err, secs);
#if VM_TRACE
    if (tfp) tfp->close();
#endif
    top->final();
    delete top;
    delete ctx;
    return 0;
}}
"#
    )
}

/// Writes `beats.bin`.
pub fn write_beats(path: &Path, beats: &[Beat]) -> Result<(), TbError> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    for b in beats {
        for l in b.data {
            f.write_all(&l.to_le_bytes())?;
        }
        f.write_all(&(b.kind as u64).to_le_bytes())?;
    }
    f.flush()?;
    Ok(())
}

/// Reads `pixels.bin`: each pixel with the clock it was taken on.
pub fn read_pixels(path: &Path) -> Result<Vec<(PixelBeat, u64)>, TbError> {
    let bytes = std::fs::read(path)?;
    Ok(bytes
        .chunks_exact(24)
        .map(|r| {
            let u = |a: usize| u64::from_le_bytes(r[a..a + 8].try_into().unwrap_or([0; 8]));
            let rgb = u32::from_le_bytes(r[0..4].try_into().unwrap_or([0; 4]));
            let ul = u(8);
            (
                PixelBeat {
                    rgb,
                    user: ul & !(1 << 63),
                    last: ul >> 63 == 1,
                },
                u(16),
            )
        })
        .collect())
}

/// The Verilator build of the core `top` with the frame harness, from the shared build
/// cache ([`crate::external::verilator_build_cached_in`]); `trace` adds `--trace` (the
/// VCD of a mismatch).
fn core_build(
    cache: &Path,
    top: &str,
    verilog: &str,
    trace: bool,
) -> Result<(PathBuf, crate::external::BuildInfo), TbError> {
    let flags: &[&str] = if trace { &["--trace"] } else { &[] };
    crate::external::verilator_build_cached_in(
        cache,
        top,
        &[(format!("{top}.v"), verilog.to_string())],
        &harness_cpp(top),
        flags,
    )
}

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
        let g = golden[i];
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

/// The arguments of the frame harness.
fn harness_args(
    work: &Path,
    spec: &FrameSpec,
    cs: &CoreStream,
    max_cycles: u64,
    extra: &[String],
) -> Vec<String> {
    let mut a = vec![
        work.join("beats.bin").display().to_string(),
        work.join("pixels.bin").display().to_string(),
        spec.seed.to_string(),
        spec.gap_pct.to_string(),
        spec.stall_pct.to_string(),
        cs.pixels().to_string(),
        max_cycles.to_string(),
    ];
    a.extend_from_slice(extra);
    a
}

/// Builds (or takes from the cache) and runs the Verilated core; fills the build, run and
/// cycle figures of `r`; returns the pixels with their clocks.
fn run_verilator(
    cs: &CoreStream,
    plan: &FramePlan,
    spec: &FrameSpec,
    max_cycles: u64,
    model: &pixelproc_sim::core_model::FrameRun,
    r: &mut FrameResult,
    say: &mut dyn FnMut(&str),
) -> Result<Vec<(PixelBeat, u64)>, TbError> {
    let (work, verilog, module) = write_core(cs, plan, spec)?;
    say(&format!(
        "building {module} in Verilator (cached by the Verilog's hash) ..."
    ));
    let (exe, info) = core_build(&spec.cache, &module, &verilog, false)?;
    r.build_seconds = if info.cached { 0.0 } else { info.seconds };
    r.build_cached = info.cached;
    write_beats(&work.join("beats.bin"), &cs.beats)?;
    say(&format!(
        "simulating {} beats, {} pixels (seed {}, input gaps {} %, output stalls {} %) ...",
        cs.beats.len(),
        cs.pixels(),
        spec.seed,
        spec.gap_pct,
        spec.stall_pct
    ));
    let t0 = std::time::Instant::now();
    let o = Proc::new(&exe)
        .args(harness_args(&work, spec, cs, max_cycles, &[]))
        .output()?;
    r.run_seconds = t0.elapsed().as_secs_f64();
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    if !o.status.success() {
        return Err(TbError::Sim(format!(
            "the Verilated core failed: {out}{}",
            String::from_utf8_lossy(&o.stderr)
        )));
    }
    let pixels_path = work.join("pixels.bin");
    let got = read_pixels(&pixels_path)?;
    let _ = std::fs::remove_file(&pixels_path);
    let _ = std::fs::remove_file(work.join("beats.bin"));
    (r.cycles, r.proto_err) = harness_report(&out, model);
    Ok(got)
}

/// A VCD of the clocks `clock − 200 ..= clock + 20` from a traced build of the core.
fn mismatch_vcd(
    work: &Path,
    module: &str,
    clock: u64,
    spec: &FrameSpec,
    cs: &CoreStream,
    max_cycles: u64,
    say: &mut dyn FnMut(&str),
) -> Option<PathBuf> {
    let work = work.canonicalize().ok()?;
    let verilog = std::fs::read_to_string(work.join(format!("{module}.v"))).ok()?;
    say("building a traced model for the VCD of the mismatch ...");
    let (texe, _) = core_build(&spec.cache, module, &verilog, true).ok()?;
    write_beats(&work.join("beats.bin"), &cs.beats).ok()?;
    let vcd = work.join("frame_mismatch.vcd");
    let extra = [
        vcd.display().to_string(),
        clock.saturating_sub(200).to_string(),
        (clock + 20).to_string(),
    ];
    let ok = Proc::new(&texe)
        .args(harness_args(&work, spec, cs, max_cycles, &extra))
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    let _ = std::fs::remove_file(work.join("pixels.bin"));
    let _ = std::fs::remove_file(work.join("beats.bin"));
    ok.then_some(vcd)
}

/// The Verilog testbench that runs a frame on module `top` in Icarus Verilog: the same
/// stimulus, stall sequence and outputs as [`harness_cpp`], with `beats.hex` (one beat per
/// line: the kind, then `tdata` as 64 hex digits) and `pixels.txt` (`rgb user last clock`
/// in hex, hex, decimal, decimal).
pub fn harness_verilog(
    top: &str,
    beats: usize,
    pixels: usize,
    spec: &FrameSpec,
    max_cycles: u64,
) -> String {
    let in_level_w = pixelproc_sim::core_model::DEFAULT_IN_ABITS + 1;
    format!(
        r#"// Frame testbench for {top} in Icarus Verilog; generated by pixelproc.
`timescale 1ns/1ps
module tb_core;
    localparam integer NBEATS = {beats};
    localparam integer NPIX = {pixels};
    localparam [63:0] MAXC = 64'd{max_cycles};
    localparam [63:0] GAP = 64'd{gap}, STALL = 64'd{stall};
    reg clock = 1'b0, rst = 1'b1;
    reg [259:0] beats [0:NBEATS-1];
    reg s_tvalid = 1'b0, m_tready = 1'b0;
    reg [255:0] s_tdata = 256'd0;
    reg [3:0] s_tuser = 4'd0;
    wire s_tready, m_tvalid, m_tlast, proto_err;
    wire [23:0] m_tdata;
    wire [50:0] m_tuser;
    wire [{lw}:0] in_level;
    {top} dut (.clock(clock), .rst(rst), .s_axis_tvalid(s_tvalid), .s_axis_tready(s_tready),
        .s_axis_tdata(s_tdata), .s_axis_tuser(s_tuser), .m_axis_tvalid(m_tvalid),
        .m_axis_tready(m_tready), .m_axis_tdata(m_tdata), .m_axis_tuser(m_tuser),
        .m_axis_tlast(m_tlast), .proto_err(proto_err), .in_level(in_level));
    reg [63:0] xs, a, r, cycle, in_stall, out_stall;
    integer next, pixels, fd;
    reg offered, valid, ready, sready, mvalid, last;
    reg [23:0] rgb;
    reg [50:0] user;
    task xnext(output [63:0] v);
        begin
            xs = xs ^ (xs >> 12); xs = xs ^ (xs << 25); xs = xs ^ (xs >> 27);
            v = xs * 64'h2545F4914F6CDD1D;
        end
    endtask
    initial begin
        $readmemh("beats.hex", beats);
        fd = $fopen("pixels.txt", "w");
        xs = 64'd{seed};
        next = 0; pixels = 0; cycle = 0; in_stall = 0; out_stall = 0; offered = 1'b0;
        #1 clock = 1'b1; #1 clock = 1'b0; rst = 1'b0;
        while (pixels < NPIX && cycle < MAXC) begin
            xnext(a); xnext(r);
            valid = (next < NBEATS) && (offered || (a % 100) >= GAP);
            offered = valid;
            ready = (r % 100) >= STALL;
            s_tvalid = valid;
            if (next < NBEATS) {{s_tuser, s_tdata}} = beats[next];
            m_tready = ready;
            #1;
            sready = s_tready; mvalid = m_tvalid; rgb = m_tdata; user = m_tuser; last = m_tlast;
            clock = 1'b1; #1 clock = 1'b0;
            if (valid && sready) begin next = next + 1; offered = 1'b0; end
            if (valid && !sready) in_stall = in_stall + 1;
            if (mvalid && !ready) out_stall = out_stall + 1;
            if (mvalid && ready) begin
                $fwrite(fd, "%h %h %0d %0d\n", rgb, user, last, cycle);
                pixels = pixels + 1;
            end
            cycle = cycle + 1;
        end
        $fclose(fd);
        $display("CYCLES %0d TAKEN %0d IN_STALL %0d OUT_STALL %0d PIXELS %0d ERR %0d", cycle, next, in_stall, out_stall, pixels, proto_err);
        $finish;
    end
endmodule
"#,
        lw = in_level_w - 1,
        gap = spec.gap_pct,
        stall = spec.stall_pct,
        seed = spec.seed.max(1),
    )
}

/// Runs the frame in Icarus Verilog; fills the build, run and cycle figures of `r`;
/// returns the pixels with their clocks.
fn run_icarus(
    cs: &CoreStream,
    plan: &FramePlan,
    spec: &FrameSpec,
    max_cycles: u64,
    model: &pixelproc_sim::core_model::FrameRun,
    r: &mut FrameResult,
    say: &mut dyn FnMut(&str),
) -> Result<Vec<(PixelBeat, u64)>, TbError> {
    use std::fmt::Write as _;
    let (work, _, module) = write_core(cs, plan, spec)?;
    let vfile = work.join(format!("{module}.v"));
    let mut hex = String::with_capacity(cs.beats.len() * 66);
    for b in &cs.beats {
        let d = b.data;
        writeln!(
            hex,
            "{:x}{:016x}{:016x}{:016x}{:016x}",
            b.kind, d[3], d[2], d[1], d[0]
        )
        .ok();
    }
    std::fs::write(work.join("beats.hex"), hex)?;
    std::fs::write(
        work.join("tb_core.v"),
        harness_verilog(&module, cs.beats.len(), cs.pixels(), spec, max_cycles),
    )?;
    say(&format!(
        "simulating {module} in Icarus Verilog: {} beats, {} pixels ...",
        cs.beats.len(),
        cs.pixels()
    ));
    let (out, b, t) = crate::external::build_and_run(
        crate::external::ExternalSim::Icarus,
        &work,
        "tb_core",
        &vfile,
    )?;
    r.build_seconds = b;
    r.run_seconds = t;
    let text = std::fs::read_to_string(work.join("pixels.txt"))?;
    let _ = std::fs::remove_file(work.join("pixels.txt"));
    let _ = std::fs::remove_file(work.join("beats.hex"));
    let mut got = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let parse = || -> Option<(PixelBeat, u64)> {
            Some((
                PixelBeat {
                    rgb: u32::from_str_radix(f.first()?, 16).ok()?,
                    user: u64::from_str_radix(f.get(1)?, 16).ok()?,
                    last: f.get(2)? == &"1",
                },
                f.get(3)?.parse().ok()?,
            ))
        };
        got.push(parse().ok_or_else(|| TbError::Sim(format!("bad pixel line `{line}`")))?);
    }
    (r.cycles, r.proto_err) = harness_report(&out, model);
    Ok(got)
}
