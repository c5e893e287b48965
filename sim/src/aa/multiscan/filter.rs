//! The filters of multi-scanning (seed 002, Nishita & Nakamae, §2.2.1 box and §2.2.2
//! axisymmetric Gaussian and cone): integer weight tables integrated per sub-scanline,
//! the per-pixel accumulator that sums weighted colours and per-triangle weights, and the
//! adding of one sub-scanline's visible pieces to it under each filter.

use super::colour::{ColourRow, PieceColour};
use super::walk::{Active, Piece};
use super::{Filter, GAUSS_SIGMA, ONE16};
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
    #[inline(always)]
    pub(super) fn add(&mut self, i: usize, w: i64, col: [i64; 3], tri: i32) {
        if w == 0 {
            return;
        }
        let c = &mut self.c[i];
        for ch in 0..3 {
            c[ch] += (w * col[ch]) as u64;
        }
        if let Some(ws) = self.w.get_mut(i) {
            weigh(ws, w, tri);
        }
    }

    /// The colour sums of the `count` pixels from `first` on, for a run of them to add
    /// weight `w` of triangle `tri` to each, having added that weight to each pixel's
    /// triangle's when weights are kept (as [`PixRow::add`] does pixel by pixel).
    #[inline]
    pub(super) fn run(&mut self, first: usize, count: usize, w: i64, tri: i32) -> &mut [[u64; 3]] {
        let r = first..first + count;
        if !self.w.is_empty() && w != 0 {
            self.w[r.clone()]
                .iter_mut()
                .for_each(|ws| weigh(ws, w, tri));
        }
        &mut self.c[r]
    }
}

/// Adds weight `w` to triangle `tri`'s in one pixel's weights.
#[inline(always)]
fn weigh(ws: &mut Weights, w: i64, tri: i32) {
    match ws.iter_mut().find(|e| e.0 == tri) {
        Some(e) => e.1 += w,
        None => ws.push((tri, w)),
    }
}

/// The visible triangle of a pixel: the largest weight, the lowest index (background −1
/// first) on a tie; −1 when nothing was added.
pub(super) fn dominant(w: &Weights) -> i32 {
    w.iter()
        .min_by_key(|e| (std::cmp::Reverse(e.1), e.0))
        .map_or(-1, |e| e.0)
}

/// Box filter: adds each piece, split at pixel boundaries, with line weight `wl`, to the
/// pixel row `acc`.
pub(super) fn accumulate_box(
    mut acc: PixRow,
    pieces: &[Piece],
    act: &[Active],
    crow: &mut [Option<Option<ColourRow>>],
    ynum: i64,
    wl: i64,
    bgc: [i64; 3],
) {
    for pc in pieces {
        let mut pcol = PieceColour::new(act, crow, pc, ynum, bgc);
        let (x0, x1, tri) = (pc.x0, pc.x1, pc.tri);
        // A part in the first pixel unless it is whole, the whole pixels, a part in the
        // last pixel.
        let i0 = x0.div_euclid(ONE16);
        let mut first = i0;
        if x0 != i0 * ONE16 || x1 < (i0 + 1) * ONE16 {
            let b0 = x1.min((i0 + 1) * ONE16);
            acc.add(i0 as usize, wl * (b0 - x0), pcol.at(x0, b0, x1), tri);
            if b0 == x1 {
                continue;
            }
            first = i0 + 1;
        }
        let i1 = x1.div_euclid(ONE16);
        let sums = acc.run(
            first as usize,
            (i1 - first).max(0) as usize,
            wl * ONE16,
            tri,
        );
        pcol.add_whole(first * ONE16, sums, wl * ONE16);
        let b1 = i1 * ONE16;
        if b1 < x1 {
            acc.add(i1 as usize, wl * (x1 - b1), pcol.at(b1, x1, x1), tri);
        }
    }
}

/// Axisymmetric filter: adds each piece, split at pixel centres (square R_i spans centres
/// i .. i+1), to the two pixels of its square with the table weights `fm`. `acc` is the
/// pixel row.
pub(super) fn accumulate_filtered(
    mut acc: PixRow,
    pieces: &[Piece],
    act: &[Active],
    crow: &mut [Option<Option<ColourRow>>],
    (ynum, fm): (i64, &[i64; 65]),
    bgc: [i64; 3],
) {
    for pc in pieces {
        let mut pcol = PieceColour::new(act, crow, pc, ynum, bgc);
        let mut x0 = pc.x0;
        while x0 < pc.x1 {
            let i = (x0 - ONE16 / 2).div_euclid(ONE16);
            let cx = i * ONE16 + ONE16 / 2;
            let x1 = pc.x1.min(cx + ONE16);
            let col = pcol.at(x0, x1, pc.x1);
            let q = |x: i64| ((x - cx + 512) >> 10).clamp(0, 64) as usize;
            let (k1, k2) = (q(x0), q(x1));
            if i >= 0 {
                acc.add(i as usize, fm[k2] - fm[k1], col, pc.tri);
            }
            if i + 1 < acc.len() as i64 {
                acc.add((i + 1) as usize, fm[64 - k1] - fm[64 - k2], col, pc.tri);
            }
            x0 = x1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run adds to each of its pixels what [`PixRow::add`] adds there, weights
    /// included: random runs and single additions over rows with and without weights.
    #[test]
    fn a_run_adds_what_single_additions_add() {
        let mut rng = crate::rng::Lcg64(0x0a0d_5e75);
        for case in 0..300 {
            let (len, track) = (40, case % 3 != 0);
            let (mut by_run, mut by_pixel) = (PixMem::default(), PixMem::default());
            by_run.reset(len, track);
            by_pixel.reset(len, track);
            for _ in 0..30 {
                let first = (rng.step() % len as u64) as usize;
                let count = (rng.step() % (len - first) as u64 + 1) as usize;
                let w = (rng.step() % 3) as i64 * ONE16;
                let tri = (rng.step() % 5) as i32 - 1;
                let cols: Vec<[i64; 3]> = (0..count)
                    .map(|_| [0; 3].map(|_| (rng.step() % (1 << 20)) as i64))
                    .collect();
                let mut row = by_run.row(0..len);
                for (s, c) in row.run(first, count, w, tri).iter_mut().zip(&cols) {
                    for ch in 0..3 {
                        s[ch] += (w * c[ch]) as u64;
                    }
                }
                let mut row = by_pixel.row(0..len);
                for (k, c) in cols.iter().enumerate() {
                    row.add(first + k, w, *c, tri);
                }
            }
            assert_eq!(by_run.c, by_pixel.c, "case {case}");
            assert_eq!(by_run.w, by_pixel.w, "case {case}");
            assert_eq!(by_run.w.len(), if track { len } else { 0 });
        }
    }

    #[test]
    fn tables_are_monotone_and_total_near_2_24() {
        for f in [Filter::Gauss, Filter::Cone] {
            for n in [1, 3, 8] {
                let t = tables(f, n);
                for row in &t.f {
                    assert!(row.windows(2).all(|w| w[1] >= w[0]));
                }
                assert!((t.total - (1 << 24)).abs() < 64, "{f:?} {n}: {}", t.total);
            }
        }
    }
}
