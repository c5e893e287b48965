//! The A-buffer with the depth search unit (seed 000, JP2569952B2): fragment generation,
//! the search unit, packing and resolve, as one fragment pipeline.
//!
//! **Exact** (RTL exists, `docs/rtl_mask_search.md`): the search unit's clocks. The
//! iterative unit tests one search line per clock, so a search costs the lines it tests
//! up to and including the first hit ([`diagonal_steps`]: the seed's claim 1, steps 3–5,
//! for the diagonal family; the test `hwcost_abuffer` checks it against
//! [`crate::mask_search::SearchUnit`] on every 4×4 mask and corner), one search after
//! another without gaps, the last result `12` clocks after its last step
//! (`BACK_LATENCY`); the pipelined unit takes one search per clock and shows each
//! result on the `lines + 12`-th clock counting the one that accepted it (19 for 4×4, 27
//! for 8×8). Both counts are the bare unit's, without the stream wrappers' FIFO (the test
//! `mask_search_rusthdl` checks them against the RTL's clock-by-clock schedule). The
//! frame's searches and their steps are the renderer's own
//! ([`crate::abuffer::AbufferStats`]: `sorted_fragments` searches per direction,
//! `search_steps` the golden `SearchUnit`'s step count).
//!
//! **Stated** (no RTL): one lane, pixels in scanline order; the fragment generator (edge
//! masks ANDed, seed 000 "Background" step 1) emits one fragment per clock; packing ANDs
//! one fragment per clock with the free mask and accumulates its contribution × colour, so
//! the resolve leaves one pixel per clock; the stages are decoupled by FIFOs deep enough
//! that the frame costs its busiest stage's clocks plus the search latency. The
//! `center` variant needs no search (the centre depth comes with the fragment); the
//! `exhaustive` variant evaluates one subpixel depth per clock on one depth calculator.

use super::{Frame, HwConfig, HwCost, HwCostError, Resources};
use crate::abuffer::{render_abuffer, AbufferParams};
use crate::mask_search::DepthSelect;
use pixelproc_formats::abuffer::{Corner, MaskSize};

/// Clocks from a search's last step to its result (`BACK_LATENCY`, `docs/rtl_mask_search.md`:
/// 1 input register + 5 ROM + 6 depth).
pub const BACK_LATENCY: u64 = 12;

/// Which search unit (`docs/rtl_mask_search.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SearchKind {
    /// `MaskSearchIter`: one search line per clock.
    Iterative,
    /// `MaskSearchPipe`: one stage per line, one search per clock.
    Pipelined,
}

/// Search lines of the diagonal family: `n + m − 1` (7 for 4×4, 15 for 8×8).
pub fn lines(size: MaskSize) -> u32 {
    size.n() + size.m() - 1
}

/// Clocks the iterative unit spends on one search (seed 000, claim 1): the search line
/// `k` through subpixel `(c, r)` is its distance `c' + r'` from the start corner (column
/// and row counted from that corner); the unit tests lines `0, 1, …` until the AND with
/// the fraction mask is non-zero, one per clock, so it spends the nearest set subpixel's
/// line + 1 clocks, or every line for an empty mask.
pub fn diagonal_steps(size: MaskSize, mask: u64, corner: Corner) -> u32 {
    let mut best = lines(size);
    let mut bits = mask & size.full();
    while bits != 0 {
        let b = bits.trailing_zeros();
        bits &= bits - 1;
        let (c, r) = size.col_row(b);
        let cc = if corner.right() { size.n() - 1 - c } else { c };
        let rr = if corner.bottom() { size.m() - 1 - r } else { r };
        best = best.min(cc + rr + 1);
    }
    best
}

/// Clocks from the one that accepts the first search to the one that shows the last
/// result, both counted, for searches of `steps` clocks each (their order does not
/// matter), on `kind` with `lines` search lines.
pub fn search_cycles(kind: SearchKind, steps: impl IntoIterator<Item = u32>, lines: u32) -> u64 {
    match kind {
        SearchKind::Iterative => {
            let mut it = steps.into_iter().peekable();
            if it.peek().is_none() {
                return 0;
            }
            it.map(u64::from).sum::<u64>() + BACK_LATENCY
        }
        SearchKind::Pipelined => {
            let m = steps.into_iter().count() as u64;
            if m == 0 {
                0
            } else {
                m - 1 + lines as u64 + BACK_LATENCY
            }
        }
    }
}

/// The search unit's clocks for `searches` searches that took `total_steps` clocks on the
/// iterative unit (the same closed form as [`search_cycles`], from totals).
pub fn search_cycles_of_totals(
    kind: SearchKind,
    searches: u64,
    total_steps: u64,
    lines: u32,
) -> u64 {
    if searches == 0 {
        return 0;
    }
    match kind {
        SearchKind::Iterative => total_steps + BACK_LATENCY,
        SearchKind::Pipelined => searches - 1 + lines as u64 + BACK_LATENCY,
    }
}

/// ECP5 LUT4/FF of the pipelined search unit as placed and routed over eight seeds
/// (`docs/rtl_mask_search.md`, "The current netlists over eight placement seeds": the
/// netlists with the offset ROM's fifth register stage); the iterative unit was
/// synthesized but not routed.
pub fn search_resources(size: MaskSize, kind: SearchKind) -> Option<Resources> {
    match (kind, size.n()) {
        (SearchKind::Pipelined, 4) => Some(Resources {
            lut4: 2940,
            ff: 3932,
            measured: true,
            source: "mask_search_pipe_4x4, routed ECP5 (docs/rtl_mask_search.md); search unit only",
        }),
        (SearchKind::Pipelined, 8) => Some(Resources {
            lut4: 3111,
            ff: 7350,
            measured: true,
            source: "mask_search_pipe_8x8, routed ECP5 (docs/rtl_mask_search.md); search unit only",
        }),
        _ => None,
    }
}

/// The A-buffer's frame: renders `frame` with `p` for its fragment and search counts, then
/// the pipeline of the module header. `extra_memory_bits`: one row of pixels' fragment
/// lists is not bounded, so it counts the per-pixel free mask and accumulator of one
/// pixel (the rest of the fragment store is off-chip, as in seed 000).
pub fn cost(
    frame: &Frame<'_>,
    _cfg: &HwConfig,
    p: &AbufferParams,
    kind: SearchKind,
) -> Result<HwCost, HwCostError> {
    let a = render_abuffer(frame.tris, frame.width, frame.height, [0, 0, 0], p)
        .map_err(|e| HwCostError::Scene(e.to_string()))?;
    let st = &a.stats;
    let pixels = frame.width as u64 * frame.height as u64;
    let dirs = 1 + p.interpenetrating as u64;
    let searches = st.sorted_fragments * dirs;
    let search = match p.depth {
        DepthSelect::Center => 0,
        DepthSelect::Exhaustive => st.depth_evals,
        DepthSelect::Search | DepthSelect::Slope => {
            search_cycles_of_totals(kind, searches, st.search_steps, lines(p.size))
        }
    };
    let kept = st.fragments - st.merges;
    let busiest = st.fragments.max(search).max(kept).max(pixels);
    Ok(HwCost {
        cycles: busiest,
        passes_per_row_milli: 1000,
        samples: st.fragments,
        extra_memory_bits: p.size.bits() as u64 + 3 * 20,
        resources: match p.depth {
            DepthSelect::Search | DepthSelect::Slope => search_resources(p.size, kind),
            _ => None,
        },
    })
}
