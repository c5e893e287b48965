//! The pixel-processor array in the streaming core (seed 001 on `docs/core.md`'s core):
//! cycles per frame from the core's controller timing, in closed form.
//!
//! **The timing** (`docs/core.md`, "Timing"; every figure is the RTL's and
//! [`crate::core_model::CoreModel`]'s, with a source that offers a beat every clock and a
//! sink that is always ready):
//! - the first beat, offered on the first clock after reset, is issued to the array at the
//!   third rising edge (one edge into the input FIFO, one to its head register, one to
//!   issue); after that the FIFO issues one beat per clock;
//! - a TILE or END beat is held while a readout job is waiting or sweeping; every other
//!   beat (span words, shadow controls, TABLE writes) issues as soon as it is at the head;
//! - a TILE or END issued at edge `E` starts the readout of the tile-line before it (if
//!   any): 4 clocks of wait (`READOUT_WAIT`), then one processor per clock, so the job
//!   ends at edge `E + 4 + L` for a tile-line of `L` pixels and the next TILE or END can
//!   issue at `E + 5 + L`;
//! - a pixel read at edge `G` is taken by the sink at edge `G + 10` (3 tracking stages, 5
//!   shading stages, `SHADE_STAGES`, the output FIFO's write and head registers); the
//!   END's job reads
//!   its last pixel at `E + 4 + L`.
//!
//! So with tile-line `t` holding `b_t` beats (its TILE and the commands binned to it) and
//! `L_t` pixels, the TILE of tile-line `t` issues at
//! `E_t = max(E_{t−1} + b_{t−1}, E_{t−1} + 5 + L_{t−2})` (first: `E_0 = 3 + table beats`),
//! END likewise, and the frame ends `L_last + 11` clocks after END issues ([`core_cycles`]).
//! A tile-line costs `max(b_t, L_{t−1} + 5)` clocks: the commands or the readout, whichever
//! is longer. The test `hwcost_array` checks this against the cycle model on whole
//! frames.

use super::{Frame, HwConfig, HwCost, HwCostError, Resources};
use crate::core_model::READOUT_WAIT;
use crate::render::SpanSource;
use crate::stream::SceneStream;
use pixelproc_formats::core_stream::SHADE_STAGES;

/// One tile-line of the core's stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileLine {
    /// Beats: the TILE beat and the commands binned to the tile (≥ 1).
    pub beats: u64,
    /// Pixels streamed out: `min(N, width − base)`.
    pub pixels: u32,
}

/// Clocks from the first beat offered to its issue to the array.
const FIRST_ISSUE: u64 = 3;
/// Clocks from a pixel's read to the sink taking it: three readout registers, the
/// shading step's stages, the output FIFO's write and its output.
const READ_TO_OUT: u64 = 3 + SHADE_STAGES as u64 + 2;

/// Cycles of a frame through the core: `table_beats` TABLE beats, the tile-lines in
/// stream order, then END (see the module header). Exact integer count.
pub fn core_cycles(table_beats: u64, lines: impl IntoIterator<Item = TileLine>) -> u64 {
    let wait = READOUT_WAIT as u64;
    // Edge at which the next beat would issue if not held; edge from which a TILE/END may
    // issue (the readout job is over); pixels of the tile-line awaiting readout.
    let mut next = FIRST_ISSUE + table_beats;
    let mut free = 0u64;
    let mut pending: Option<u32> = None;
    for t in lines {
        let e = next.max(free);
        if let Some(l) = pending {
            free = e + wait + 1 + l as u64;
        }
        pending = Some(t.pixels);
        next = e + t.beats.max(1);
    }
    let e = next.max(free);
    match pending {
        // The END's job reads the last tile-line: processor 0 at e + 5, the last at e + 4 + L.
        Some(l) => e + wait + l as u64 + READ_TO_OUT,
        None => e,
    }
}

/// The tile-lines of a scene stream on an `n`-processor array: per row, per tile, the
/// commands [`SceneStream::tile`] bins to it (its `ClearLine` is the TILE beat).
pub fn stream_tile_lines(s: &SceneStream, n: u32) -> Vec<TileLine> {
    let (w, h) = (s.width(), s.height());
    let mut out = Vec::new();
    for j in 0..h {
        for base in (0..w).step_by(n as usize) {
            out.push(TileLine {
                beats: s.tile(j, base, n).len() as u64,
                pixels: (w - base).min(n),
            });
        }
    }
    out
}

