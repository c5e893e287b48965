//! RustHDL RTL of the pixelproc back-end: the pixel-processor array of seed 001
//! (Matsumoto) with its span-parity shadow logic, the A-buffer mask search unit of seed 000
//! with its offset ROM, and Verilog export.
//!
//! Blocks (one file each): [`span_parity::SpanParity`], [`pixel_processor::PixelProcessor`],
//! [`pixel_array::PixelProcessorArray`], and under [`mask_search`] the iterative and
//! pipelined search units with their stages, offset ROM, depth calculator and shift-add
//! sub-blocks. The array's per-clock command interface mirrors the golden model's
//! `Command` ([`opcodes`]); [`layout`] carries the `formats` field tables into kernels;
//! [`verilog`] is the one export path. `docs/rtl.md` and `docs/rtl_mask_search.md` give
//! ports, latency, protocol, and the lint and synthesis results.
//!
//! This crate depends on `pixelproc-formats` and `rust-hdl` only, never on the golden
//! model.

#![warn(missing_docs)]

pub mod bank_ram;
pub mod colour_lane;
pub mod core_top;
pub mod entry_channel;
pub mod layout;
pub mod lut_ram;
pub mod mask_search;
pub mod mul_reg;
pub mod opcodes;
pub mod pixel_array;
pub mod pixel_processor;
pub mod shade_unit;
pub mod span_parity;
pub mod stream_fifo;
pub mod verilog;

/// Marsaglia's xorshift64 (13, 7, 17): the unit tests' one stream of random patterns.
#[cfg(test)]
pub(crate) fn xorshift64(x: &mut u64) -> u64 {
    *x ^= *x << 13;
    *x ^= *x >> 7;
    *x ^= *x << 17;
    *x
}

use thiserror::Error;

/// Errors of RTL construction and export.
#[derive(Debug, Error)]
pub enum RtlError {
    /// The array width is outside `1 ..= MAX_SCREEN` (4096).
    #[error("array width {0} is outside 1..={max}", max = pixelproc_formats::MAX_SCREEN)]
    BadWidth(usize),
    /// Writing a Verilog file failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

#[cfg(test)]
mod tests {
    #[test]
    fn bad_width_message_names_the_limit() {
        assert_eq!(
            crate::RtlError::BadWidth(5000).to_string(),
            "array width 5000 is outside 1..=4096"
        );
    }
}
