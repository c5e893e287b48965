//! Clock-by-clock comparison of the RTL mask search unit (`pixelproc_rtl::mask_search`,
//! seed 000) with the golden `pixelproc_sim::mask_search::SearchUnit`, in RustHDL, Icarus
//! Verilog and Verilator.
//!
//! **Schedule.** The golden model alone turns a list of search jobs (fraction mask, start
//! corner, depth plane) into per-clock port vectors: `inputs[t]` is driven before rising
//! edge `t + 1`, `expect[t]` is what every output must show after that edge (vector 0 is
//! the reset clock).
//! - Iterative variant: `expect[t]` holds the golden `SearchUnit::step()` output of the
//!   state after edge `t + 1` (`active`, `line`, `search_mask`, `and_result`, `zero`,
//!   `moved`, `hit`, `done`) and `ready = !active | done`; a job is started on the next
//!   vector whenever `ready` (so the golden model decides the handshake), and the golden
//!   `start` follows the `step` exactly as the RTL's start overrides its state at the edge.
//!   The result of a search shown as `done` in `expect[t]` is due in `expect[t + 6]`.
//! - Pipelined variant: one job per vector (optionally with bubbles); the job of vector
//!   `t` is due in `expect[t + latency]`; in RustHDL every stage's registers are also
//!   compared each clock with the golden search state after `k` steps.
//! - Result fields: golden `SearchUnit::run` (steps, first non-zero AND result), the golden
//!   compacted ROM (`SearchTables::offset_rom(..).pack()`), and the golden depth calculator
//!   (`depth_calc`): `z1`, `z2` (= `z1` without a pair), min, max; an empty mask reads ROM
//!   word 0 and every depth `zc` (the golden `DepthSelector` fallback). They are compared
//!   whenever a result is due; `out_valid` is compared on every clock.
//!
//! **Stimulus.** [`Stimulus::Exhaustive`]: every 4×4 mask × 4 corners with a pseudo-random
//! plane per job (full 48-bit range, extremes included); [`Stimulus::Random`];
//! [`Stimulus::Scene`]: the fragments the golden A-buffer builds at the multi-fragment
//! pixels of a built-in scene (mask, start corner of the min search, plane), plus the
//! max search from the opposite corner.
//!
//! **Mismatch.** The first differing clock is reported with its inputs and both outputs,
//! and the run up to it is replayed in the traced RustHDL simulator into `mismatch.vcd`
//! (external simulators dump their own VCD).

use crate::external::{skip_or_fail, tool_available};
use crate::{SimKind, TbError};
use pixelproc_formats::abuffer::{Corner, FragPlane, MaskSize, SearchFamily, PLANE_MAX};
use pixelproc_rtl::mask_search::{
    mask_search_verilog, MaskSearchIter, MaskSearchPipe, Variant, BACK_LATENCY, Z_BITS,
};
use pixelproc_sim::abuffer::FragSetup;
use pixelproc_sim::mask_search::{depth_calc, SearchTables, SearchUnit, StepOutput};
use rust_hdl::prelude::*;
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One search: what the unit is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchJob {
    /// Fraction mask.
    pub mask: u64,
    /// Start corner.
    pub corner: Corner,
    /// Depth plane.
    pub plane: FragPlane,
}

/// The stimulus of a check.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stimulus {
    /// Every 4×4 mask × 4 corners (262,144 searches).
    Exhaustive,
    /// `count` random masks (biased towards sparse and edge-like masks), random corners
    /// and planes.
    Random {
        /// Number of jobs.
        count: usize,
        /// Seed.
        seed: u64,
    },
    /// The multi-fragment pixels of a built-in scene (`scene::load_builtin`).
    Scene(String),
}

/// Outcome of a check.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Variant checked.
    pub variant: Variant,
    /// Mask size.
    pub size: MaskSize,
    /// Simulator.
    pub sim: SimKind,
    /// Searches fed.
    pub jobs: usize,
    /// Clock cycles simulated.
    pub cycles: u64,
    /// Seconds of simulation (external: the run, not the build).
    pub seconds: f64,
    /// Seconds to build the external simulator (0 for RustHDL).
    pub build_seconds: f64,
    /// Every compared value identical.
    pub bit_exact: bool,
    /// First mismatch (or `SKIPPED: ...` when a tool is missing outside CI).
    pub detail: String,
    /// Trace of the failing run, if one was written.
    pub vcd: Option<PathBuf>,
}

impl Summary {
    /// True if the check was skipped because a tool is missing.
    pub fn skipped(&self) -> bool {
        self.detail.starts_with("SKIPPED")
    }
}

/// xorshift64*.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn plane_field(&mut self) -> i64 {
        let r = self.next();
        match r % 8 {
            0 => PLANE_MAX,
            1 => -PLANE_MAX,
            2 => (r >> 8) as i64 % 4096 - 2048,
            3 => 0,
            _ => ((r >> 16) as i64 % PLANE_MAX) * if r & 0x100 != 0 { -1 } else { 1 },
        }
    }
    fn plane(&mut self) -> FragPlane {
        FragPlane {
            zc: self.plane_field(),
            sx: self.plane_field(),
            sy: self.plane_field(),
        }
    }
}

