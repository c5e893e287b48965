//! Point-sampling methods through the array: corner-shared sampling (seed 003,
//! JP4801088B2), the D3D 4× and ordered 2×2 patterns, and `k×k` supersampling.
//!
//! **Exact:** each row of samples is a row of tile-lines through the core, costed by
//! [`super::array::core_cycles`] from the spans of the scene at that row's `y`.
//!
//! **Stated** (no RTL): the array draws one row of samples per pass: samples that share a
//! `y` share a span word (the array's processors sample one scanline), so a pattern costs
//! one pass per distinct sample `y` in a pixel row, each pass as wide as the samples at
//! that `y`:
//!
//! | pattern | passes per pixel row | samples per pass | new samples per pixel |
//! |---|---|---|---|
//! | corner, 1 spp | 2 (even corners at `−1/6`, odd at `+1/6` from the corner row; `sim::aa::corner`'s table), plus the bottom corner row | `⌈(W+1)/2⌉`, `⌊(W+1)/2⌋` | 1 |
//! | corner + centre, 2 spp | 3 (the two corner passes and the centres) | as above, and `W` | 2 |
//! | D3D 4× | 4 (sample `y` at `−6, −2, 2, 6` sixteenths) | `W` | 4 |
//! | ordered 2×2 | 2 (`y` at `±1/4`) | `2W` | 4 |
//! | `k×k` | `k` | `kW` | `k²` |
//!
//! The resolve reads the samples back through the readout and weights them at one pixel
//! per clock, adding no clocks. Corner sampling keeps the seed 003 row buffer (the previous
//! row of corner samples and the previous sample) so that each pixel reads one new sample:
//! `(W + 1)` samples of 24 bits on chip. The per-pixel patterns need a row of
//! `samples per pixel × W` samples to gather a pixel's samples from its passes.

use super::array::{core_resources, sample_rows_cycles, SampleRows};
use super::{Frame, HwConfig, HwCost, HwCostError};
use crate::aa::{CornerParams, Pattern};

/// Bits per stored sample (RGB888).
pub const SAMPLE_BITS: u64 = 24;

/// Offset of the corner samples from their corner row, 1/256 pixel: `±1/6` rounded.
const SIXTH_Q8: i32 = 43;

fn row(dy_q8: i32, rows: std::ops::Range<u32>, num: u32, den: u32, width: u32) -> SampleRows {
    SampleRows {
        dy_q8,
        rows,
        num,
        den,
        width,
    }
}

/// The passes of a corner-family pattern on a `width`×`height` frame (module header).
pub fn corner_passes(p: &CornerParams, width: u32, height: u32) -> Vec<SampleRows> {
    let (w, h) = (width, height);
    let mut out = Vec::new();
    match p.pattern {
        Pattern::Corner => {
            let (even, odd) = ((w + 1).div_ceil(2), w.div_ceil(2));
            out.push(row(-SIXTH_Q8, 0..h, 1, 2, even));
            out.push(row(SIXTH_Q8, 0..h, 1, 2, odd));
            if p.centre {
                out.push(row(128, 0..h, 1, 1, w));
            }
            // Corner row J = H, below the last pixel row.
            out.push(row(256 - SIXTH_Q8, h - 1..h, 1, 2, even));
            out.push(row(256 + SIXTH_Q8, h - 1..h, 1, 2, odd));
        }
        Pattern::D3d4x => {
            for s in [-6, -2, 2, 6] {
                out.push(row(128 + 16 * s, 0..h, 1, 1, w));
            }
            if p.centre {
                out.push(row(128, 0..h, 1, 1, w));
            }
        }
        Pattern::Grid2x2 => {
            for dy in [64, 192] {
                out.push(row(dy, 0..h, 2, 1, 2 * w));
            }
            if p.centre {
                out.push(row(128, 0..h, 1, 1, w));
            }
        }
    }
    out
}

/// The passes of `k×k` supersampling: `k` rows of `kW` samples per pixel row.
pub fn ssaa_passes(k: u32, width: u32, height: u32) -> Vec<SampleRows> {
    let k = k.max(1);
    (0..k)
        .map(|m| row(((2 * m + 1) * 128 / k) as i32, 0..height, k, 1, k * width))
        .collect()
}

fn cost_of(
    frame: &Frame<'_>,
    cfg: &HwConfig,
    passes: &[SampleRows],
    memory_samples: u64,
) -> Result<HwCost, HwCostError> {
    let (cycles, samples) = sample_rows_cycles(frame, cfg.array_width, passes)?;
    let per_row = passes
        .iter()
        .filter(|p| p.rows.len() as u32 == frame.height)
        .count() as u64;
    Ok(HwCost {
        cycles,
        passes_per_row_milli: 1000 * per_row,
        samples,
        extra_memory_bits: memory_samples * SAMPLE_BITS,
        resources: Some(core_resources(cfg.array_width)),
    })
}

/// Corner sampling, D3D 4× or ordered 2×2 on the array (module header).
pub fn corner_cost(
    frame: &Frame<'_>,
    cfg: &HwConfig,
    p: &CornerParams,
) -> Result<HwCost, HwCostError> {
    let ps = corner_passes(p, frame.width, frame.height);
    let w = frame.width as u64;
    let mem = match p.pattern {
        Pattern::Corner => w + 1 + p.centre as u64 * w,
        Pattern::D3d4x => (4 + p.centre as u64) * w,
        Pattern::Grid2x2 => (4 + p.centre as u64) * w,
    };
    cost_of(frame, cfg, &ps, mem)
}

/// `k×k` supersampling on the array (module header).
pub fn ssaa_cost(frame: &Frame<'_>, cfg: &HwConfig, k: u32) -> Result<HwCost, HwCostError> {
    let ps = ssaa_passes(k, frame.width, frame.height);
    cost_of(frame, cfg, &ps, (k as u64 * k as u64) * frame.width as u64)
}
