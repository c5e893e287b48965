//! What a frame rate costs: for a method on a frame, the clock it needs at a given array
//! width, and the smallest array width that reaches the rate at a given clock.
//!
//! Both come from the method's cycle model ([`super::method_cost`]) and nothing else:
//! `fps = clock / cycles`, so the clock for `fps` frames per second at width `N` is
//! `cycles(N) · fps`, and a width reaches `fps` at `clock` when
//! `cycles(N) ≤ clock / fps`.
//!
//! **The search over N.** Widths beyond the frame's width change nothing (a tile-line
//! holds `min(N, width − base)` pixels and the whole row is one tile), so the fewest
//! cycles any width gives are those at `N = min(width, 4096)`: if that misses the budget,
//! no width reaches the rate (the array methods are then bound by their readout, one
//! pixel per clock per pass, plus five clocks per tile-line; the A-buffer, whose model
//! does not depend on `N`, by its busiest stage at one fragment or pixel per clock).
//! Otherwise the smallest width is found by bisection on `1..=width`, which assumes the
//! cycles do not grow with `N`. For a frame without commands that is exact (a row of `W`
//! pixels costs `W + 5·⌈W/N⌉` clocks per pass); with spans, a wider tile also gathers
//! more span words, and a tile-line's cost is the larger of its words and its readout, so
//! the count is non-increasing in practice but not by construction.

use super::{method_cost, Frame, HwConfig, HwCostError};
use crate::aa::AaMethod;

/// The clock, MHz, at which a frame of `cycles` runs at `fps` frames per second.
pub fn clock_for_fps(cycles: u64, fps: f64) -> f64 {
    cycles as f64 * fps / 1e6
}

/// The smallest array width reaching a frame rate at a clock ([`min_width_for_fps`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WidthFor {
    /// The smallest width that reaches the rate, with its cycles per frame.
    Width {
        /// Processors, `N`.
        n: u32,
        /// Cycles per frame at that width.
        cycles: u64,
    },
    /// No width reaches the rate: even the widest useful array needs `floor_cycles`.
    NotReachable {
        /// Cycles per frame at `N = min(width, 4096)`, the fewest any width gives.
        floor_cycles: u64,
    },
}

/// The widest array that changes a frame's cycles: the frame's width (at most 4096).
pub fn widest_useful(frame: &Frame<'_>) -> u32 {
    frame.width.clamp(1, pixelproc_formats::MAX_SCREEN)
}

/// The smallest array width at which `method` renders `frame` at `fps` frames per second
/// or faster with a clock of `clock_mhz` (see the module header for the search).
pub fn min_width_for_fps(
    method: &AaMethod,
    frame: &Frame<'_>,
    clock_mhz: f64,
    fps: f64,
) -> Result<WidthFor, HwCostError> {
    let cycles_at = |n: u32| -> Result<u64, HwCostError> {
        Ok(method_cost(method, frame, &HwConfig::new(n as u64, clock_mhz)?)?.cycles)
    };
    let fits = |c: u64| c as f64 * fps <= clock_mhz * 1e6;
    let hi = widest_useful(frame);
    let floor = cycles_at(hi)?;
    if !fits(floor) {
        return Ok(WidthFor::NotReachable {
            floor_cycles: floor,
        });
    }
    // Invariant: `hi` fits; every width below `lo` does not.
    let (mut lo, mut hi, mut best) = (1u32, hi, floor);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        let c = cycles_at(mid)?;
        if fits(c) {
            (hi, best) = (mid, c);
        } else {
            lo = mid + 1;
        }
    }
    Ok(WidthFor::Width {
        n: hi,
        cycles: best,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame with no triangles: every tile-line holds only its TILE beat, so each is
    /// readout-bound, `L + 5` clocks, and the frame is `Σ (L + 5) + 17` (`array`'s
    /// header: 3 clocks to the first issue, 1 beat, and 4 + 14 after END's readout: 3
    /// readout registers, 9 shading stages, 2 through the output FIFO).
    /// 256×100: at N = 64, 4 tiles of 64 per row, 100·4·69 + 17 = 27,617 cycles; at
    /// N = 256, 100·261 + 17 = 26,117; at any N in 128..=255, two tiles per row,
    /// 100·(256 + 10) + 17 = 26,617.
    #[test]
    fn empty_frame_by_hand() {
        let frame = Frame {
            tris: &[],
            width: 256,
            height: 100,
        };
        let none = AaMethod::None;
        let c64 = method_cost(&none, &frame, &HwConfig::new(64, 1.0).unwrap()).unwrap();
        assert_eq!(c64.cycles, 27_617);
        // 60 frames per second at N = 64: 27,617 · 60 = 1,657,020 clocks per second.
        assert!((clock_for_fps(c64.cycles, 60.0) - 1.657_02).abs() < 1e-12);
        // At 1 MHz, 38 fps allows 1e6 / 38 = 26,315.8 cycles: only one tile per row
        // (26,117) fits; two tiles (26,617) do not, so the answer is 256, not the
        // 128 = ⌈256 / 2⌉ a pixel count alone would suggest.
        assert_eq!(
            min_width_for_fps(&none, &frame, 1.0, 38.0).unwrap(),
            WidthFor::Width {
                n: 256,
                cycles: 26_117
            }
        );
        // 39 fps allows 25,641 cycles, below the 26,117 of the widest array.
        assert_eq!(
            min_width_for_fps(&none, &frame, 1.0, 39.0).unwrap(),
            WidthFor::NotReachable {
                floor_cycles: 26_117
            }
        );
        // 36.5 fps allows 27,397: four tiles (64..=85: 100·(256 + 20) + 17 = 27,617)
        // miss, three (86..=127: 100·(256 + 15) + 17 = 27,117) fit: the smallest is 86.
        assert_eq!(
            min_width_for_fps(&none, &frame, 1.0, 36.5).unwrap(),
            WidthFor::Width {
                n: 86,
                cycles: 27_117
            }
        );
    }
}