/// Every 4×4 mask × 4 corners, with a pseudo-random plane per job.
pub fn exhaustive_jobs() -> Vec<SearchJob> {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut v = Vec::with_capacity(4 << 16);
    for mask in 0..=0xFFFFu64 {
        for corner in Corner::ALL {
            v.push(SearchJob {
                mask,
                corner,
                plane: rng.plane(),
            });
        }
    }
    v
}

/// Random jobs for `size`: a third uniform masks, a third sparse (1–3 bits), a third
/// half-plane masks (edge pixels), random corners and planes.
pub fn random_jobs(size: MaskSize, count: usize, seed: u64) -> Vec<SearchJob> {
    let mut rng = Rng(seed | 1);
    let full = size.full();
    (0..count)
        .map(|k| {
            let r = rng.next();
            let mask = match k % 3 {
                0 => r & full,
                1 => (0..1 + r % 3).fold(0u64, |a, _| a | 1 << (rng.next() % size.bits() as u64)),
                _ => {
                    // Subpixels on one side of a random line through the pixel.
                    let (a, b, c) = (
                        (rng.next() % 33) as i64 - 16,
                        (rng.next() % 33) as i64 - 16,
                        (rng.next() % 65) as i64 - 32,
                    );
                    let mut m = 0u64;
                    for b_ in 0..size.bits() {
                        let (col, row) = size.col_row(b_);
                        let o = size.offset(col, row);
                        if a * o.dx as i64 + b * o.dy as i64 + c > 0 {
                            m |= 1 << b_;
                        }
                    }
                    m
                }
            };
            SearchJob {
                mask,
                corner: Corner::from_code((r >> 60) as u8),
                plane: rng.plane(),
            }
        })
        .collect()
}

/// The fragments at the multi-fragment pixels of built-in scene `name` (golden front end,
/// golden fraction masks and planes, as the A-buffer renderer builds them): each gives a
/// min search from `Corner::of_min(sx, sy)` and a max search from the opposite corner.
pub fn scene_jobs(name: &str, size: MaskSize) -> Result<Vec<SearchJob>, TbError> {
    let ls = pixelproc_sim::scene::load_builtin(name).map_err(|e| TbError::Sim(e.to_string()))?;
    loaded_scene_jobs(&ls, size)
}

/// As [`scene_jobs`], for a scene already loaded (a file or a built-in).
pub fn loaded_scene_jobs(
    ls: &pixelproc_sim::scene::LoadedScene,
    size: MaskSize,
) -> Result<Vec<SearchJob>, TbError> {
    use pixelproc_sim::frontend;
    let err = |e: String| TbError::Sim(e);
    let proj = frontend::project(ls).map_err(|e| err(e.to_string()))?;
    let (w, h) = (ls.scene.width, ls.scene.height);
    let mut setups = Vec::new();
    for (k, t) in proj.tris.iter().enumerate() {
        if let Some(s) = FragSetup::new(t, k as u32, size).map_err(|e| err(e.to_string()))? {
            setups.push(s);
        }
    }
    // Triangles per row (clamped to the screen).
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); h as usize];
    for (k, s) in setups.iter().enumerate() {
        let lo = s.edges.row_min.max(0);
        let hi = s.edges.row_max.min(h as i64 - 1);
        for j in lo..=hi {
            rows[j as usize].push(k);
        }
    }
    let mut jobs = Vec::new();
    let mut entries: Vec<(i64, usize, u64)> = Vec::new();
    for j in 0..h as i64 {
        entries.clear();
        for &k in &rows[j as usize] {
            let s = &setups[k];
            let Some(rc) = s.edges.row_coverage(j, w) else {
                continue;
            };
            for i in rc.touched.0..=rc.touched.1 {
                let mask = s.edges.fraction_mask(i, j);
                if mask != 0 {
                    entries.push((i, k, mask));
                }
            }
        }
        entries.sort_by_key(|e| e.0);
        let mut a = 0;
        while a < entries.len() {
            let mut b = a;
            while b < entries.len() && entries[b].0 == entries[a].0 {
                b += 1;
            }
            if b - a >= 2 {
                for &(i, k, mask) in &entries[a..b] {
                    let f = setups[k].fragment(i, j, mask);
                    let c = Corner::of_min(f.plane.sx, f.plane.sy);
                    for corner in [c, c.opposite()] {
                        jobs.push(SearchJob {
                            mask: f.mask,
                            corner,
                            plane: f.plane,
                        });
                    }
                }
            }
            a = b;
        }
    }
    Ok(jobs)
}

/// Input port values of one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InVec {
    /// `rst`.
    pub rst: bool,
    /// `in_valid`.
    pub valid: bool,
    /// `in_mask`.
    pub mask: u64,
    /// `in_corner`.
    pub corner: u8,
    /// `in_zc`, `in_sx`, `in_sy` (48-bit fields).
    pub plane: [u64; 3],
}

/// Result ports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResultPorts {
    /// `out_valid`.
    pub valid: bool,
    /// `out_hit`.
    pub hit: bool,
    /// `out_steps`.
    pub steps: u32,
    /// `out_and`.
    pub and_result: u64,
    /// `out_rom` (golden `RomWord::pack`).
    pub rom: u32,
    /// `out_z1`, `out_z2`, `out_zmin`, `out_zmax` (sign-extended).
    pub z: [i64; 4],
}