/// Appends the tile-lines of one row of `width` samples whose spans cover the inclusive
/// sample ranges `spans`, binned as the core's driver bins OP spans (a span goes to the
/// tiles `xl / n ..= xr / n`).
pub fn push_row(
    out: &mut Vec<TileLine>,
    width: u32,
    spans: impl IntoIterator<Item = (u32, u32)>,
    n: u32,
) {
    let tiles = width.div_ceil(n) as usize;
    let start = out.len();
    for t in 0..tiles {
        out.push(TileLine {
            beats: 1,
            pixels: (width - t as u32 * n).min(n),
        });
    }
    for (xl, xr) in spans {
        let (a, b) = ((xl / n) as usize, ((xr / n) as usize).min(tiles - 1));
        for t in out[start..].iter_mut().take(b + 1).skip(a) {
            t.beats += 1;
        }
    }
}

/// The OP span ranges of row `j` of `src`, in pixel columns (inclusive).
pub(crate) fn row_ranges(src: &SpanSource, j: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
    src.row_spans(j).iter().map(|w| (w.xl as u32, w.xr as u32))
}

/// Rows of samples the array processes for one sample position: for every pixel row `j`
/// in `rows`, a row of `width` samples at `y = j + dy_q8 / 256` (0 = the pixel row's top
/// edge, 128 = its centres), `num / den` samples per pixel along x.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SampleRows {
    /// Vertical position within the pixel row, 1/256 pixel (may leave `0..256`: a row
    /// of samples above or below the pixel row).
    pub dy_q8: i32,
    /// Pixel rows that get this row of samples.
    pub rows: std::ops::Range<u32>,
    /// Samples per pixel along x, numerator.
    pub num: u32,
    /// Samples per pixel along x, denominator.
    pub den: u32,
    /// Samples in the row.
    pub width: u32,
}

/// Cycles of the array drawing every row of samples of `passes`: pixel rows top to
/// bottom, and per pixel row the passes in the order given, each a run of tile-lines
/// through the core ([`core_cycles`]). A row's OP spans are the scene's spans at the
/// row's `y` (the scene moved by the rounded offset, `shift_y`); a span over
/// pixel columns `xl..=xr` covers samples `⌊xl·num/den⌋ ..= ⌊((xr+1)·num − 1)/den⌋`, exact
/// for one sample per pixel and within one pixel's samples otherwise (stated: the
/// samples' own x positions inside the pixel are not used). Returns the cycles and the
/// samples drawn.
pub fn sample_rows_cycles(
    frame: &Frame<'_>,
    n: u32,
    passes: &[SampleRows],
) -> Result<(u64, u64), HwCostError> {
    let mut sources = Vec::with_capacity(passes.len());
    for p in passes {
        let h = p.rows.end.saturating_sub(p.rows.start);
        if h == 0 || p.width == 0 || p.den == 0 {
            sources.push(None);
            continue;
        }
        // Row r of the moved scene samples the original at y = rows.start + r + dy/256.
        let tris = super::shift_y(frame.tris, 128 - p.dy_q8 - 256 * p.rows.start as i32);
        let f = Frame {
            tris: &tris,
            width: frame.width,
            height: h,
        };
        sources.push(Some(span_source(&f)?));
    }
    let lo = passes.iter().map(|p| p.rows.start).min().unwrap_or(0);
    let hi = passes.iter().map(|p| p.rows.end).max().unwrap_or(0);
    let mut lines = Vec::new();
    let mut samples = 0u64;
    for j in lo..hi {
        for (p, src) in passes.iter().zip(&sources) {
            let Some(src) = src else { continue };
            if !p.rows.contains(&j) {
                continue;
            }
            let last = p.width - 1;
            let spans = row_ranges(src, j - p.rows.start).filter_map(|(xl, xr)| {
                let a = (xl as u64 * p.num as u64 / p.den as u64) as u32;
                let b = (((xr as u64 + 1) * p.num as u64).saturating_sub(1) / p.den as u64) as u32;
                (a <= last).then_some((a, b.min(last)))
            });
            push_row(&mut lines, p.width, spans, n);
            samples += p.width as u64;
        }
    }
    Ok((core_cycles(0, lines), samples))
}

