//! Testbenches for the pixelproc RTL: every clock, every processor of the RustHDL
//! `PixelProcessorArray` is compared with the golden model's `PixelArray::step`
//! ([`compare`]); the same stimulus and expected values are written as `$readmemh`
//! vector files for the exported Verilog in Icarus Verilog and Verilator ([`external`]).

#![warn(missing_docs)]

pub mod compare;
pub mod core_tb;
pub mod external;
pub mod frame;
pub mod mask_search_tb;
pub mod sim_tools;
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
    /// A simulator is missing under `CI=true`.
    #[error("{0} not installed; install with: {}", external::INSTALL_HINT)]
    ToolMissing(String),
    /// File system error.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The golden pipeline could not build a scene's command stream.
    #[error("scene")]
    Scene(#[from] pixelproc_sim::pipeline::RenderError),
    /// A golden command the array's command port cannot carry (a CHECK range beyond
    /// column 4095).
    #[error("the RTL array cannot encode {0}")]
    Unsupported(String),
    /// A scene or plan the core (`pixelproc_rtl::core_top`) cannot take: more shadowing
    /// lights or area-light samples than its shading table's address, an anti-aliased plan.
    #[error("{0}")]
    Core(String),
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

/// How a comparison of the RTL with the golden model ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every compared value identical.
    BitExact,
    /// A difference: the first mismatch, or the simulator's log.
    Mismatch(String),
    /// Not run: a simulator is missing (outside CI, where that is an error).
    Skipped {
        /// The missing program.
        tool: String,
        /// The command that installs it.
        install: String,
    },
}

impl Outcome {
    /// `BitExact` if `same`, else a mismatch described by `detail`.
    pub fn compared(same: bool, detail: impl FnOnce() -> String) -> Outcome {
        if same {
            Outcome::BitExact
        } else {
            Outcome::Mismatch(detail())
        }
    }
    /// The outcome of a run that needed the missing program `tool`.
    pub fn missing(tool: &str) -> Outcome {
        Outcome::Skipped {
            tool: tool.to_string(),
            install: external::INSTALL_HINT.to_string(),
        }
    }
    /// True if every compared value was identical.
    pub fn bit_exact(&self) -> bool {
        *self == Outcome::BitExact
    }
    /// True if the run was skipped.
    pub fn skipped(&self) -> bool {
        matches!(self, Outcome::Skipped { .. })
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Outcome::BitExact => write!(f, "bit-exact"),
            Outcome::Mismatch(detail) => write!(f, "{detail}"),
            Outcome::Skipped { tool, install } => {
                write!(f, "SKIPPED: {tool} not installed; install with: {install}")
            }
        }
    }
}

/// Summary of a `testbench` run.
#[derive(Clone, Debug)]
pub struct TestbenchSummary {
    /// Bit-exact, a mismatch (with the first mismatch or the simulator's log), or
    /// skipped because a simulator is missing outside CI.
    pub outcome: Outcome,
    /// Span words fed (each tile counts).
    pub span_words: usize,
    /// Clock cycles simulated.
    pub cycles: u64,
    /// Simulation wall time, seconds (the run alone, for an external simulator).
    pub seconds: f64,
    /// Seconds spent compiling the exported Verilog (0 for the RustHDL model).
    pub build_seconds: f64,
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
                outcome: match c.mismatch {
                    Some(m) => Outcome::Mismatch(m.to_string()),
                    None => Outcome::BitExact,
                },
                span_words: c.span_words,
                cycles: c.cycles,
                seconds: c.seconds,
                build_seconds: 0.0,
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
                    outcome: Outcome::missing(es.tool()),
                    span_words: words,
                    cycles: 0,
                    seconds: 0.0,
                    build_seconds: 0.0,
                }),
                Some(r) => Ok(TestbenchSummary {
                    outcome: Outcome::compared(r.pass, || r.log),
                    span_words: words,
                    cycles: r.cycles as u64,
                    seconds: r.run_seconds,
                    build_seconds: r.build_seconds,
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
        .map_err(pixelproc_sim::pipeline::RenderError::from)?;
    let dir = std::env::temp_dir().join("pixelproc-quick-check");
    testbench(s.lines, s.bg, 24, 8, true, SimKind::RustHdl, &dir)
}
