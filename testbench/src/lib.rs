//! Testbenches for the pixelproc RTL: every clock, every processor of the RustHDL
//! `PixelProcessorArray` is compared with the golden model's `PixelArray::step`
//! ([`compare`]); the same stimulus and expected values are written as `$readmemh`
//! vector files for the exported Verilog in Icarus Verilog and Verilator ([`external`]).

#![warn(missing_docs)]

pub mod compare;
pub mod stimulus;

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
}
