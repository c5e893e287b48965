//! The mask search unit (seed 000) in the RustHDL simulator, compared with the golden
//! schedule every clock (and, pipelined, every stage's registers).

use super::schedule::{sext, MASK48};
use super::{schedule_with, summary, InVec, OutVec, ResultPorts, Schedule, SearchJob, Summary};
use crate::{SimKind, TbError};
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::{MaskSearchIter, MaskSearchPipe, Variant, Z_BITS};
use pixelproc_sim::mask_search::{SearchTables, SearchUnit, StepOutput};
use rust_hdl::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