/// Expected (or observed) outputs of one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OutVec {
    /// Iterative only: `ready`.
    pub ready: bool,
    /// Iterative only: the step ports.
    pub step: StepOutput,
    /// Result ports (fields other than `valid` compared only when valid).
    pub result: ResultPorts,
}

const MASK48: u64 = (1 << 48) - 1;

fn in_vec(job: &SearchJob) -> InVec {
    InVec {
        rst: false,
        valid: true,
        mask: job.mask,
        corner: job.corner.code(),
        plane: [job.plane.zc, job.plane.sx, job.plane.sy].map(|v| v as u64 & MASK48),
    }
}

/// The golden result of a whole search.
pub fn golden_result(tables: &SearchTables, job: &SearchJob) -> ResultPorts {
    let r = SearchUnit::new(tables).run(job.mask, job.corner);
    match r.hit {
        Some((and_result, w)) => {
            let (z1, z2, _) = depth_calc(&job.plane, w);
            let z2 = z2.unwrap_or(z1);
            ResultPorts {
                valid: true,
                hit: true,
                steps: r.steps,
                and_result,
                rom: w.pack(),
                z: [z1, z2, z1.min(z2), z1.max(z2)],
            }
        }
        None => ResultPorts {
            valid: true,
            hit: false,
            steps: r.steps,
            and_result: 0,
            rom: 0,
            z: [job.plane.zc; 4],
        },
    }
}

/// A per-clock schedule built from the golden model.
#[derive(Clone, Debug, Default)]
pub struct Schedule {
    /// Inputs per clock.
    pub inputs: Vec<InVec>,
    /// Expected outputs per clock.
    pub expect: Vec<OutVec>,
    /// Pipelined only: the job index sampled with each vector.
    pub job_of: Vec<Option<usize>>,
}

/// The iterative variant's schedule (see the module header).
pub fn schedule_iter(tables: &SearchTables, jobs: &[SearchJob]) -> Schedule {
    let mut s = Schedule::default();
    let mut unit = SearchUnit::new(tables);
    let mut results: VecDeque<(usize, ResultPorts)> = VecDeque::new();
    let mut next = 0usize;
    let mut current: Option<usize> = None;
    let mut cur = StepOutput::default();
    let mut t = 0usize;
    loop {
        let drained = next >= jobs.len() && !cur.active && results.is_empty();
        if drained && t > 0 {
            break;
        }
        let mut v = InVec::default();
        if t == 0 {
            v.rst = true;
        } else if (!cur.active || cur.done) && next < jobs.len() {
            v = in_vec(&jobs[next]);
            unit.start(jobs[next].mask, jobs[next].corner);
            current = Some(next);
            next += 1;
        }
        // State after edge t + 1: its step output.
        cur = unit.step();
        if cur.done {
            let job = &jobs[current.expect("a running search has a job")];
            results.push_back((t + BACK_LATENCY, golden_result(tables, job)));
        }
        let mut o = OutVec {
            ready: !cur.active || cur.done,
            step: cur,
            result: ResultPorts::default(),
        };
        if results.front().map(|r| r.0) == Some(t) {
            o.result = results.pop_front().map(|r| r.1).unwrap_or_default();
        }
        s.inputs.push(v);
        s.expect.push(o);
        s.job_of.push(None);
        t += 1;
    }
    s
}

/// The pipelined variant's schedule: one job per clock, with a bubble after every
/// `bubble_every`-th job if non-zero.
pub fn schedule_pipe(
    tables: &SearchTables,
    jobs: &[SearchJob],
    latency: usize,
    bubble_every: usize,
) -> Schedule {
    let mut s = Schedule::default();
    s.inputs.push(InVec {
        rst: true,
        ..Default::default()
    });
    s.job_of.push(None);
    for (k, j) in jobs.iter().enumerate() {
        s.inputs.push(in_vec(j));
        s.job_of.push(Some(k));
        if bubble_every > 0 && k % bubble_every == bubble_every - 1 {
            s.inputs.push(InVec::default());
            s.job_of.push(None);
        }
    }
    for _ in 0..latency + 2 {
        s.inputs.push(InVec::default());
        s.job_of.push(None);
    }
    s.expect = vec![OutVec::default(); s.inputs.len()];
    for t in 0..s.inputs.len() {
        if let Some(k) = s.job_of[t] {
            s.expect[t + latency - 1].result = golden_result(tables, &jobs[k]);
        }
    }
    s
}

fn sext(v: u64, bits: usize) -> i64 {
    ((v << (64 - bits)) as i64) >> (64 - bits)
}

/// Access to either variant's ports in the RustHDL model.
trait Dut: Block + Sized {
    fn set_inputs(&mut self, v: &InVec);
    fn drive(&mut self, v: &InVec) -> Result<(), TbError>;
    fn read(&self) -> OutVec;
    /// Replays `inputs` in the traced simulator and writes a VCD to `path`.
    fn write_vcd(self, inputs: &[InVec], path: &Path) -> Result<(), TbError>;
}

const HALF_PS: u64 = 5_000;

