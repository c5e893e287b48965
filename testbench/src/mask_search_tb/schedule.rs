//! The golden per-clock schedule of the mask search checks (seed 000): inputs and
//! expected outputs of every clock, from `pixelproc_sim::mask_search` alone.

use super::SearchJob;
use pixelproc_rtl::mask_search::BACK_LATENCY;
use pixelproc_sim::mask_search::{depth_calc, SearchTables, SearchUnit, StepOutput};
use std::collections::VecDeque;

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

pub(crate) const MASK48: u64 = (1 << 48) - 1;

pub(crate) fn in_vec(job: &SearchJob) -> InVec {
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

/// `v` of `bits` bits, sign-extended.
pub(crate) fn sext(v: u64, bits: usize) -> i64 {
    ((v << (64 - bits)) as i64) >> (64 - bits)
}
