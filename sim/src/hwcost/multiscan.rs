//! Multi-scanning (seed 002, Nishita & Nakamae) mapped onto seed 001's array: one pass of
//! the array per sub-scanline.
//!
//! **Exact:** each pass is a row of tile-lines through the core, costed by
//! [`super::array::core_cycles`] from the spans of the scene at that sub-scanline.
//!
//! **Stated** (no RTL):
//! - *Passes.* Box filter (§2.2.1): sub-scanlines `l = 0..n` at `y = j + l/n` include
//!   both pixel edges and the edge `l = n` is the next row's `l = 0`, so each row costs
//!   `n` passes and the frame `n·H + 1`. Axisymmetric filters (§2.2.2, Gaussian or cone):
//!   sub-scanlines divide the distance between pixel centres into `n`; a pixel uses the
//!   `2n − 1` between the centres above and below it (the two at the neighbouring centres
//!   carry no weight), each shared with the neighbouring row, so the frame costs
//!   `n·H + n − 1` passes (the centre rows, `n − 1` between each pair of centres, and
//!   `n − 1` above the first centre).
//! - *Processors.* Each processor measures the visible length of the span in its pixel
//!   (`L_{f,l}`: the span's ends are exact along x, seed 002 §2), not a point sample; one
//!   span word per clock as in the core.
//! - *Weighting.* The readout of each pass is weighted (`d_l` for the box; the 64-step
//!   lookup table `F_l` of §2.2.2 for the others) and accumulated at one pixel per clock
//!   in the readout pipeline, so it adds no clocks; for the axisymmetric filters a piece
//!   goes to four pixels in two rows, which the two row banks and a one-pixel register
//!   absorb.
//! - *Memory.* Two rows of pixel accumulators (§3: "only two rows of pixel memory"):
//!   `2 · width · 3 channels · 20 bits` (8-bit colour, 12 bits of weight).
//!
//! Sub-scanline positions are rounded to 1/256 pixel (n = 3, 6, 12 do not divide 256).

use super::array::{core_resources, sample_rows_cycles, SampleRows};
use super::{Frame, HwConfig, HwCost, HwCostError};
use crate::aa::{Filter, MultiscanParams};

/// Accumulator bits per channel of the two-row memory (stated).
pub const ACC_BITS: u64 = 20;

/// The sub-scanline passes of `p` on a frame of `height` rows and `width` pixels (see the
/// module header).
pub fn passes(p: &MultiscanParams, width: u32, height: u32) -> Vec<SampleRows> {
    let n = p.subscanlines.max(1) as i32;
    let at = |dy_q8: i32, rows: std::ops::Range<u32>| SampleRows {
        dy_q8,
        rows,
        num: 1,
        den: 1,
        width,
    };
    let q = |l: i32| (l * 256 + n / 2) / n;
    let mut out = Vec::new();
    match p.filter {
        Filter::Box => {
            for l in 0..n {
                out.push(at(q(l), 0..height));
            }
            // The bottom edge of the last row.
            out.push(at(256, height - 1..height));
        }
        Filter::Gauss | Filter::Cone => {
            // Above the first centre, then per row its centre and the lines below it.
            for l in (1..n).rev() {
                out.push(at(128 - q(l), 0..1));
            }
            for l in 0..n {
                out.push(at(128 + q(l), 0..height));
            }
        }
    }
    out
}

/// Multi-scanning's frame on the array (module header).
pub fn cost(frame: &Frame<'_>, cfg: &HwConfig, p: &MultiscanParams) -> Result<HwCost, HwCostError> {
    let ps = passes(p, frame.width, frame.height);
    let (cycles, samples) = sample_rows_cycles(frame, cfg.array_width, &ps)?;
    Ok(HwCost {
        cycles,
        passes_per_row_milli: 1000 * p.subscanlines.max(1) as u64,
        samples,
        extra_memory_bits: 2 * frame.width as u64 * 3 * ACC_BITS,
        resources: Some(core_resources(cfg.array_width)),
    })
}