macro_rules! impl_dut {
    ($t:ident, $iter:expr) => {
        impl<const B: usize> Dut for $t<B> {
            fn set_inputs(&mut self, v: &InVec) {
                self.rst.next = v.rst;
                self.in_valid.next = v.valid;
                self.in_mask.next = v.mask.to_bits();
                self.in_corner.next = (v.corner as u64).to_bits();
                self.in_zc.next = v.plane[0].to_bits();
                self.in_sx.next = v.plane[1].to_bits();
                self.in_sy.next = v.plane[2].to_bits();
            }
            fn write_vcd(self, inputs: &[InVec], path: &Path) -> Result<(), TbError> {
                let vecs = inputs.to_vec();
                let count = vecs.len() as u64;
                let mut sim = Simulation::new();
                sim.add_clock(HALF_PS, |x: &mut Box<$t<B>>| x.clock.next = !x.clock.val());
                sim.add_testbench(move |mut ep: Sim<$t<B>>| {
                    let mut x = ep.init()?;
                    for v in &vecs {
                        x.set_inputs(v);
                        wait_clock_cycle!(ep, clock, x);
                    }
                    ep.done(x)
                });
                let path_s = path.to_string_lossy().to_string();
                sim.run_to_file(Box::new(self), (count + 4) * 2 * HALF_PS, &path_s)
                    .map_err(|e| TbError::Sim(format!("{e:?}")))
            }
            fn drive(&mut self, v: &InVec) -> Result<(), TbError> {
                self.set_inputs(v);
                self.clock.next = Clock { clk: true };
                if !simulate(self, 200) {
                    return Err(TbError::NoConvergence);
                }
                self.clock.next = Clock { clk: false };
                if !simulate(self, 200) {
                    return Err(TbError::NoConvergence);
                }
                Ok(())
            }
            fn read(&self) -> OutVec {
                let z = |s: &Signal<Out, Bits<Z_BITS>>| sext(s.val().to_u64(), Z_BITS);
                let mut o = OutVec {
                    result: ResultPorts {
                        valid: self.out_valid.val(),
                        hit: self.out_hit.val(),
                        steps: self.out_steps.val().to_u64() as u32,
                        and_result: self.out_and.val().to_u64(),
                        rom: self.out_rom.val().to_u64() as u32,
                        z: [
                            z(&self.out_z1),
                            z(&self.out_z2),
                            z(&self.out_zmin),
                            z(&self.out_zmax),
                        ],
                    },
                    ..Default::default()
                };
                $iter(self, &mut o);
                o
            }
        }
    };
}

fn read_iter_steps<const B: usize>(u: &MaskSearchIter<B>, o: &mut OutVec) {
    o.ready = u.ready.val();
    o.step = StepOutput {
        active: u.active.val(),
        line: u.line.val().to_u64() as u32,
        search_mask: u.search_mask.val().to_u64(),
        and_result: u.and_result.val().to_u64(),
        zero: u.zero.val(),
        moved: u.moved.val(),
        hit: u.hit.val(),
        done: u.done.val(),
    };
}

fn no_steps<const B: usize>(_: &MaskSearchPipe<B>, _: &mut OutVec) {}

impl_dut!(MaskSearchIter, read_iter_steps);
impl_dut!(MaskSearchPipe, no_steps);

/// True if observed and expected outputs differ where they are compared.
fn differs(variant: Variant, exp: &OutVec, got: &OutVec) -> bool {
    if variant == Variant::Iterative && (exp.ready != got.ready || exp.step != got.step) {
        return true;
    }
    if exp.result.valid != got.result.valid {
        return true;
    }
    exp.result.valid && exp.result != got.result
}

/// The expected registers of pipeline stage `k` holding `job` (golden state after `k`
/// steps): `(found, and_result, steps)`.
fn stage_expect(tables: &SearchTables, job: &SearchJob, k: usize) -> (bool, u64, u32) {
    let mut u = SearchUnit::new(tables);
    u.start(job.mask, job.corner);
    let (mut found, mut and_result, mut steps) = (false, 0, 0);
    for _ in 0..k {
        let o = u.step();
        if !o.active {
            break;
        }
        steps = o.line + 1;
        if o.hit {
            found = true;
            and_result = o.and_result;
        }
    }
    (found, and_result, steps)
}

struct RunOut {
    cycles: u64,
    seconds: f64,
    mismatch: Option<(usize, String)>,
}

fn run_rusthdl<D: Dut>(
    uut: &mut D,
    variant: Variant,
    sched: &Schedule,
    stage_check: &dyn Fn(&D, usize, &Schedule) -> Option<String>,
) -> Result<RunOut, TbError> {
    uut.connect_all();
    let t0 = std::time::Instant::now();
    for (t, v) in sched.inputs.iter().enumerate() {
        uut.drive(v)?;
        let got = uut.read();
        let exp = &sched.expect[t];
        if t >= 1 && differs(variant, exp, &got) {
            return Ok(RunOut {
                cycles: t as u64 + 1,
                seconds: t0.elapsed().as_secs_f64(),
                mismatch: Some((
                    t,
                    format!(
                        "first mismatch after edge {} (vector {t}): inputs {:?}\n  golden {:?}\n  rtl    {:?}",
                        t + 1,
                        v,
                        exp,
                        got
                    ),
                )),
            });
        }
        if let Some(m) = stage_check(uut, t, sched) {
            return Ok(RunOut {
                cycles: t as u64 + 1,
                seconds: t0.elapsed().as_secs_f64(),
                mismatch: Some((t, format!("after edge {} (vector {t}): {m}", t + 1))),
            });
        }
    }
    Ok(RunOut {
        cycles: sched.inputs.len() as u64,
        seconds: t0.elapsed().as_secs_f64(),
        mismatch: None,
    })
}

