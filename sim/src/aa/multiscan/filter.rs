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

/// Per-pixel accumulator of one output row.
#[derive(Clone, Default)]
pub(super) struct PixAcc {
    pub(super) c: [u64; 3],
    /// Weight per triangle (−1: background), in order of first contribution; held in
    /// the accumulator itself up to a few triangles (most pixels see one to three).
    pub(super) w: SmallVec<[(i32, i64); 3]>,
}

impl PixAcc {
    #[allow(clippy::needless_range_loop)]
    /// Adds colour `col` with weight `w`, and (`track`) the weight to triangle `tri`'s.
    #[inline]
    pub(super) fn add(&mut self, w: i64, col: [i64; 3], tri: i32, track: bool) {
        if w == 0 {
            return;
        }
        for ch in 0..3 {
            self.c[ch] += (w * col[ch]) as u64;
        }
        if !track {
            return;
        }
        match self.w.iter_mut().find(|e| e.0 == tri) {
            Some(e) => e.1 += w,
            None => self.w.push((tri, w)),
        }
    }

    /// The visible triangle: the largest weight, the lowest index (background −1 first)
    /// on a tie; −1 when nothing was added.
    pub(super) fn dominant(&self) -> i32 {
        self.w
            .iter()
            .min_by_key(|e| (std::cmp::Reverse(e.1), e.0))
            .map_or(-1, |e| e.0)
    }
}
