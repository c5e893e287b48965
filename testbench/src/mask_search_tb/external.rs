//! The exported mask search unit (seed 000) in Icarus Verilog or Verilator, through the
//! shared external-simulator runner.

use super::{schedule_with, summary, testbench_verilog, write_vectors, SearchJob, Summary};
use crate::external::{skip_or_fail, tool_available};
use crate::{SimKind, TbError};
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use pixelproc_rtl::mask_search::{mask_search_verilog, Variant};
use std::path::Path;

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