/// The pipelined variant's per-stage check: stage `k` after vector `t` holds the job of
/// vector `t − k` with the golden search state after `k` steps.
fn pipe_stage_check<'a, const B: usize>(
    tables: &'a SearchTables,
    jobs: &'a [SearchJob],
) -> impl Fn(&MaskSearchPipe<B>, usize, &Schedule) -> Option<String> + 'a {
    move |u, t, sched| {
        if t == 0 {
            return None;
        }
        for (k, st) in u.stages.iter().enumerate() {
            let p = st.probe();
            let src = t
                .checked_sub(k)
                .and_then(|i| if i >= 1 { sched.job_of[i] } else { None });
            let Some(ji) = src else {
                if p.valid {
                    return Some(format!("stage {k} valid without a job: {p:?}"));
                }
                continue;
            };
            let job = &jobs[ji];
            let (found, and_result, steps) = stage_expect(tables, job, k);
            let want = pixelproc_rtl::mask_search::StageProbe {
                valid: true,
                mask: job.mask,
                corner: job.corner.code(),
                found,
                and_result,
                steps,
                plane: [job.plane.zc, job.plane.sx, job.plane.sy].map(|v| v as u64 & MASK48),
            };
            if p != want {
                return Some(format!(
                    "stage {k} registers (job {ji}: {job:?})\n  golden {want:?}\n  rtl    {p:?}"
                ));
            }
        }
        None
    }
}

/// Which jobs a stimulus means for a size.
pub fn jobs_for(stim: &Stimulus, size: MaskSize) -> Result<Vec<SearchJob>, TbError> {
    match stim {
        Stimulus::Exhaustive => {
            if size != MaskSize::S4X4 {
                return Err(TbError::Sim(format!(
                    "the exhaustive set is defined for 4x4 masks, not {size}"
                )));
            }
            Ok(exhaustive_jobs())
        }
        Stimulus::Random { count, seed } => Ok(random_jobs(size, *count, *seed)),
        Stimulus::Scene(name) => scene_jobs(name, size),
    }
}

fn summary(variant: Variant, size: MaskSize, sim: SimKind, jobs: usize) -> Summary {
    Summary {
        variant,
        size,
        sim,
        jobs,
        cycles: 0,
        seconds: 0.0,
        build_seconds: 0.0,
        bit_exact: false,
        detail: String::new(),
        vcd: None,
    }
}

/// The schedule of `variant` for `jobs` (seed diagonal family).
pub fn schedule(variant: Variant, size: MaskSize, jobs: &[SearchJob]) -> Schedule {
    schedule_with(variant, size, jobs, SearchFamily::DIAGONAL)
}

fn schedule_with(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    family: SearchFamily,
) -> Schedule {
    let tables = SearchTables::new(size, family);
    match variant {
        Variant::Iterative => schedule_iter(&tables, jobs),
        Variant::Pipelined => {
            let lat = SearchFamily::DIAGONAL.lines(size) as usize + BACK_LATENCY;
            // A bubble every 97 jobs exercises `in_valid = 0` without slowing the run.
            schedule_pipe(&tables, jobs, lat, 97)
        }
    }
}

fn check_rusthdl<const B: usize>(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    sched: &Schedule,
    work_dir: Option<&Path>,
    golden_family: SearchFamily,
) -> Result<(RunOut, Option<PathBuf>), TbError> {
    let fam = SearchFamily::DIAGONAL;
    let err = |e: pixelproc_rtl::mask_search::MaskSearchError| TbError::Sim(e.to_string());
    let tables = SearchTables::new(size, golden_family);
    let (run, vcd) = match variant {
        Variant::Iterative => {
            let mut u = MaskSearchIter::<B>::new(size, fam).map_err(err)?;
            let r = run_rusthdl(&mut u, variant, sched, &|_, _, _| None)?;
            let vcd = dump(&r, work_dir, sched, || {
                MaskSearchIter::<B>::new(size, fam).map_err(err)
            })?;
            (r, vcd)
        }
        Variant::Pipelined => {
            let mut u = MaskSearchPipe::<B>::new(size, fam).map_err(err)?;
            let chk = pipe_stage_check::<B>(&tables, jobs);
            let r = run_rusthdl(&mut u, variant, sched, &chk)?;
            let vcd = dump(&r, work_dir, sched, || {
                MaskSearchPipe::<B>::new(size, fam).map_err(err)
            })?;
            (r, vcd)
        }
    };
    Ok((run, vcd))
}

fn dump<D: Dut>(
    r: &RunOut,
    work_dir: Option<&Path>,
    sched: &Schedule,
    make: impl Fn() -> Result<D, TbError>,
) -> Result<Option<PathBuf>, TbError> {
    match (&r.mismatch, work_dir) {
        (Some((t, _)), Some(dir)) => {
            std::fs::create_dir_all(dir)?;
            let p = dir.join("mismatch.vcd");
            make()?.write_vcd(&sched.inputs[..=*t], &p)?;
            Ok(Some(p))
        }
        _ => Ok(None),
    }
}

/// Jobs per RustHDL run before a check is split over threads.
const CHUNK_MIN: usize = 16_384;

