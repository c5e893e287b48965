//! Testbenches for the pixelproc RTL: every clock, every processor of the RustHDL
//! `PixelProcessorArray` is compared with the golden model's `PixelArray::step`
//! ([`compare`]); the same stimulus and expected values are written as `$readmemh`
//! vector files for the exported Verilog in Icarus Verilog and Verilator ([`external`]).

#![warn(missing_docs)]

pub mod compare;
pub mod external;
pub mod mask_search_tb;
pub mod stimulus;

pub use stimulus::scene_stream;

use thiserror::Error;

/// Testbench errors.
#[derive(Debug, Error)]
pub enum TbError {
    /// A span word field is out of range.
    #[error(transparent)]
    Field(#[from] pixelproc_formats::FieldRangeError),
    /// RTL construction failed.
    #[error(transparent)]
    Rtl(#[from] pixelproc_rtl::RtlError),
    /// The combinational logic did not settle.
    #[error("RustHDL simulation did not converge")]
    NoConvergence,
    /// The traced simulator failed.
    #[error("RustHDL simulation failed: {0}")]
    Sim(String),
    /// File system error.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The golden pipeline could not build a scene's command stream.
    #[error("scene: {0}")]
    Scene(String),
    /// A golden command the array's command port cannot carry (a CHECK range beyond
    /// column 4095).
    #[error("the RTL array cannot encode {0}")]
    Unsupported(String),
}

use pixelproc_sim::pixel_array::Command;

/// Which simulator runs the RTL.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimKind {
    /// The RustHDL model itself, every processor's registers compared every clock.
    RustHdl,
    /// The exported Verilog in Icarus Verilog (readout port compared every clock).
    Icarus,
    /// The exported Verilog in Verilator (readout port compared every clock).
    Verilator,
}

/// Summary of a `testbench` run.
#[derive(Clone, Debug)]
pub struct TestbenchSummary {
    /// Bit-exact on every compared value.
    pub bit_exact: bool,
    /// Span words fed (each tile counts).
    pub span_words: usize,
    /// Clock cycles simulated.
    pub cycles: u64,
    /// Simulation wall time, seconds.
    pub seconds: f64,
    /// First mismatch or simulator log, when not bit-exact; `SKIPPED: ...` if a tool
    /// is missing outside CI.
    pub detail: String,
}

/// Runs a scene's command stream (`lines`: per scanline, the commands after its
/// `ClearLine`; `bg` RGB888; `width` screen width) on an array of `n` processors in
/// `sim`, comparing with the golden model. `work_dir` receives VCDs and vector files.
pub fn testbench(
    lines: Vec<Vec<Command>>,
    bg: u32,
    width: u32,
    n: usize,
    shadows: bool,
    sim: SimKind,
    work_dir: &std::path::Path,
) -> Result<TestbenchSummary, TbError> {
    let stream = stimulus::LineStream { width, bg, lines };
    let cmds = stream.flatten(n);
    match sim {
        SimKind::RustHdl => {
            let c = compare::compare_commands(&cmds, n, shadows, Some(work_dir))?;
            Ok(TestbenchSummary {
                bit_exact: c.bit_exact(),
                span_words: c.span_words,
                cycles: c.cycles,
                seconds: c.seconds,
                detail: c.mismatch.map(|m| m.to_string()).unwrap_or_default(),
            })
        }
        SimKind::Icarus | SimKind::Verilator => {
            let es = if sim == SimKind::Icarus {
                external::ExternalSim::Icarus
            } else {
                external::ExternalSim::Verilator
            };
            let words = cmds
                .iter()
                .filter(|(_, c)| matches!(c, Command::Span(_)))
                .count();
            match external::run_external(es, work_dir, &cmds, n, shadows)? {
                None => Ok(TestbenchSummary {
                    bit_exact: false,
                    span_words: words,
                    cycles: 0,
                    seconds: 0.0,
                    detail: format!(
                        "SKIPPED: tool missing; install with: {}",
                        external::INSTALL_HINT
                    ),
                }),
                Some(r) => Ok(TestbenchSummary {
                    bit_exact: r.pass,
                    span_words: words,
                    cycles: r.cycles as u64,
                    seconds: r.run_seconds,
                    detail: if r.pass { String::new() } else { r.log },
                }),
            }
        }
    }
}

/// The fast default check: four scanlines of random triangles on a 24-pixel screen,
/// an 8-processor array with shadow logic (three tiles per line), RustHDL simulation
/// compared with the golden model every clock.
pub fn quick_check() -> Result<TestbenchSummary, TbError> {
    let mut rng = stimulus::Rng::new(2024);
    let tris = stimulus::random_triangles(&mut rng, 5, 24, 4);
    let s = stimulus::LineStream::from_triangles(&tris, 24, 4, [16, 32, 48])
        .map_err(|e| TbError::Sim(e.to_string()))?;
    let dir = std::env::temp_dir().join("pixelproc-quick-check");
    testbench(s.lines, s.bg, 24, 8, true, SimKind::RustHdl, &dir)
}
