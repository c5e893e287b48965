//! Which rows a triangle can touch, and binning triangles into bands of rows (the span
//! generator of seed 001 section 3 and the A-buffer's fragment generator of seed 000 run
//! band by band, in parallel).
//!
//! Two row rules exist, because the consumers sample different points:
//! - [`centre_rows`]: rows whose pixel *centre* line `256·j + 128` lies within the
//!   triangle's y extent (span setup, one sample per pixel centre);
//! - [`touched_rows`]: rows whose pixel *area* `[256·j, 256·j + 256)` holds the extent's
//!   ends (fraction masks, which sample subpixel centres anywhere in the pixel).

use super::{ceil_div, floor_div};
use pixelproc_formats::SUBPIXEL_ONE;

/// Rows `j` whose centre `256·j + 128` lies in `[ymin, ymax]` (Q.8), inclusive, unclamped.
pub fn centre_rows(ymin: i64, ymax: i64) -> (i64, i64) {
    let one = SUBPIXEL_ONE as i64;
    let half = one / 2;
    (ceil_div(ymin - half, one), floor_div(ymax - half, one))
}

/// Rows `j` from the one holding `ymin` to the one holding `ymax` (Q.8), inclusive,
/// unclamped.
pub fn touched_rows(ymin: i64, ymax: i64) -> (i64, i64) {
    let one = SUBPIXEL_ONE as i64;
    (floor_div(ymin, one), floor_div(ymax, one))
}

/// Triangles binned into bands of `band` rows: a triangle whose (inclusive, unclamped) row
/// range meets the screen is listed, in input order, in every band its clamped range
/// meets.
#[derive(Clone, Debug)]
pub struct Bands {
    band: i64,
    height: i64,
    bins: Vec<Vec<u32>>,
}

impl Bands {
    /// Bins the row ranges `ranges` (one per triangle, in order) on a screen of `height`
    /// rows.
    pub fn new(band: i64, height: u32, ranges: impl Iterator<Item = (i64, i64)>) -> Bands {
        let height = height as i64;
        let nb = (height + band - 1) / band;
        let mut bins = vec![Vec::new(); nb as usize];
        for (k, (lo, hi)) in ranges.enumerate() {
            let (lo, hi) = (lo.max(0), hi.min(height - 1));
            if lo > hi {
                continue;
            }
            for b in lo / band..=hi / band {
                bins[b as usize].push(k as u32);
            }
        }
        Bands { band, height, bins }
    }

    /// Number of bands.
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    /// No band (a screen of zero rows).
    pub fn is_empty(&self) -> bool {
        self.bins.is_empty()
    }

    /// Rows per band.
    pub fn band(&self) -> i64 {
        self.band
    }

    /// The band holding row `j`.
    pub fn of_row(&self, j: i64) -> usize {
        (j / self.band) as usize
    }

    /// Rows `lo..=hi` of band `b`, clamped to the screen.
    pub fn rows(&self, b: usize) -> (i64, i64) {
        let lo = b as i64 * self.band;
        (lo, (lo + self.band - 1).min(self.height - 1))
    }

    /// The triangles (input positions) binned into band `b`, in order.
    pub fn members(&self, b: usize) -> &[u32] {
        &self.bins[b]
    }
}