/// Runs the RustHDL model of `variant` against a schedule built from the golden model
/// of `golden_family` (the RTL is always the seed's diagonal family; a different golden
/// family is how tests show that mismatches are caught and reported).
///
/// Long job lists are split into one contiguous chunk per available core, each simulated
/// from reset by its own model instance (every clock of every chunk is compared); the
/// summary adds the cycles, reports wall time, and the mismatch of the earliest failing
/// chunk.
pub fn check_rusthdl_against(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    golden_family: SearchFamily,
    work_dir: Option<&Path>,
) -> Result<Summary, TbError> {
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .min(jobs.len() / CHUNK_MIN)
        .max(1);
    if threads == 1 {
        return check_chunk(variant, size, jobs, golden_family, work_dir);
    }
    let t0 = std::time::Instant::now();
    let per = jobs.len().div_ceil(threads);
    let parts: Vec<Result<Summary, TbError>> = std::thread::scope(|sc| {
        let hs: Vec<_> = jobs
            .chunks(per)
            .enumerate()
            .map(|(k, c)| {
                let wd = work_dir.map(|d| d.join(format!("chunk{k}")));
                sc.spawn(move || check_chunk(variant, size, c, golden_family, wd.as_deref()))
            })
            .collect();
        hs.into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(TbError::Sim("checker thread panicked".into())))
            })
            .collect()
    });
    let mut s = summary(variant, size, SimKind::RustHdl, jobs.len());
    s.bit_exact = true;
    for (k, p) in parts.into_iter().enumerate() {
        let p = p?;
        s.cycles += p.cycles;
        if !p.bit_exact && s.bit_exact {
            s.bit_exact = false;
            s.detail = format!("chunk {k} (jobs from {}): {}", k * per, p.detail);
            s.vcd = p.vcd;
        }
    }
    s.seconds = t0.elapsed().as_secs_f64();
    Ok(s)
}

fn check_chunk(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    golden_family: SearchFamily,
    work_dir: Option<&Path>,
) -> Result<Summary, TbError> {
    let sched = schedule_with(variant, size, jobs, golden_family);
    let (run, vcd) = match size.bits() {
        16 => check_rusthdl::<16>(variant, size, jobs, &sched, work_dir, golden_family)?,
        64 => check_rusthdl::<64>(variant, size, jobs, &sched, work_dir, golden_family)?,
        b => {
            return Err(TbError::Sim(format!(
                "no RTL build for {b}-bit masks (4x4, 8x8)"
            )))
        }
    };
    let mut s = summary(variant, size, SimKind::RustHdl, jobs.len());
    s.cycles = run.cycles;
    s.seconds = run.seconds;
    s.bit_exact = run.mismatch.is_none();
    s.detail = run.mismatch.map(|m| m.1).unwrap_or_default();
    if let Some(p) = &vcd {
        let _ = write!(s.detail, "\n  trace: {}", p.display());
    }
    s.vcd = vcd;
    Ok(s)
}

/// Bits packed LSB first into 64-bit limbs; printed as hex, most significant first.
#[derive(Default)]
struct Packer {
    limbs: Vec<u64>,
    n: usize,
}

impl Packer {
    fn push(&mut self, v: u64, w: usize) {
        for i in 0..w {
            if self.n.is_multiple_of(64) {
                self.limbs.push(0);
            }
            if (v >> i) & 1 == 1 {
                let l = self.n / 64;
                self.limbs[l] |= 1 << (self.n % 64);
            }
            self.n += 1;
        }
    }
    fn hex(&self, digits: usize, out: &mut String) {
        for d in (0..digits).rev() {
            let bit = 4 * d;
            let l = bit / 64;
            let v = if l < self.limbs.len() {
                (self.limbs[l] >> (bit % 64)) & 0xF
            } else {
                0
            };
            out.push(char::from_digit(v as u32, 16).unwrap_or('0'));
        }
        out.push('\n');
    }
}

/// Width of the result part of an expect line for `b`-bit masks.
fn result_bits(b: usize) -> usize {
    1 + 1 + 5 + b + 17 + 4 * Z_BITS
}

/// Width of the step part (iterative only).
fn step_bits(b: usize) -> usize {
    1 + 1 + 5 + b + b + 4
}

fn stim_bits(b: usize) -> usize {
    1 + 1 + b + 2 + 3 * 48
}

