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
//!
//! **Stream.** [`stream`] runs the AXI4-Stream units on the whole search stream of an
//! A-buffer render with random input gaps and output back-pressure ([`run_search_stream`]).
//!
//! Files: [`jobs`] (stimulus), [`schedule`](mod@schedule) (golden per-clock vectors), [`rusthdl`] (the
//! RustHDL runs), [`vectors`] (vector files and the Verilog testbench), [`external`]
//! (Icarus Verilog and Verilator through the shared runner of `crate::external`).

pub mod external;
pub mod jobs;
pub mod rusthdl;
pub mod schedule;
pub mod stream;
mod stream_rusthdl;
pub mod vectors;

pub use external::{check_external, check_external_against};
pub use jobs::{exhaustive_jobs, loaded_scene_jobs, random_jobs, scene_jobs};
pub use rusthdl::check_rusthdl_against;
pub use schedule::{
    golden_result, schedule_iter, schedule_pipe, InVec, OutVec, ResultPorts, Schedule,
};
pub use stream::{
    run_search_stream, run_stream_words, scene_requests, stream_words, StreamSummary, StreamWords,
};
pub use vectors::{testbench_verilog, write_vectors};

use crate::{SimKind, TbError};
use pixelproc_formats::abuffer::{Corner, FragPlane, MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::{Variant, BACK_LATENCY};
use pixelproc_sim::mask_search::SearchTables;
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

pub(crate) fn summary(variant: Variant, size: MaskSize, sim: SimKind, jobs: usize) -> Summary {
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

pub(crate) fn schedule_with(
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
