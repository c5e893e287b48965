//! Post-process anti-aliasing (seed 004, Sony CN1674049) after the array's frame.
//!
//! **Exact:** the array's frame ([`super::array::no_aa_cost`]).
//!
//! **Stated** (no RTL): seed 004 says the method "can run in step with scan-out to the
//! display, reading only the z-buffer". The unit reads the finished frame once, one pixel
//! per clock, through a window of 5 lines (2 above, 2 below: the seed's "5 lines at once");
//! the x and y scans run in parallel in that window, and the second loop (class-2 edges)
//! follows the first two lines behind in the same window. The frame is double-buffered, so
//! the unit works on frame `t` while the array draws frame `t + 1`: the frame time is the
//! slower of the two, the array's cycles or the scan-out pass's `W·H + 2W` (2 lines of
//! window fill). Memory: 5 lines of depth (24 bits), colour (24) and the 2-bit edge and
//! blended flags per pixel.

use super::array::{core_resources, no_aa_cost};
use super::{Frame, HwConfig, HwCost, HwCostError};

/// Bits per pixel of the 5-line window: depth 24, RGB 24, edge and blended flags 2.
pub const WINDOW_BITS_PER_PIXEL: u64 = 50;

/// The post-process's frame (module header).
pub fn cost(frame: &Frame<'_>, cfg: &HwConfig) -> Result<HwCost, HwCostError> {
    let base = no_aa_cost(frame, cfg)?;
    let (w, h) = (frame.width as u64, frame.height as u64);
    let scan = w * h + 2 * w;
    Ok(HwCost {
        cycles: base.cycles.max(scan),
        passes_per_row_milli: 1000,
        samples: w * h,
        extra_memory_bits: 5 * w * WINDOW_BITS_PER_PIXEL,
        resources: Some(core_resources(cfg.array_width)),
    })
}