/// Writes `stim.hex` and `expect.hex` for a schedule (layouts in the testbench Verilog of
/// [`testbench_verilog`]); returns the number of vectors.
pub fn write_vectors(
    dir: &Path,
    variant: Variant,
    b: usize,
    sched: &Schedule,
) -> Result<usize, TbError> {
    let sd = stim_bits(b).div_ceil(4);
    let ed = (result_bits(b)
        + if variant == Variant::Iterative {
            step_bits(b)
        } else {
            0
        })
    .div_ceil(4);
    let mut stim = String::with_capacity(sched.inputs.len() * (sd + 1));
    let mut exp = String::with_capacity(sched.inputs.len() * (ed + 1));
    let zm = (1u64 << Z_BITS) - 1;
    for (v, e) in sched.inputs.iter().zip(&sched.expect) {
        let mut p = Packer::default();
        p.push(v.rst as u64, 1);
        p.push(v.valid as u64, 1);
        p.push(v.mask, b);
        p.push(v.corner as u64, 2);
        for f in v.plane {
            p.push(f, 48);
        }
        p.hex(sd, &mut stim);
        let mut q = Packer::default();
        let r = &e.result;
        q.push(r.valid as u64, 1);
        q.push(r.hit as u64, 1);
        q.push(r.steps as u64, 5);
        q.push(r.and_result, b);
        q.push(r.rom as u64, 17);
        for z in r.z {
            q.push(z as u64 & zm, Z_BITS);
        }
        if variant == Variant::Iterative {
            let s = &e.step;
            q.push(e.ready as u64, 1);
            q.push(s.active as u64, 1);
            q.push(s.line as u64, 5);
            q.push(s.search_mask, b);
            q.push(s.and_result, b);
            q.push(s.zero as u64, 1);
            q.push(s.moved as u64, 1);
            q.push(s.hit as u64, 1);
            q.push(s.done as u64, 1);
        }
        q.hex(ed, &mut exp);
    }
    std::fs::write(dir.join("stim.hex"), stim)?;
    std::fs::write(dir.join("expect.hex"), exp)?;
    Ok(sched.inputs.len())
}

