//! Per-clock command opcodes of the pixel-processor array (seed 001, Matsumoto,
//! sections 3 to 6).
//!
//! The list lives in `pixelproc-formats` ([`pixelproc_formats::opcodes`]), beside the
//! span word, so the RTL, the golden model's testbench encoders and the documentation
//! read one definition; this module re-exports it under its historical path.

pub use pixelproc_formats::opcodes::*;
