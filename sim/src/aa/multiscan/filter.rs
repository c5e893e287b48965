//! The filters of multi-scanning (seed 002, Nishita & Nakamae, §2.2.1 box and §2.2.2
//! axisymmetric Gaussian and cone): integer weight tables integrated per sub-scanline,
//! and the per-pixel accumulator that sums weighted colours and per-triangle weights.

use super::{Filter, GAUSS_SIGMA};
use smallvec::SmallVec;

/// Integer filter tables: `f[m][k]` for `m = 0..=n`, `k = 0..=64`, and the total weight
/// of a fully covered pixel.
pub(super) struct Tables {
    pub(super) f: Vec<[i64; 65]>,
    pub(super) total: i64,
}

#[allow(clippy::needless_range_loop)]
pub(super) fn tables(filter: Filter, n: u32) -> Tables {
    let prof = |r: f64| -> f64 {
        if r >= 1.0 {
            return 0.0;
        }
        match filter {
            Filter::Gauss => (-r * r / (2.0 * GAUSS_SIGMA * GAUSS_SIGMA)).exp(),
            Filter::Cone => 1.0 - r,
            Filter::Box => 1.0,
        }
    };
    // Float integrals (Simpson, 16 intervals per table step), then a scale to ~2^24.
    let nf = n as f64;
    let mut fl = vec![[0.0f64; 65]; n as usize + 1];
    for (m, row) in fl.iter_mut().enumerate() {
        let dy = m as f64 / nf;
        let mut acc = 0.0;
        for k in 1..=64 {
            let (a, b) = ((k - 1) as f64 / 64.0, k as f64 / 64.0);
            let steps = 16;
            let h = (b - a) / steps as f64;
            let mut s = 0.0;
            for q in 0..=steps {
                let t = a + q as f64 * h;
                let w = if q == 0 || q == steps {
                    1.0
                } else if q % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                s += w * prof((t * t + dy * dy).sqrt());
            }
            acc += s * h / 3.0 / nf;
            row[k] = acc;
        }
    }
    // Full weight: sub-scanlines at dy = m/n, |m| < n, each both sides of the centre.
    let full: f64 = (0..n as usize)
        .map(|m| if m == 0 { 2.0 } else { 4.0 } * fl[m][64])
        .sum();
    let scale = (1u64 << 24) as f64 / full;
    let f: Vec<[i64; 65]> = fl
        .iter()
        .map(|r| r.map(|v| (v * scale).round() as i64))
        .collect();
    let total = (0..n as usize)
        .map(|m| if m == 0 { 2 } else { 4 } * f[m][64])
        .sum();
    Tables { f, total }
}

/// Weights per triangle of one pixel (−1: background), in order of first contribution;
/// held inline up to a few triangles (most pixels see one to three).
pub(super) type Weights = SmallVec<[(i32, i64); 3]>;

/// Pixel memory of a band's rows, row after row: the colour sums, and the weights per
/// triangle only while the visible-triangle AOV is made (else `w` is empty), so that the
/// sums alone are what every sub-scanline touches.
#[derive(Default)]
pub(super) struct PixMem {
    pub(super) c: Vec<[u64; 3]>,
    pub(super) w: Vec<Weights>,
}

impl PixMem {
    /// Clears `len` pixels, with weights when `track`.
    pub(super) fn reset(&mut self, len: usize, track: bool) {
        self.c.clear();
        self.c.resize(len, [0; 3]);
        self.w.iter_mut().for_each(|w| w.clear());
        self.w
            .resize_with(if track { len } else { 0 }, Weights::default);
    }

    /// The pixels `r` (one row).
    pub(super) fn row(&mut self, r: std::ops::Range<usize>) -> PixRow<'_> {
        let w = if self.w.is_empty() {
            &mut []
        } else {
            &mut self.w[r.clone()]
        };
        PixRow {
            c: &mut self.c[r],
            w,
        }
    }
}

/// One row of [`PixMem`].
pub(super) struct PixRow<'a> {
    c: &'a mut [[u64; 3]],
    w: &'a mut [Weights],
}

impl PixRow<'_> {
    /// Pixels in the row.
    #[inline]
    pub(super) fn len(&self) -> usize {
        self.c.len()
    }

    /// Adds colour `col` with weight `w` to pixel `i`, and the weight to triangle `tri`'s
    /// when weights are kept.
    #[inline]
    pub(super) fn add(&mut self, i: usize, w: i64, col: [i64; 3], tri: i32) {
        if w == 0 {
            return;
        }
        let c = &mut self.c[i];
        for ch in 0..3 {
            c[ch] += (w * col[ch]) as u64;
        }
        if let Some(ws) = self.w.get_mut(i) {
            match ws.iter_mut().find(|e| e.0 == tri) {
                Some(e) => e.1 += w,
                None => ws.push((tri, w)),
            }
        }
    }
}

/// The visible triangle of a pixel: the largest weight, the lowest index (background −1
/// first) on a tie; −1 when nothing was added.
pub(super) fn dominant(w: &Weights) -> i32 {
    w.iter()
        .min_by_key(|e| (std::cmp::Reverse(e.1), e.0))
        .map_or(-1, |e| e.0)
}