/// The span source of `frame`, checked.
pub(crate) fn span_source(frame: &Frame<'_>) -> Result<SpanSource, HwCostError> {
    if frame.width == 0
        || frame.height == 0
        || frame.width > pixelproc_formats::MAX_SCREEN
        || frame.height > pixelproc_formats::MAX_SCREEN
    {
        return Err(HwCostError::Scene(format!(
            "screen {}×{} is not supported (1..=4096)",
            frame.width, frame.height
        )));
    }
    SpanSource::new(frame.tris, frame.width, frame.height)
        .map_err(|e| HwCostError::Scene(e.to_string()))
}

/// ECP5 LUT4 of the core at `N = 8` without shadows, placed and routed (`docs/fpga.md`).
pub const CORE_N8_LUT4: u64 = 6226;
/// ECP5 FF of the same.
pub const CORE_N8_FF: u64 = 4829;
/// ECP5 LUT4 of one `pixel_processor_noshadow` (`docs/rtl.md`, after the shade-channel
/// change).
pub const PROC_LUT4: u64 = 562;
/// ECP5 FF of the same.
pub const PROC_FF: u64 = 466;

/// The core's LUT4/FF at `n` processors without shadows: measured at `N = 8`
/// (`docs/fpga.md`); otherwise the `N = 8` figure plus or minus `pixel_processor_noshadow`
/// per processor (`docs/rtl.md`), a linear extrapolation (the controller, FIFOs and entry
/// pipeline do not grow with `N`, except the readout select, which this ignores).
pub fn core_resources(n: u32) -> Resources {
    let n = n as i64;
    let f = |base: u64, per: u64| (base as i64 + (n - 8) * per as i64).max(0) as u64;
    Resources {
        lut4: f(CORE_N8_LUT4, PROC_LUT4),
        ff: f(CORE_N8_FF, PROC_FF),
        measured: n == 8,
        source: if n == 8 {
            "core N=8 no shadows, routed ECP5 (docs/fpga.md)"
        } else {
            "core N=8 no shadows (docs/fpga.md) ± pixel_processor_noshadow per processor (docs/rtl.md): extrapolated"
        },
    }
}

/// No anti-aliasing: the frame's OP spans through the core (no shadows, no TABLE beats),
/// one pass per row of `width` pixels. Exact: the core's cycle count for this stream.
pub fn no_aa_cost(frame: &Frame<'_>, cfg: &HwConfig) -> Result<HwCost, HwCostError> {
    let src = span_source(frame)?;
    let n = cfg.array_width;
    let mut lines = Vec::new();
    for j in 0..frame.height {
        push_row(&mut lines, frame.width, row_ranges(&src, j), n);
    }
    Ok(HwCost {
        cycles: core_cycles(0, lines),
        passes_per_row_milli: 1000,
        samples: frame.width as u64 * frame.height as u64,
        extra_memory_bits: 0,
        resources: Some(core_resources(n)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-counted: one tile-line of 3 pixels with 2 commands. TILE issues at edge 3,
    /// commands at 4 and 5, END at 6 (the job only starts there); pixels read at
    /// 6 + 5 = 11, 12, 13; the last is taken at 13 + 14 = 27 (3 readout registers, 9 shading
    /// stages, 2 through the output FIFO).
    #[test]
    fn one_tile_line_by_hand() {
        let c = core_cycles(
            0,
            [TileLine {
                beats: 3,
                pixels: 3,
            }],
        );
        assert_eq!(c, 27);
    }

    /// Two readout-bound tile-lines of 4 pixels, one beat each: TILE0 at 3, TILE1 at 4
    /// (no job yet), END held until 4 + 5 + 4 = 13; last pixel read at 13 + 4 + 4 = 21,
    /// out at 21 + 14 = 35.
    #[test]
    fn readout_bound_by_hand() {
        let t = TileLine {
            beats: 1,
            pixels: 4,
        };
        assert_eq!(core_cycles(0, [t, t]), 35);
    }
}