/// The vector testbench for module `dut` (`b`-bit masks) over `cycles` vectors.
///
/// `stim.hex`, LSB first: `rst`, `in_valid`, `in_mask[b]`, `in_corner[2]`, `in_zc[48]`,
/// `in_sx[48]`, `in_sy[48]`. `expect.hex`, LSB first: `out_valid`, `out_hit`,
/// `out_steps[5]`, `out_and[b]`, `out_rom[17]`, `out_z1`, `out_z2`, `out_zmin`,
/// `out_zmax` (53 each); iterative then `ready`, `active`, `line[5]`, `search_mask[b]`,
/// `and_result[b]`, `zero`, `moved`, `hit`, `done`. After each rising edge every step port
/// and `out_valid` is compared, the other result ports when `out_valid` is expected.
pub fn testbench_verilog(dut: &str, variant: Variant, b: usize, cycles: usize) -> String {
    let rb = result_bits(b);
    let iter = variant == Variant::Iterative;
    let eb = rb + if iter { step_bits(b) } else { 0 };
    let sb = stim_bits(b);
    let (step_decl, step_conn, step_cat) = if iter {
        (
            format!(
                "    wire ready, active, zero, moved, hit, done;\n    wire [4:0] line;\n    wire [{m}:0] search_mask, and_result;\n",
                m = b - 1
            ),
            ", .ready(ready), .active(active), .line(line), .search_mask(search_mask), .and_result(and_result), .zero(zero), .moved(moved), .hit(hit), .done(done)".to_string(),
            "done, hit, moved, zero, and_result, search_mask, line, active, ready, ".to_string(),
        )
    } else {
        (String::new(), String::new(), String::new())
    };
    let step_cmp = if iter {
        format!("got[{}:{rb}] !== expv[t][{}:{rb}] || ", eb - 1, eb - 1)
    } else {
        String::new()
    };
    format!(
        r#"// Vector testbench for {dut}: drives stim.hex, checks the outputs against expect.hex.
`timescale 1ns/1ps
module tb_mask_search;
    localparam integer NCYC = {cycles};
    reg clock = 1'b0;
    reg [{sb1}:0] stim [0:NCYC-1];
    reg [{eb1}:0] expv [0:NCYC-1];
    reg rst, in_valid;
    reg [{b1}:0] in_mask;
    reg [1:0] in_corner;
    reg [47:0] in_zc, in_sx, in_sy;
    wire out_valid, out_hit;
    wire [4:0] out_steps;
    wire [{b1}:0] out_and;
    wire [16:0] out_rom;
    wire [52:0] out_z1, out_z2, out_zmin, out_zmax;
{step_decl}    wire [{eb1}:0] got = {{{step_cat}out_zmax, out_zmin, out_z2, out_z1, out_rom, out_and, out_steps, out_hit, out_valid}};
    integer t;
    {dut} dut (.clock(clock), .rst(rst), .in_valid(in_valid), .in_mask(in_mask),
        .in_corner(in_corner), .in_zc(in_zc), .in_sx(in_sx), .in_sy(in_sy),
        .out_valid(out_valid), .out_hit(out_hit), .out_steps(out_steps), .out_and(out_and),
        .out_rom(out_rom), .out_z1(out_z1), .out_z2(out_z2), .out_zmin(out_zmin),
        .out_zmax(out_zmax){step_conn});
    always #5 clock = ~clock;
    initial begin
        $readmemh("stim.hex", stim);
        $readmemh("expect.hex", expv);
        $dumpfile("tb_mask_search.vcd");
        $dumpvars(1, tb_mask_search);
        for (t = 0; t < NCYC; t = t + 1) begin
            rst = stim[t][0];
            in_valid = stim[t][1];
            in_mask = stim[t][{mb}:2];
            in_corner = stim[t][{cb}:{cb0}];
            in_zc = stim[t][{z0}+47:{z0}];
            in_sx = stim[t][{z0}+95:{z0}+48];
            in_sy = stim[t][{z0}+143:{z0}+96];
            @(posedge clock);
            #1;
            if (t >= 1 && ({step_cmp}got[0] !== expv[t][0] || (expv[t][0] && got[{rb1}:0] !== expv[t][{rb1}:0]))) begin
                $display("MISMATCH cycle=%0d inputs=%h expected=%h got=%h", t, stim[t], expv[t], got);
                $finish;
            end
        end
        $display("PASS cycles=%0d", NCYC);
        $finish;
    end
endmodule
"#,
        sb1 = sb - 1,
        eb1 = eb - 1,
        b1 = b - 1,
        mb = b + 1,
        cb = b + 3,
        cb0 = b + 2,
        z0 = b + 4,
        rb1 = rb - 1,
    )
}

/// Exports `variant`, writes the golden vectors for `jobs` and runs them in Icarus Verilog
/// or Verilator inside `dir`. A missing tool: `SKIPPED` summary (error under `CI=true`).
pub fn check_external(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    sim: SimKind,
    dir: &Path,
) -> Result<Summary, TbError> {
    check_external_against(variant, size, jobs, sim, dir, SearchFamily::DIAGONAL)
}

/// As [`check_external`], with the expected vectors from the golden model of
/// `golden_family` (a family other than the diagonal must be reported as a mismatch).
pub fn check_external_against(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    sim: SimKind,
    dir: &Path,
    golden_family: SearchFamily,
) -> Result<Summary, TbError> {
    let mut s = summary(variant, size, sim, jobs.len());
    let tool = match sim {
        SimKind::Icarus => "iverilog",
        SimKind::Verilator => "verilator",
        SimKind::RustHdl => return Err(TbError::Sim("not an external simulator".into())),
    };
    if !tool_available(tool) {
        skip_or_fail(tool)?;
        s.detail = format!(
            "SKIPPED: {tool} not installed; install with: {}",
            crate::external::INSTALL_HINT
        );
        return Ok(s);
    }
    std::fs::create_dir_all(dir)?;
    let dir = dir.canonicalize()?;
    let (name, text) =
        mask_search_verilog(variant, size).map_err(|e| TbError::Sim(e.to_string()))?;
    let vfile = dir.join(format!("{name}.v"));
    std::fs::write(&vfile, text)?;
    let sched = schedule_with(variant, size, jobs, golden_family);
    let b = size.bits() as usize;
    let cycles = write_vectors(&dir, variant, b, &sched)?;
    std::fs::write(
        dir.join("tb_mask_search.v"),
        testbench_verilog(&name, variant, b, cycles),
    )?;
    let ext = match sim {
        SimKind::Icarus => crate::external::ExternalSim::Icarus,
        _ => crate::external::ExternalSim::Verilator,
    };
    let (out, build_seconds, run_seconds) =
        crate::external::build_and_run(ext, &dir, "tb_mask_search", &vfile)?;
    s.build_seconds = build_seconds;
    s.seconds = run_seconds;
    s.cycles = cycles as u64;
    s.bit_exact = out.contains(&format!("PASS cycles={cycles}")) && !out.contains("MISMATCH");
    if !s.bit_exact {
        s.detail = out;
        s.vcd = Some(dir.join("tb_mask_search.vcd"));
    }
    Ok(s)
}

/// The check the CLI runs: `variant` on `stim` (`size` 4×4 or 8×8; the exhaustive set is
/// 4×4) in `sim`, compared with the golden model every clock. `work_dir` receives vector
/// files and traces.
pub fn search_unit_check(
    variant: Variant,
    size: MaskSize,
    stim: &Stimulus,
    sim: SimKind,
    work_dir: &Path,
) -> Result<Summary, TbError> {
    let jobs = jobs_for(stim, size)?;
    search_unit_check_jobs(variant, size, &jobs, sim, work_dir)
}

/// As [`search_unit_check`], for a prepared list of searches (e.g. [`loaded_scene_jobs`]).
pub fn search_unit_check_jobs(
    variant: Variant,
    size: MaskSize,
    jobs: &[SearchJob],
    sim: SimKind,
    work_dir: &Path,
) -> Result<Summary, TbError> {
    let jobs = jobs.to_vec();
    match sim {
        SimKind::RustHdl => {
            check_rusthdl_against(variant, size, &jobs, SearchFamily::DIAGONAL, Some(work_dir))
        }
        _ => check_external(variant, size, &jobs, sim, work_dir),
    }
}

/// The fast default check: 3,000 random 4×4 and 1,000 random 8×8 searches through both
/// variants in RustHDL (well under a second in a release build).
pub fn search_unit_quick_check() -> Result<Vec<Summary>, TbError> {
    let dir = std::env::temp_dir().join("pixelproc-mask-search-quick");
    let mut out = Vec::new();
    for (size, n) in [(MaskSize::S4X4, 3000), (MaskSize::S8X8, 1000)] {
        let jobs = random_jobs(size, n, 7);
        for v in Variant::ALL {
            out.push(check_rusthdl_against(
                v,
                size,
                &jobs,
                SearchFamily::DIAGONAL,
                Some(&dir),
            )?);
        }
    }
    Ok(out)
}

/// Writes the search unit's Verilog (both variants, 4×4 and 8×8) into `dir`.
pub fn write_mask_search_verilog(dir: &Path) -> Result<Vec<PathBuf>, TbError> {
    pixelproc_rtl::verilog::write_mask_search_verilog(dir).map_err(|e| TbError::Sim(e.to_string()))
}
